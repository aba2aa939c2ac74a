#!/bin/sh
# stats.sh FLITTER: --stats in a window run prints the headless run's
# "stats:" lines (frames, per-frame eval/physics, allocations, state) and
# the window's (draw and present ms per frame shown, frames shown and
# dropped: in lockstep every frame is shown); --window-size WxH sizes the
# physics view window of a script without !window, and a bad size is a
# usage error.
. "$(dirname "$0")/common.sh"
cat >x.fl <<'FL'
!window size=120;80
    !canvas
        !path
            !rect point=0;0 size=120;80
            !fill color=0;0.5;1
!counter state=:n rate=1
FL
"$flitter" run --window --lockstep --frames 30 --stats x.fl >out 2>err || fail "exit status $?"
grep -q '^stats: 30 frames in [0-9.]* s: [0-9.]* frames/s$' err || fail "no frames line"
grep -q '^stats: per frame: eval [0-9.]* ms, physics [0-9.]* ms, other [0-9.]* ms$' err ||
    fail "no per-frame line"
grep -q '^stats: per steady frame: eval [0-9.]* ms, physics [0-9.]* ms, other [0-9.]* ms$' err ||
    fail "no steady frame line"
grep -q '^stats: allocations: first frame ' err || fail "no allocations line"
grep -q '^stats: state per frame: ' err || fail "no state line"
grep -q '^stats: window: per frame shown: draw [0-9.]* ms, present [0-9.]* ms$' err ||
    fail "no draw/present line"
grep -q '^stats: window: 30 frames shown, 0 dropped$' err || fail "not 30 frames shown, 0 dropped"
# draw and present took some time: not the zeros of an unmeasured run
awk '/^stats: window: per frame shown/ { exit !($7 > 0 && $10 > 0) }' err ||
    fail "draw or present is zero"
# without --stats, no stats lines
"$flitter" run --window --lockstep --frames 3 x.fl >out 2>err || fail "exit status $?"
grep -q '^stats:' err && fail "stats lines without --stats"

# --window-size: the physics view window of a script without !window
cat >p.fl <<'FL'
!physics state=:p dimensions=2
    !particle id=:a position=0;0 radius=5
FL
"$flitter" run --window --window-size 300x200 --frames 100000 p.fl >out 2>err &
pid=$!; pids=$pid
wait_window p.fl
[ "$WIDTH" = 300 ] && [ "$HEIGHT" = 200 ] || fail "--window-size 300x200: window is ${WIDTH}x$HEIGHT"
xdotool key Escape
wait_exit $pid 2
[ "$RC" = 0 ] || fail "--window-size: exit status $RC"
for bad in 300 300x 0x200 x200 300x200x 300x-2 99999x10 3e2x200; do
    "$flitter" run --window --window-size "$bad" --frames 1 p.fl >out 2>err
    rc=$?
    [ "$rc" = 2 ] || fail "--window-size $bad: exit status $rc, not 2"
done
echo "ok: --stats lines in a window run (30 shown, 0 dropped), --window-size 300x200"
