#!/bin/sh
# canvas3d.sh FLITTER: a !window with a !canvas3d, shown live in a window
# (issue 25: "the window of issue [2] shows !canvas3d live"): the
# screenshot equals the picture !record writes, pixel for pixel (the record
# writes every frame, so that the window shows its 8-bit sRGB picture: on a
# frame that writes no file, the record passes its child's picture up
# unquantised, pass_program.c pass_through, and two GL paths may round a
# colour at .5 of a step differently); a box lit by an ambient light alone shows its colour times
# (1 - F0) at the centre (F0 = 0.04, a dielectric's reflectance at normal
# incidence: Flitter docs/canvas3d.md, Materials), sRGB-encoded; the
# corners are the window's black; when the script's colour changes, the
# window follows within two seconds; no node is skipped.
. "$(dirname "$0")/common.sh"
write() {   # write RED: a box of colour RED;0.5;1 under white ambient light
    cat >main.fl.new <<FL
!window size=120;90 title="canvas3d test"
    !record filename="rec.png"
        !canvas3d
            !light color=1
            !box size=20 color=$1;0.5;1
FL
    mv main.fl.new main.fl
}
# wait_like X Y PATTERN SECONDS: wait until the window's pixel X,Y matches
# the case PATTERN; fails after SECONDS
wait_like() {
    n=$(awk -v s="$4" 'BEGIN { print int(s / 0.05) }')
    while :; do
        got=$(screen_pixel "$1" "$2")
        eval "case \$got in $3) return 0 ;; esac"
        [ "$n" -le 0 ] && fail "pixel $1,$2 is $got, not $3, after $4 s"
        n=$((n - 1)); sleep 0.05
    done
}
write 0
"$flitter" run --window --lockstep --frames 100000 main.fl >out 2>err &
pid=$!; pids=$pid
wait_window "canvas3d test"
[ "$WIDTH" = 120 ] && [ "$HEIGHT" = 90 ] || fail "window is ${WIDTH}x$HEIGHT, not 120x90"
i=0; while [ ! -s rec.png ] && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
[ -s rec.png ] || fail "rec.png not written"
# linear (1 - 0.04) * (0, 0.5, 1) = 0, 0.48, 0.96, sRGB-encoded for the
# screen (1.055 * c^(1/2.4) - 0.055): 0, 0.722, 0.982, times 255: 0, 184,
# 250 (one step of slack)
wait_like 60 45 '0,18[345],2[45][019]' 5
for xy in "0 0" "119 0" "0 89" "119 89"; do
    set -- $xy
    c=$(screen_pixel "$1" "$2")
    [ "$c" = 0,0,0 ] || fail "window corner $1,$2 is $c, not black"
done
sleep 0.3
shot canvas3d
cp rec.png "$SHOTS/canvas3d-record.png"
diff=$(compare -metric AE "$SHOTS/canvas3d-window.png" rec.png null: 2>&1)
[ "$diff" = 0 ] || fail "$diff pixels of the window differ from the !record picture"
write 1
wait_like 60 45 '2[45][019],18[345],2[45][019]' 2
xdotool key Escape
wait_exit $pid 10
[ "$RC" = 0 ] || fail "exit status $RC"
grep -qi "skip" err && fail "a node was skipped: $(cat err)"
echo "ok: !canvas3d live in the window (= !record picture, lit centre, black corners, reload)"
