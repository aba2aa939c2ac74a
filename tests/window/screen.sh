#!/bin/sh
# screen.sh FLITTER: the window options. --fullscreen fills the screen
# (the 1280x1024 Xvfb screen, with a window manager, openbox, to obey the
# request: Xvfb alone ignores it) with the picture letterboxed in it;
# --screen N for a screen that is not there opens the window on screen 0
# and says so; --vsync is taken and every frame of a lockstep run is shown.
# Skipped (77) when openbox is missing (Debian: openbox).
if [ -z "${FLITTER_WINDOW_TEST_INNER:-}" ] && ! command -v openbox >/dev/null 2>&1; then
    echo "skipped: openbox is missing (a window manager is needed for --fullscreen)"
    exit 77
fi
WINDOW_TEST_TIMEOUT=${WINDOW_TEST_TIMEOUT:-55}   # openbox first, then three runs
. "$(dirname "$0")/common.sh"
openbox >/dev/null 2>&1 &
pids=$!
# wait for the window manager to take the screen (it names itself on the root)
i=0
while ! xprop -root _NET_SUPPORTING_WM_CHECK 2>/dev/null | grep -q 'window id' && [ $i -lt 100 ]; do
    sleep 0.05; i=$((i + 1))
done
cat >w.fl <<'FL'
!window size=200;100 title="screen test"
    !canvas
        !path
            !rect point=0;0 size=200;100
            !fill color=1;0;0
FL

# --fullscreen: the whole 1280x1024 screen, the 2:1 picture 1280x640 in
# the middle, black bars above and below
"$flitter" run --window --fullscreen w.fl >out 2>err &
pid=$!; pids="$pids $pid"
wait_window "screen test"
i=0
while { [ "$WIDTH" != 1280 ] || [ "$HEIGHT" != 1024 ]; } && [ $i -lt 40 ]; do
    sleep 0.05; i=$((i + 1))
    eval "$(xdotool getwindowgeometry --shell "$WID")"
done
[ "$WIDTH" = 1280 ] && [ "$HEIGHT" = 1024 ] || fail "--fullscreen: window is ${WIDTH}x$HEIGHT, not 1280x1024"
wait_pixel 640 512 255,0,0 5
[ "$(screen_pixel 640 20)" = 0,0,0 ] || fail "--fullscreen: no black bar above the picture"
[ "$(screen_pixel 640 1000)" = 0,0,0 ] || fail "--fullscreen: no black bar below the picture"
[ "$(screen_pixel 5 200)" = 255,0,0 ] || fail "--fullscreen: the picture does not reach the left edge"
shot screen-fullscreen
xdotool key Escape
wait_exit $pid 5
[ "$RC" = 0 ] || fail "--fullscreen: exit status $RC"

# --screen 3 on a one-screen display: screen 0, with a message
"$flitter" run --window --screen 3 w.fl >out 2>err &
pid=$!; pids="$pids $pid"
wait_window "screen test"
[ "$WIDTH" = 200 ] && [ "$HEIGHT" = 100 ] || fail "--screen 3: window is ${WIDTH}x$HEIGHT"
wait_pixel 100 50 255,0,0 5
xdotool key Escape
wait_exit $pid 5
[ "$RC" = 0 ] || fail "--screen 3: exit status $RC"
grep -q '^flitter: no screen 3 (1 screen): using screen 0$' err || fail "--screen 3: no message"

# --vsync: taken, and a lockstep run shows every frame
"$flitter" run --window --vsync --lockstep --frames 30 --stats w.fl >out 2>err || fail "--vsync: exit status $?"
grep -q '^stats: window: 30 frames shown, 0 dropped$' err || fail "--vsync: not 30 frames shown"
echo "ok: --fullscreen fills 1280x1024, --screen 3 falls back to screen 0, --vsync runs"
