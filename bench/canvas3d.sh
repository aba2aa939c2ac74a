#!/bin/sh
# bench/canvas3d.sh [BUILD_DIR] [FRAMES]: milliseconds per frame of
# `!canvas3d` drawing for Flitter's own examples/physics.fl and
# examples/bounce.fl (1080x1080, samples=4, each inside a !bloom), as a
# front end draws the window after every frame, on whatever OpenGL EGL
# gives (Mesa's llvmpipe on a machine without a GPU).
#
# The two scripts are Flitter's (https://github.com/jonathanhogg/flitter,
# BSD 2-clause licence, copyright Jonathan Hogg); they are not copied into
# this repository but read at run time from a Flitter git repository
# (FLITTER_REPO, default /work/.mirror/jonathanhogg+flitter/repo, at
# FLITTER_REV, default v1.0.0b28) or, when FLITTER_EXAMPLES names a
# directory, from that directory (a Flitter checkout's examples/).
#
# Each runs as examples/Makefile renders it (10 frames a second, with
# --physics=upstream so that the particles are Flitter's own) for FRAMES
# frames (default 10) after one warm-up frame; printed: the mean drawing
# time (fl_draw_window: the 3D scene, the bloom, the compositing), the
# fastest frame's, the mean CPU time of drawing (all threads) and the
# mean evaluation+physics time. LP_NUM_THREADS
# (Mesa's llvmpipe rasteriser threads) and the other Mesa variables pass
# through.
# Not part of the test suite: timings vary with the machine and its load.
set -u
build=${1:-build}
frames=${2:-10}
case $build in /*) ;; *) build=$PWD/$build ;; esac
bench="$build/tests/bench_canvas3d"
[ -x "$bench" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
tmp=$(mktemp -d) || exit 2
trap 'rm -rf "$tmp"' EXIT
repo=${FLITTER_REPO:-/work/.mirror/jonathanhogg+flitter/repo}
rev=${FLITTER_REV:-v1.0.0b28}
for ex in physics bounce; do
    if [ -n "${FLITTER_EXAMPLES:-}" ]; then
        cp "$FLITTER_EXAMPLES/$ex.fl" "$tmp/$ex.fl" || exit 2
    elif ! git -C "$repo" show "$rev:examples/$ex.fl" >"$tmp/$ex.fl" 2>/dev/null; then
        echo "no Flitter examples: set FLITTER_EXAMPLES=DIR or FLITTER_REPO=GIT_DIR (see $0)" >&2
        exit 2
    fi
done
echo "canvas3d benchmark: $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)${LP_NUM_THREADS:+, LP_NUM_THREADS=$LP_NUM_THREADS}"
for ex in physics bounce; do
    (cd "$tmp" && "$bench" --script "$ex.fl" --fps 10 --frames "$frames" --physics upstream -D OUTPUT=) || exit 1
done
