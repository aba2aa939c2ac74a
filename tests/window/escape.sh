#!/bin/sh
# escape.sh FLITTER: Flitter's command line `flitter --state FILE SCRIPT`
# opens a window when there is a display; Escape ends the run within a
# second with status 0, the state saved and --dump-state printed; SIGTERM
# and SIGINT (Ctrl-C) do the same; a script whose !key claims Escape keeps
# it (the run goes on); a closed standard output ends the run too.
. "$(dirname "$0")/common.sh"
cat >x.fl <<'FL'
!window size=120;80
    !canvas
        !path
            !rect point=0;0 size=120;80
            !fill color=0;0.5;1
!counter state=:n rate=1
FL
"$flitter" --state st --dump-state x.fl >out 2>err &
pid=$!; pids=$pid
wait_window x.fl
sleep 0.5
xdotool key Escape
wait_exit $pid 1
[ "$RC" = 0 ] || fail "Escape: exit status $RC"
echo "Escape: ended in $TOOK s"
[ -s st ] || fail "--state file not saved"
grep -q '^# frame ' out || fail "no --dump-state on stdout"
n=$(sed -n 's/^:n = //p' out)
over "$n" 0.3 || fail "counter :n = '$n' after half a second of realtime"
# the saved state is the one dumped: a headless run resumes from it
"$flitter" run --frames 1 --state st --dump-state x.fl >resumed 2>>err || fail "resume failed"
n2=$(sed -n 's/^:n = //p' resumed)
over "$n2" "$n" || over "$n2" "$(awk -v a="$n" 'BEGIN{print a - 1e-9}')" || fail "resumed :n = $n2 < $n"

for sig in TERM INT; do
    rm -f st out
    "$flitter" --state st --dump-state x.fl >out 2>err &
    pid=$!; pids=$pid
    wait_window x.fl
    sleep 0.3
    kill -$sig $pid
    wait_exit $pid 1
    [ "$RC" = 0 ] || fail "SIG$sig: exit status $RC"
    [ -s st ] || fail "SIG$sig: --state not saved"
    grep -q '^# frame ' out || fail "SIG$sig: no --dump-state"
    echo "SIG$sig: ended in $TOOK s"
done

# a !key claiming escape takes it from the front end
cat >claim.fl <<'FL'
!window size=120;80 title="claim"
    !key name="escape" state=:esc
FL
"$flitter" run --window --dump-state claim.fl >out 2>err &
pid=$!; pids=$pid
wait_window claim
xdotool key Escape
sleep 0.5
kill -0 $pid 2>/dev/null || fail "Escape ended a run whose !key claims it"
kill -TERM $pid
wait_exit $pid 2
[ "$RC" = 0 ] || fail "claimed: exit status $RC"
grep -qxF ':esc;:released = 1' out || fail "claimed Escape not in the state: $(cat out)"

# standard output closed under the run (`flitter --dump-state ... | head`):
# the next dump fails and the run ends as Escape ends it, status 0 and the
# state saved (a window run does not die of SIGPIPE: it blocks it, so that
# a killed X connection ends it through Xlib's error path, window/lost)
rm -f st out err
mkfifo pipe
"$flitter" --state st --dump-state --dump-every 1 x.fl >pipe 2>err &
pid=$!; pids=$pid
head -c 1 pipe >/dev/null
wait_exit $pid 5
rm -f pipe
[ "$RC" = 0 ] || fail "standard output closed: exit status $RC, not 0"
grep -q "standard output closed" err || fail "standard output closed: not said: $(cat err)"
[ -s st ] || fail "standard output closed: --state not saved"
echo "standard output closed: ended in $TOOK s"
echo "ok: Escape, SIGTERM, SIGINT and a closed standard output end cleanly; a claimed Escape does not"
