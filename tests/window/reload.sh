#!/bin/sh
# reload.sh FLITTER: live reload in a realtime window: saving an imported
# file, then the script itself, changes the picture within a second; a
# broken save keeps the last picture running with the error shown over the
# bottom of the window (and `FILE:LINE:COL: error:` on stderr); the next
# good save replaces both.
. "$(dirname "$0")/common.sh"
printf 'let col = 1;0;0\n' >colour.fl
write_main() {   # write_main COLOUR-EXPRESSION
    cat >main.fl.new <<FL
import col from "colour.fl"
!window size=160;120 title="reload test"
    !canvas
        !path
            !rect point=0;0 size=160;120
            !fill color=$1
FL
    mv main.fl.new main.fl
}
write_main col
"$flitter" run --stats --window main.fl >out 2>err &
pid=$!; pids=$pid
wait_window "reload test"
wait_pixel 10 10 255,0,0 5
sleep 0.2
printf 'let col = 0;1;0\n' >colour.fl            # an imported file, written in place
wait_pixel 10 10 0,255,0 1 || fail "import"
echo "imported file saved: new picture after $TOOK s"
write_main '0;0;1'                                # the script, replaced by rename
wait_pixel 10 10 0,0,255 1
echo "script saved: new picture after $TOOK s"
shot reload-good
sleep 0.2
printf '!window size=160;120 title="reload test"\n    !canvas\n        !path\n            !rect size=(1+\n' >main.fl
i=0; while ! grep -q 'main.fl:[0-9]*:[0-9]*: error' err && [ $i -lt 20 ]; do sleep 0.05; i=$((i + 1)); done
grep -q 'main.fl:[0-9]*:[0-9]*: error' err || fail "no error message on stderr"
sleep 0.5
shot reload-error
kill -0 $pid 2>/dev/null || fail "the run ended on a broken save"
top=$(screen_pixel 10 10)
[ "$top" = 0,0,255 ] || fail "the last picture is not kept: $top"
# the error box: dark red (0.6,0,0 at 0.85) over the blue picture, left of the text
bottom=$(screen_pixel 2 117)
case $bottom in 12[89],0,3[789]|13[01],0,3[789]) ;; *) fail "no error box at the bottom: $bottom" ;; esac
# and some text in it: white-ish pixels along the box
white=$(convert "$SHOTS/reload-error-window.png" -crop 160x60+0+60 +repage -fx '(g>0.6&&b>0.6)' -format '%[fx:round(mean*w*h)]' info:)
[ "$white" -gt 20 ] || fail "no text in the error box ($white white pixels)"
write_main '1;1;1'
wait_pixel 2 117 255,255,255 1
echo "fixed: error gone, new picture after $TOOK s"
[ "$(screen_pixel 10 10)" = 255,255,255 ] || fail "top not white"
xdotool key Escape
wait_exit $pid 5
[ "$RC" = 0 ] || fail "exit status $RC"
# --stats counts the good reloads (the import, the script, the fix: at
# least 3; a save seen half-written may add one) and times the last
reloads=$(sed -n 's/^stats: load [0-9]*\.[0-9]\{3\} ms; \([0-9]*\) live reloads, the last [0-9]*\.[0-9]\{3\} ms$/\1/p' err)
[ -n "$reloads" ] && [ "$reloads" -ge 3 ] || fail "--stats load line: $(grep '^stats: load' err)"
echo "ok: live reload, broken save shown and survived ($reloads reloads counted)"
