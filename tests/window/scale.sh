#!/bin/sh
# scale.sh FLITTER: the live window's dynamic resolution
# (src/window_scale.c). A realtime window whose picture is heavy for its
# first 2.5 s of clock (a shader of 1,600 sines a pixel at 400x400, tens of
# milliseconds a picture on a CPU rasteriser) and trivial after: the
# pictures are scaled down under the load, never below the floor
# (--min-scale, default a quarter of the pixels: scale 0.5), and back to
# full size when it ends; --stats says so. --min-scale 1 and --lockstep
# never scale (no scale line); bad --min-scale values are usage errors.
. "$(dirname "$0")/common.sh"
cat >heavy.fl <<'FL'
let heavy = '''${HEADER}
in vec2 coord;
out vec4 color;
uniform float n;
void main() {
    float v = 0.0;
    for (int i = 0; i < int(n); i++) v += sin(coord.x * float(i) + coord.y);
    color = vec4(fract(v), 0.5, 0.0, 1.0);
}
'''
!window size=400;400
    !shader fragment=heavy n=(1600 if time < 2.5 else 0)
FL
"$flitter" run --window --stats --runtime 7 heavy.fl >out 2>err || fail "exit status $?"
line=$(grep '^stats: window: scale: ' err) || fail "no scale line"
echo "$line"
# stats: window: scale: N pictures below full size (mean scale M), least L (P% of pixels), now S; C changes
echo "$line" | awk '{
    below = $4; least = $13; now = $18; changes = $19
    if (below < 5) { print "too few pictures below full size: " below; exit 1 }
    if (least > 0.75 || least < 0.5) { print "least scale " least ", not within 0.5..0.75"; exit 1 }
    if (now != "1;") { print "not back to full size: now " now; exit 1 }
    if (changes < 2) { print "fewer than 2 changes: " changes; exit 1 }
}' || fail "scale under load and after it"

# a higher floor: never below it (0.5625 of the pixels: 12/16 of the side)
"$flitter" run --window --stats --runtime 4 --min-scale 0.5625 heavy.fl >out 2>err || fail "exit status $?"
line=$(grep '^stats: window: scale: ' err) || fail "--min-scale 0.5625: no scale line"
echo "$line" | awk '{ if ($13 != 0.75) { print "least " $13 ", not 0.75"; exit 1 } }' ||
    fail "--min-scale 0.5625"

# never scaled: --min-scale 1, and lockstep (every frame shown whole)
"$flitter" run --window --stats --runtime 2 --min-scale 1 heavy.fl >out 2>err || fail "exit status $?"
grep -q '^stats: window: scale' err && fail "--min-scale 1 scaled"
"$flitter" run --window --lockstep --stats --frames 5 heavy.fl >out 2>err || fail "exit status $?"
grep -q '^stats: window: scale' err && fail "--lockstep scaled"
grep -q '^stats: window: 5 frames shown, 0 dropped$' err || fail "--lockstep: not 5 frames shown"

for bad in 0 -0.5 1.5 nan x 0.5x ''; do
    "$flitter" run --window --min-scale "$bad" --frames 1 heavy.fl >out 2>err
    rc=$?
    [ "$rc" = 2 ] || fail "--min-scale '$bad': exit status $rc, not 2"
    grep -q "bad value" err || fail "--min-scale '$bad': no message"
done
echo "ok: scaled down under load and back to full size, the floor kept, --min-scale 1 and lockstep whole"
