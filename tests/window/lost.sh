#!/bin/sh
# lost.sh FLITTER: a run whose window or X display is lost ends as Escape
# ends it (src/window_lost.h): the --state file saved, --dump-state
# printed, a !record video finished, one line on stderr, exit status 3,
# within seconds. Three losses: the window destroyed by another X client
# (xdotool windowclose: XDestroyWindow), the connection killed (xdotool
# windowkill: XKillClient, as xkill does), the X server gone (its Xvfb
# killed: one started for it); and the REPL's :window destroyed (the
# window closes, the session goes on) or its connection killed (the state
# saved to the recovery file, status 3). Before, Xlib's
# default handlers ended the process with status 1 and nothing saved.
. "$(dirname "$0")/common.sh"
cat >x.fl <<'FL'
!window size=160;120
    !record filename="rec.mp4"
        !canvas
            !path
                !rect point=0;0 size=160;120
                !fill color=0;0.5;1
!counter state=:n rate=1
FL

# lose MODE [ARGS...]: run x.fl with a window, lose it after half a second
# of frames in way MODE, and check how the run ended
lose() {
    mode=$1
    shift
    rm -f st out err rec.mp4
    "$flitter" --state st --dump-state "$@" x.fl >out 2>err &
    pid=$!; pids=$pid
    wait_window x.fl
    sleep 0.5
    case $mode in
    destroy) xdotool windowclose "$WID"; why="destroyed by another X client" ;;
    hidden)   # one of the hidden windows that hold the OpenGL contexts
        other=$(xdotool search --pid "$pid" 2>/dev/null | grep -vx "$WID" | head -n 1)
        [ -n "$other" ] || fail "hidden: no other window of the run"
        xdotool windowclose "$other"; why="destroyed by another X client" ;;
    kill) xdotool windowkill "$WID"; why="connection to the X display was lost" ;;
    server) kill "$xserver"; why="connection to the X display was lost" ;;
    esac
    wait_exit $pid 10
    [ "$RC" = 3 ] || fail "$mode $*: exit status $RC, not 3"
    grep -q "$why" err || fail "$mode $*: no '$why' on stderr"
    [ -s st ] || fail "$mode $*: --state file not saved"
    grep -q '^# frame ' out || fail "$mode $*: no --dump-state on stdout"
    n=$(sed -n 's/^:n = //p' out)
    over "$n" 0.2 || fail "$mode $*: counter :n = '$n' after half a second"
    if command -v ffprobe >/dev/null 2>&1; then
        frames=$(ffprobe -v error -count_frames -select_streams v -show_entries stream=nb_read_frames \
                 -of csv=p=0 rec.mp4 2>/dev/null)
        [ "${frames:-0}" -gt 0 ] 2>/dev/null || fail "$mode $*: rec.mp4 not finished ('$frames' frames)"
    else
        frames="(no ffprobe)"
    fi
    # the state saved is the one dumped: a headless run resumes from it
    "$flitter" run --frames 1 --state st --dump-state x.fl >resumed 2>>err || fail "$mode: resume failed"
    n2=$(sed -n 's/^:n = //p' resumed)
    over "$n2" "$n" || fail "$mode $*: resumed :n = $n2, not after $n"
    echo "$mode $*: status 3 in $TOOK s, :n = $n, rec.mp4 $frames frames"
}

lose destroy
lose destroy --lockstep
lose hidden
lose kill
lose kill --lockstep

# the REPL's :window: destroyed, the window closes and the session goes
# on; the connection killed, the session's state goes to the recovery file
# and the process exits with status 3
cp "$here/../golden/petri.fl" petri.fl
repl_lose() {
    mode=$1
    rm -f in out err recovery.state
    mkfifo in
    FLITTER_RECOVERY=$dir/recovery.state "$flitter" repl petri.fl <in >out 2>err &
    pid=$!; pids=$pid
    exec 3>in
    printf ':step 10\n:window\n' >&3
    wait_window petri.fl
    case $mode in
    destroy) xdotool windowclose "$WID" ;;
    kill) xdotool windowkill "$WID" ;;
    esac
    sleep 0.2
    # (the window's events are read after a frame; a killed window may
    # have ended the session already, its end of the pipe closed: that
    # write's SIGPIPE must not end this script)
    (trap '' PIPE; printf ':step 1\n' >&3) 2>/dev/null || true
    if [ "$mode" = destroy ]; then
        i=0
        until grep -q '^frame 10 ' out && grep -qx 'window closed' out; do
            i=$((i + 1)); [ $i -gt 250 ] && fail "REPL destroy: no 'window closed': $(cat out)"
            sleep 0.02
        done
        grep -q "destroyed by another X client" err || fail "REPL destroy: not said on stderr"
        printf ':step 1\n:quit\n' >&3
        wait_exit $pid 5
        [ "$RC" = 0 ] || fail "REPL destroy: the session ended with status $RC"
        grep -q '^frame 11 ' out || fail "REPL destroy: the session did not go on: $(cat out)"
    else
        wait_exit $pid 10
        [ "$RC" = 3 ] || fail "REPL kill: exit status $RC, not 3"
        [ -s recovery.state ] || fail "REPL kill: no recovery file"
        grep -q "^state saved to $dir/recovery.state" out || fail "REPL kill: not said where: $(cat out)"
    fi
    exec 3>&-
    echo "REPL $mode: ok (status $RC)"
}
repl_lose destroy
repl_lose kill

# the server: an Xvfb of this test's own (xvfb-run's would make xvfb-run
# fail when it cannot kill it at the end)
command -v Xvfb >/dev/null 2>&1 || fail "Xvfb is missing"
Xvfb -displayfd 5 -screen 0 640x480x24 -nolisten tcp 5>dpy 2>xvfb.log &
xserver=$!; pids="$pids $xserver"
for i in $(seq 100); do [ -s dpy ] && break; sleep 0.05; done
[ -s dpy ] || fail "our own Xvfb did not start: $(cat xvfb.log)"
DISPLAY=:$(cat dpy)
export DISPLAY
lose server
echo "ok: a lost window or display ends the run with its state saved, dumps printed, status 3"
