#!/bin/sh
# readme_drawing.sh FLITTER SAMPLES: README's drawing example, word for
# word on a copy of samples/easings.fl: Flitter's command line writes the
# !record picture next to the script (OUTPUT relative to the script's
# folder, as Flitter), 960x540, with the `linear` panel's line at its
# middle (120;90) in its colour (hsv 0;0.7;1: sRGB 255;77;77) over the
# dark ground.
set -u
flitter=$1 samples=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
case $samples in /*) ;; *) samples=$PWD/$samples ;; esac
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v convert >/dev/null 2>&1 || { echo "skipped: ImageMagick's convert is missing"; exit 77; }
mkdir "$dir/samples" && cp "$samples/easings.fl" "$dir/samples/" || exit 1
cd "$dir" || exit 1
"$flitter" --offscreen --lockstep --fps=1 --runtime=1 --define OUTPUT=easings.png samples/easings.fl >out 2>err ||
    fail "exit status $?: $(cat err)"
# no message of flitter's own (a sanitizer's summary lines may follow)
grep -Eq '^(samples/easings\.fl|flitter|Execution error|Physics error)' err && fail "messages: $(cat err)"
[ -f samples/easings.png ] || fail "no samples/easings.png"
got=$(convert samples/easings.png -format '%wx%h %[pixel:p{120,90}] %[pixel:p{5,5}]' info:) || fail "unreadable PNG"
set -- $got
[ "$1" = 960x540 ] || fail "size $1, not 960x540"
echo "$2" | awk -F'[(),]' '{ exit !($2 >= 240 && $3 >= 55 && $3 <= 100 && $4 >= 55 && $4 <= 100) }' ||
    fail "linear's line at 120;90 is $2"
echo "$3" | awk -F'[(),]' '{ exit !($2 < 40 && $3 < 40 && $4 < 40) }' || fail "ground at 5;5 is $3"
echo "ok: README's drawing example: samples/easings.png 960x540, the linear curve where it belongs"
