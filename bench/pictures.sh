#!/bin/sh
# bench/pictures.sh [BUILD_DIR] [NAME...]: Flitter's own pictures made by
# flitter-c as Flitter's Makefiles make them, each compared with Flitter's
# PNG (bench/picdiff.py: the fraction of foreground pixels within 48/255).
#
# The pictures are those of Flitter's examples/, docs/diagrams/ and
# docs/tutorial_images/, read at run time from a Flitter git repository
# (FLITTER_REPO, default /work/.mirror/jonathanhogg+flitter/repo, at
# FLITTER_REV, default v1.0.0b28) into a scratch folder; Flitter's scripts
# and pictures (BSD 2-clause licence, copyright Jonathan Hogg) are not
# copied into this repository. Each folder's Makefile runs unchanged
# (`make -B NAME.png`) with a `flitter` on its PATH that runs BUILD_DIR's
# (default build) with --physics=upstream added, since Flitter's pictures
# come from its own (unpatched) physics. examples/video.fl's video is not
# in Flitter's repository: a 20 s stand-in of moving black and white
# shapes is made with ffmpeg, so that picture runs but cannot match.
#
# Prints one line a picture: its name, the fraction, the foreground
# pixels, the seconds the run took and the kinds it skipped (from its
# stderr); keeps the pictures and a picture of the pixels off by more than
# 48/255 (white) under PICTURES_OUT (default /tmp/flitter-pictures). With
# NAMEs, only those pictures. Needs git, make, ffmpeg, ImageMagick and
# Python 3 with numpy (PYTHON, default python3).
# Not part of the test suite: it reads another repository.
set -u
build=${1:-build}
[ $# -gt 0 ] && shift
case $build in /*) ;; *) build=$PWD/$build ;; esac
[ -x "$build/src/flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
repo=${FLITTER_REPO:-/work/.mirror/jonathanhogg+flitter/repo}
rev=${FLITTER_REV:-v1.0.0b28}
out=${PICTURES_OUT:-/tmp/flitter-pictures}
python=${PYTHON:-python3}
here=$(cd "$(dirname "$0")" && pwd)
for tool in git make ffmpeg convert identify; do
    command -v $tool >/dev/null 2>&1 || { echo "bench/pictures.sh needs $tool" >&2; exit 2; }
done
work=$(mktemp -d) || exit 2
trap 'rm -rf "$work"' EXIT
mkdir -p "$out" "$work/bin" "$work/tree" || exit 2
# the three folders file by file (a mirror may lack a large file's blob)
files=$(git -C "$repo" ls-tree -r --name-only "$rev" -- examples docs/diagrams docs/tutorial_images 2>/dev/null)
[ -n "$files" ] || { echo "no Flitter repository at $repo ($rev): set FLITTER_REPO and FLITTER_REV (see $0)" >&2; exit 2; }
for f in $files; do
    mkdir -p "$work/tree/$(dirname "$f")"
    git -C "$repo" show "$rev:$f" >"$work/tree/$f" 2>/dev/null || rm -f "$work/tree/$f"
done
printf '#!/bin/sh\nexec "%s" --physics=upstream "$@"\n' "$build/src/flitter" >"$work/bin/flitter"
chmod +x "$work/bin/flitter"
if [ ! -e "$work/tree/examples/assets/badapple.m4v" ]; then
    ffmpeg -hide_banner -loglevel error -f lavfi \
        -i "color=black:s=640x480:r=30:d=20,format=yuv420p,geq=lum='255*gt(sin(X/40+T)*cos(Y/30-0.7*T)+0.3*sin(T),0)':cb=128:cr=128" \
        -c:v libx264 -pix_fmt yuv420p "$work/tree/examples/assets/badapple.m4v" ||
        echo "bench/pictures.sh: no stand-in video made: video.png will miss it" >&2
fi

wanted() {   # NAME: true when NAME was asked for (or nothing was)
    [ -z "$names" ] && return 0
    for n in $names; do [ "$n" = "$1" ] && return 0; done
    return 1
}

names="$*"
printf "%-16s %8s %10s %8s  %s\n" picture within foreground seconds skipped
for dir in examples docs/diagrams docs/tutorial_images; do
    for fl in "$work/tree/$dir"/*.fl; do
        name=$(basename "$fl" .fl)
        ref="$work/tree/$dir/$name.png"
        [ -f "$ref" ] || continue
        wanted "$name" || continue
        mv "$ref" "$work/$name.ref.png"
        start=$(date +%s.%N)
        (cd "$work/tree/$dir" && PATH="$work/bin:$PATH" make -B -s "$name.png") >"$work/$name.log" 2>&1
        rc=$?
        secs=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
        skipped=$(grep -o 'skipping unsupported ![a-z_0-9]*' "$work/$name.log" | sed 's/skipping unsupported //' |
                  sort -u | tr '\n' ' ')
        if [ $rc -ne 0 ] || [ ! -f "$work/tree/$dir/$name.png" ]; then
            printf "%-16s %8s %10s %8s  %s\n" "$name" failed - "$secs" "$(tail -n 1 "$work/$name.log")"
            continue
        fi
        cp "$work/tree/$dir/$name.png" "$out/$name.png"
        cp "$work/$name.ref.png" "$out/$name.flitter.png"
        fig=$("$python" "$here/picdiff.py" --diff "$out/$name.diff.png" "$out/$name.png" "$out/$name.flitter.png") ||
            fig="- -"
        set -- $fig
        printf "%-16s %8s %10s %8s  %s\n" "$name" "$1" "$2" "$secs" "$skipped"
    done
done
