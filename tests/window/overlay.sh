#!/bin/sh
# overlay.sh FLITTER: the front end's own keys. F1 shows the status box
# (darkening the top left of a white picture); F2 shows the physics view
# instead of the picture and back; F5 pauses (no frame is evaluated: the
# script's debug(frame) lines stop), F6 evaluates exactly one frame while
# paused, F5 again resumes. A script without !window shows its !physics
# systems in a window titled with its file name.
. "$(dirname "$0")/common.sh"
cat >ov.fl <<'FL'
!window size=200;200 title="overlay test" tag=debug(frame)
    !canvas
        !path
            !rect point=0;0 size=200;200
            !fill color=1
!physics state=:p dimensions=2
    !particle id=0 position=-40;0 radius=20 charge=1
    !particle id=1 position=40;0 radius=20 charge=-1
FL
stdbuf -o0 "$flitter" run --window --lockstep ov.fl >out 2>err &
pid=$!; pids=$pid
wait_window "overlay test"
wait_pixel 3 3 255,255,255 5
xdotool key F1
sleep 0.3
shot overlay-status
got=$(screen_pixel 3 3)
# black at 70% over white: 255 * 0.3 = 76.5, rounded by the renderer's
# blending (SDL's OpenGL renderer 76 or 77, its software renderer 75)
case $got in 7[5-7],7[5-7],7[5-7]) ;; *) fail "F1: no status box at the top left: $got" ;; esac
xdotool key F1
wait_pixel 3 3 255,255,255 1
xdotool key F2
sleep 0.3
shot overlay-view
diff=$(compare -metric AE "$SHOTS/overlay-status-window.png" "$SHOTS/overlay-view-window.png" null: 2>&1)
[ "$diff" -gt 1000 ] 2>/dev/null || fail "F2: the physics view looks like the picture ($diff pixels differ)"
xdotool key F2
wait_pixel 100 100 255,255,255 1
xdotool key F5
sleep 0.3
n1=$(wc -l <out)
sleep 0.5
n2=$(wc -l <out)
[ "$n1" = "$n2" ] || fail "F5: frames still evaluated while paused ($n1, then $n2 lines)"
xdotool key F6 F6 F6
sleep 0.5
n3=$(wc -l <out)
[ "$n3" = $((n2 + 3)) ] || fail "F6 x3: $n2 then $n3 frames, not 3 more"
[ "$(tail -n 1 out)" = "$(($(sed -n "${n2}p" out) + 3))" ] || fail "F6: frames not consecutive"
xdotool key F5
sleep 0.3
n4=$(wc -l <out)
[ "$n4" -gt "$n3" ] || fail "F5 again did not resume"
xdotool key Escape
wait_exit $pid 5
[ "$RC" = 0 ] || fail "exit status $RC"

# a script with !physics and no !window: the physics view
cat >phys.fl <<'FL'
!physics state=:p dimensions=2
    !particle id=0 position=-40;0 radius=20 charge=1
    !particle id=1 position=40;0 radius=20 charge=-1
FL
"$flitter" run --window --lockstep phys.fl >out 2>err &
pid=$!; pids=$pid
wait_window phys.fl
sleep 0.5
shot overlay-physics
colours=$(convert "$SHOTS/overlay-physics-window.png" -unique-colors -format '%w' info:)
[ "$colours" -gt 3 ] || fail "physics view: only $colours colours"
xdotool key Escape
wait_exit $pid 5
[ "$RC" = 0 ] || fail "physics view: exit status $RC"
echo "ok: F1 status, F2 view, F5 pause, F6 step, physics-only window"
