#!/bin/sh
# interrupt.sh FLITTER: SIGTERM stops a frame that would never end, inside
# the evaluation loop and inside the physics step loop, and `--state` is
# still saved consistently on the way out.
#   1. frame 3 runs an endless loop: the frame is discarded, so the saved
#      state is the one after frames 0-2 (clock line frame 3, :p;:clock 2).
#   2. each frame would need 10^12 physics steps (--max-steps 0: no limit):
#      the steps stop early, the frame completes (:p;:last = its time) with
#      the clock short of it, and the saved file loads again.
#   3. the same as 1 with SIGHUP (it used to kill the run at once, without
#      the final save) and with SIGINT.
#   4. each run above was cut short before its --frames: it exits 128 +
#      the signal's number (143 SIGTERM, 129 SIGHUP, 130 SIGINT), as a
#      shell reports a job ended by a signal (it used to exit 0, so a
#      script or a job scheduler took it for a finished run); a run
#      without --frames, which a signal is meant to end, exits 0.
# Each run must end within 20 s of the signal (it would otherwise hang).
set -u
flitter=$1
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
cat >"$dir/loop.fl" <<'FL'
!physics state=:p dimensions=1 time=frame resolution=1
    !particle id=:a position=0 velocity=1
!spin n=len((j for i in 0..2**25+frame for j in 0..2**20+frame)) if frame == 3 else 0
FL
cat >"$dir/steps.fl" <<'FL'
!physics state=:p dimensions=1 time=frame*1e12 resolution=1
    !particle id=:a position=0 velocity=1
FL
fail=0
# run CASE FRAME ARGS...: start flitter (dumping the state every frame),
# SIGTERM it once frame FRAME is dumped (plus half a second, to be inside
# the next frame), then wait for it (20 s at most)
run() {
    name=$1 ready=$2
    shift 2
    sig=${SIG:-TERM}
    stdbuf -o0 "$flitter" run --dump-every 1 "$@" >"$dir/$name.out" 2>"$dir/$name.err" &
    pid=$!
    waited=0
    until grep -q "^# frame $ready " "$dir/$name.out" 2>/dev/null; do
        if [ $waited -ge 600 ] || ! kill -0 $pid 2>/dev/null; then
            echo "$name: frame $ready never came" >&2
            fail=1
            break
        fi
        sleep 0.1
        waited=$((waited + 1))
    done
    sleep 0.5
    kill -$sig $pid
    waited=0
    while kill -0 $pid 2>/dev/null; do
        if [ $waited -ge 200 ]; then
            echo "$name: still running 20 s after SIG$sig" >&2
            kill -KILL $pid
            fail=1
            break
        fi
        sleep 0.1
        waited=$((waited + 1))
    done
    wait $pid
    rc=$?
    case $sig in TERM) want=143 ;; HUP) want=129 ;; INT) want=130 ;; esac
    [ "${WANT:-}" ] && want=$WANT
    if [ $rc -ne $want ]; then
        echo "$name: exit status $rc after SIG$sig, not $want" >&2; cat "$dir/$name.err" >&2; fail=1
    fi
}
run loop 2 --frames 10 --state "$dir/loop.state" "$dir/loop.fl"
grep -q '^clock 3 ' "$dir/loop.state" || { echo "loop: clock line is not frame 3" >&2; fail=1; }
grep -qx ':p;:clock = 2' "$dir/loop.state" || { echo "loop: :p;:clock is not 2" >&2; fail=1; }

run steps 0 --frames 3 --max-steps 0 --state "$dir/steps.state" "$dir/steps.fl"
# consistent: the last frame saved (clock line F) completed its physics,
# :p;:last = (F - 1) * 10^12, with the simulation clock short of it
frames=$(sed -n 's/^clock \([0-9]*\) .*/\1/p' "$dir/steps.state")
grep -qx ":p;:last = $(( ${frames:-0} - 1 ))000000000000" "$dir/steps.state" ||
    { echo "steps: :p;:last does not match frame ${frames:-?}" >&2; fail=1; }
clock=$(sed -n 's/^:p;:clock = //p' "$dir/steps.state")
case $clock in
    ''|0|*e*|*[!0-9]*) echo "steps: bad :p;:clock '$clock'" >&2; fail=1 ;;
esac
"$flitter" run --frames 1 --state "$dir/steps.state" "$dir/steps.fl" 2>"$dir/reload.err" ||
    { echo "steps: saved state does not load:" >&2; cat "$dir/reload.err" >&2; fail=1; }
for SIG in HUP INT; do
    run "loop$SIG" 2 --frames 10 --state "$dir/loop$SIG.state" "$dir/loop.fl"
    grep -q '^clock 3 ' "$dir/loop$SIG.state" || { echo "loop, SIG$SIG: clock line is not frame 3" >&2; fail=1; }
done
# without --frames a signal is the way a run ends: status 0, state saved
WANT=0 run endless 1 --state "$dir/endless.state" "$dir/loop.fl"
grep -q '^clock ' "$dir/endless.state" || { echo "endless: no state saved" >&2; fail=1; }
[ $fail -eq 0 ] || { cat "$dir"/*.state >&2; }
exit $fail
