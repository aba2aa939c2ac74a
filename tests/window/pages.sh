#!/bin/sh
# pages.sh FLITTER: `flitter SCRIPT1 SCRIPT2` runs two pages in one window:
# the right arrow shows the second (its picture, its file name as title),
# the left arrow the first again, whose state was kept (a key pressed on
# page 1 before the switches is still in its --dump-state at exit); with
# --resetonswitch it is gone.
. "$(dirname "$0")/common.sh"
cat >p1.fl <<'FL'
!window size=100;100
    !key name="k" state=:k
    !canvas
        !path
            !rect point=0;0 size=100;100
            !fill color=1;0;0
FL
cat >p2.fl <<'FL'
!window size=100;100
    !canvas
        !path
            !rect point=0;0 size=100;100
            !fill color=0;0;1
FL
for mode in keep reset; do
    opt=; [ $mode = reset ] && opt=--resetonswitch
    "$flitter" --lockstep $opt --dump-state p1.fl p2.fl >out 2>err &
    pid=$!; pids=$pid
    wait_window p1.fl
    wait_pixel 50 50 255,0,0 5
    xdotool key k
    sleep 0.2
    xdotool key Right
    wait_pixel 50 50 0,0,255 1
    [ "$mode" = keep ] && shot pages-2
    [ "$(xdotool getwindowname "$WID")" = p2.fl ] || fail "title on page 2: $(xdotool getwindowname "$WID")"
    xdotool key Left
    wait_pixel 50 50 255,0,0 1
    [ "$(xdotool getwindowname "$WID")" = p1.fl ] || fail "title on page 1: $(xdotool getwindowname "$WID")"
    xdotool key Escape
    wait_exit $pid 5
    [ "$RC" = 0 ] || fail "$mode: exit status $RC"
    if [ $mode = keep ]; then
        grep -q '^:k;:released;:beat = ' out || fail "page 1 lost its state: $(cat out)"
    else
        # the !key starts afresh (:released 1) but the press is forgotten
        grep -q '^:k;:released;:beat = ' out && fail "--resetonswitch kept page 1's state"
        grep -qxF ':k;:released = 1' out || fail "--resetonswitch: no fresh !key state"
        grep -q '^# frame ' out || fail "no dump"
    fi
    echo "$mode: pages switched"
done
echo "ok: two pages switched with the arrows"
