#!/bin/sh
# input.sh FLITTER: keys, pointer and buttons reach the script's state: a
# key held down and one pressed and released (`!key`), the pointer over the
# picture as fractions of it, letterboxed (`!pointer`: the window is made
# twice as wide as the picture, so the picture sits in the middle with
# black bars), a button held; checked in the --dump-state written when
# Escape ends the run, and in the picture: holding `a` turns it red, and
# the pointer's x moves a white bar.
. "$(dirname "$0")/common.sh"
cat >in.fl <<'FL'
!window size=200;200 title="input test"
    !key name="a" state=:ka
    !key name=:space state=:ksp
    !key name="left_shift" state=:ksh
    !pointer state=:ptr
    !canvas
        !path
            !rect point=0;0 size=200;200
            !fill color=((1;0;0) if $(:ka) else 0.5)
        !path
            !rect point=(200*($(:ptr)[0] or 0.9));0 size=4;20
            !fill color=1
FL
"$flitter" run --window --dump-state in.fl >out 2>err &
pid=$!; pids=$pid
wait_window "input test"
xdotool windowsize --sync "$WID" 400 200
eval "$(xdotool getwindowgeometry --shell "$WID")"
[ "$WIDTH" = 400 ] || fail "window not resized: ${WIDTH}x$HEIGHT"
sleep 0.3
shot input
# letterbox: black bars left and right, the grey picture in the middle
[ "$(screen_pixel 50 100)" = 0,0,0 ] || fail "no black bar: $(screen_pixel 50 100)"
[ "$(screen_pixel 99 100)" = 0,0,0 ] || fail "bar too narrow: $(screen_pixel 99 100)"
[ "$(screen_pixel 100 100)" = 128,128,128 ] || fail "picture not at x=100: $(screen_pixel 100 100)"
[ "$(screen_pixel 299 0)" = 128,128,128 ] || fail "picture not up to x=299"
[ "$(screen_pixel 300 100)" = 0,0,0 ] || fail "no right bar: $(screen_pixel 300 100)"
xdotool keydown a
wait_pixel 200 100 255,0,0 1 || fail "holding a did not turn the picture red"
xdotool key space
xdotool keydown shift
# picture x = 100 + 50 of 200 -> 0.25, y = 150 of 200 -> 0.75
xdotool mousemove --sync $((X + 150)) $((Y + 150))
# the white bar follows the pointer to picture x = 200*0.25 = 50 (window x 150)
wait_pixel 151 10 255,255,255 1 || fail "the pointer did not move the bar"
xdotool mousedown 3
sleep 0.3
xdotool key Escape
wait_exit $pid 5
[ "$RC" = 0 ] || fail "exit status $RC"
for line in ':ka = 1' ':ka;:pushed = 1' ':ka;:released = 0' \
            ':ksp = 0' ':ksp;:pushed = 0' ':ksp;:released = 1' \
            ':ksh = 1' ':ptr = 0.25;0.75' ':ptr;1 = 1'; do
    grep -qxF "$line" out || fail "no '$line' in the state dump: $(grep -v '^#' out | tr '\n' ' ')"
done
grep -q '^:ptr;0 ' out && fail "button 0 recorded, only the right button (1) was pressed"
echo "ok: keys, letterboxed pointer and button in the state"
