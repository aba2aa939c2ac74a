#!/bin/sh
# repl.sh FLITTER: `:window` in `flitter repl`: a window titled as the
# script opens on the session's runtime and shows the physics view of a
# script without !window; `:step 60` redraws it (the picture changes);
# `:window off` closes it; Escape on a reopened window closes the window
# but not the session; `:quit` ends the session with status 0 and no
# error; with a window open, a standard output whose reader has gone ends
# the session (not only the end of its input).
. "$(dirname "$0")/common.sh"
src=$(cd "$here/../golden" && pwd)/petri.fl
cp "$src" petri.fl
mkfifo in
"$flitter" repl petri.fl <in >out 2>err &
pid=$!; pids=$pid
exec 3>in
send() { printf '%s\n' "$1" >&3; }
# wait_out RE: wait (10 s at most) for a line matching RE (grep) on the REPL's stdout
wait_out() {
    i=0
    until grep -qx "$1" out; do
        i=$((i + 1))
        [ $i -gt 500 ] && fail "no '$1' line on stdout: $(cat out)"
        sleep 0.02
    done
}
# gone TITLE: wait (5 s at most) until no window is called TITLE
gone() {
    i=0
    while xdotool search --onlyvisible --name "^$1\$" >/dev/null 2>&1; do
        i=$((i + 1))
        [ $i -gt 250 ] && fail "window '$1' still open"
        sleep 0.02
    done
}
send ':step 1'
wait_out 'frame 0 time 0'
send ':window'
wait_out 'window open (:window off closes it)'
wait_window petri.fl
[ "$WIDTH" = 512 ] && [ "$HEIGHT" = 512 ] || fail "physics view window is ${WIDTH}x$HEIGHT, not 512x512"
sleep 0.3
shot repl-frame0
send ':step 60'
wait_out 'frame 60 time 1\.0*[0-9]*'
sleep 0.3
shot repl-frame60
diff=$(compare -metric AE "$SHOTS/repl-frame0-window.png" "$SHOTS/repl-frame60-window.png" null: 2>&1)
[ "$diff" -gt 200 ] 2>/dev/null || fail ":step 60 did not change the picture ($diff pixels differ)"
send ':window off'
wait_out 'window closed'
gone petri.fl
kill -0 $pid 2>/dev/null || fail "the session ended with the window"
# Escape closes a reopened window (seen at the next event poll), not the session
send ':window'
wait_window petri.fl
xdotool key --window "$WID" Escape
sleep 0.3
send ':step 1'
wait_out 'frame 61 time 1\.01666[0-9]*'
[ "$(grep -cx 'window closed' out)" = 2 ] || fail "Escape: no second 'window closed': $(cat out)"
gone petri.fl
send ':quit'
exec 3>&-
wait_exit $pid 5
[ "$RC" = 0 ] || fail "exit status $RC"
[ -s err ] && fail "errors on stderr"
# with a window open a closed standard output ends the session (SIGPIPE
# is blocked then: the write fails instead), though input keeps coming
mkfifo in2
("$flitter" repl petri.fl <in2 2>err2; echo $? >rc2) | head -n 1 >out2 &
# (opened for reading too, so that a :step written after the session has
# ended waits in the pipe instead of killing this shell with SIGPIPE)
exec 4<>in2
printf ':window\n' >&4
i=0
until [ -s out2 ]; do
    i=$((i + 1))
    [ $i -gt 500 ] && fail "closed stdout: no first line"
    sleep 0.02
done
wait_window petri.fl
i=0
until [ -s rc2 ]; do
    printf ':step\n' >&4 2>/dev/null
    i=$((i + 1))
    [ $i -gt 200 ] && fail "closed stdout: the session goes on after 200 :steps"
    sleep 0.05
done
exec 4>&-
grep -qx 'flitter repl: cannot write to standard output (closed?): the session ends' err2 ||
    fail "closed stdout: $(cat err2)"
echo "ok: :window opens petri.fl (512x512), :step 60 redraws ($diff pixels changed), :window off and Escape close it, :quit exits 0; a closed stdout ends the session after $i steps (exit status $(cat rc2))"
