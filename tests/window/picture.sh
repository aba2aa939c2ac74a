#!/bin/sh
# picture.sh FLITTER: `flitter run --window --lockstep` shows a !window's
# picture exactly as its !record writes it: the window (titled with the
# script's file name, as the script gives no title=) is the picture's size
# and a screenshot of it equals the recorded PNG pixel for pixel, with the
# red, blue and green rectangles where the script puts them.
. "$(dirname "$0")/common.sh"
cat >pic.fl <<'FL'
!window size=200;100
    !record filename=("rec.png" if frame == 2 else null)
        !canvas
            !path
                !rect point=0;0 size=100;100
                !fill color=1;0;0
            !path
                !rect point=100;0 size=100;50
                !fill color=0;0;1
            !path
                !rect point=100;50 size=100;50
                !fill color=0;1;0
            !path
                !ellipse point=50;50 radius=30
                !fill color=1;1;0.5
FL
"$flitter" run --window --lockstep --frames 100000 pic.fl >out 2>err &
pid=$!; pids=$pid
wait_window pic.fl
[ "$WIDTH" = 200 ] && [ "$HEIGHT" = 100 ] || fail "window is ${WIDTH}x$HEIGHT, not 200x100"
i=0; while [ ! -s rec.png ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
[ -s rec.png ] || fail "rec.png not written"
sleep 0.3
shot picture
cp rec.png "$SHOTS/picture-record.png"
diff=$(compare -metric AE "$SHOTS/picture-window.png" rec.png null: 2>&1)
[ "$diff" = 0 ] || fail "$diff pixels of the window differ from the !record picture"
for spec in "10 10 255,0,0" "150 25 0,0,255" "150 75 0,255,0" "50 50 255,255,128" "199 99 0,255,0"; do
    set -- $spec
    got=$(screen_pixel "$1" "$2")
    [ "$got" = "$3" ] || fail "window pixel $1,$2 is $got, not $3"
done
xdotool key Escape
wait_exit $pid 5
[ "$RC" = 0 ] || fail "exit status $RC"
echo "ok: window = !record picture (200x100, 0 pixels differ)"
