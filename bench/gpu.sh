#!/bin/sh
# bench/gpu.sh [BUILD_DIR] [FRAMES]: the render graph's drawing time per
# frame on whatever OpenGL device EGL finds (an NVIDIA card through its EGL
# vendor library when there is one; Mesa's llvmpipe otherwise), so that a
# machine with a GPU reports its figures with one command.
#
# Each scene runs through BUILD_DIR's tests/bench_canvas3d --script (a
# front end drawing its first window after every frame: fl_step, then
# fl_draw_window: the whole graph and the read-back of the window's
# picture) for FRAMES frames (default 20) after a warm-up frame:
#   blank      an empty !window size=1920;1080 of one !canvas
#   shader     a !window size=1920;1080 of a moving !shader under a !bloom
#   canvas10k  bench/canvas10k.fl (10,000 cairo ellipses, 1920x1080)
#   physics    Flitter's examples/physics.fl (1080x1080 !canvas3d,
#              samples=4, !bloom), --physics=upstream
#   bounce     Flitter's examples/bounce.fl (1080x1080, 150 point lights)
# Flitter's two examples are read as bench/canvas3d.sh reads them
# (FLITTER_EXAMPLES=DIR, or FLITTER_REPO at FLITTER_REV) and left out when
# there are none. Printed: the device (nvidia-smi -L, when there is one)
# and bench_canvas3d's line per scene (mean draw ms, fastest, CPU ms of
# drawing, step ms).
# Not part of the test suite: timings vary with the machine.
set -u
build=${1:-build}
frames=${2:-20}
case $build in /*) ;; *) build=$PWD/$build ;; esac
bench="$build/tests/bench_canvas3d"
[ -x "$bench" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
cd "$(dirname "$0")/.." || exit 2
tmp=$(mktemp -d) || exit 2
trap 'rm -rf "$tmp"' EXIT
repo=${FLITTER_REPO:-/work/.mirror/jonathanhogg+flitter/repo}
rev=${FLITTER_REV:-v1.0.0b28}

# NVIDIA's EGL vendor library where the driver put it (glvnd finds Mesa's
# by itself)
if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ]; then
    for f in /usr/share/glvnd/egl_vendor.d/10_nvidia.json /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json \
             /etc/glvnd/egl_vendor.d/10_nvidia.json; do
        if [ -f "$f" ]; then
            export __EGL_VENDOR_LIBRARY_FILENAMES="$f"
            break
        fi
    done
fi
gpu=$(nvidia-smi -L 2>/dev/null | head -n 1)
echo "device: ${gpu:-no nvidia-smi: EGL's own choice (Mesa's llvmpipe on a machine without a GPU)}${__EGL_VENDOR_LIBRARY_FILENAMES:+ (EGL vendor $__EGL_VENDOR_LIBRARY_FILENAMES)}"

printf '!window size=1920;1080\n    !canvas\n' >"$tmp/blank.fl"
cat >"$tmp/shader.fl" <<'FL'
let waves = """${HEADER}
in vec2 coord;
out vec4 color;
uniform float time;
void main() {
    float v = 0.5 + 0.5 * sin(40.0 * coord.x + 3.0 * time) * cos(30.0 * coord.y - 2.0 * time);
    color = vec4(v, v * v, 1.0 - v, 1.0);
}
"""
!window size=1920;1080
    !bloom radius=16
        !shader fragment=waves
FL
status=0
scene() {   # NAME SCRIPT [OPTIONS...]
    name=$1 script=$2
    shift 2
    printf "%-10s " "$name"
    "$bench" --script "$script" --frames "$frames" "$@" 2>"$tmp/$name.err" || {
        echo "failed: $(tail -n 3 "$tmp/$name.err")"
        status=1
    }
}
scene blank "$tmp/blank.fl"
scene shader "$tmp/shader.fl"
scene canvas10k bench/canvas10k.fl
for ex in physics bounce; do
    if [ -n "${FLITTER_EXAMPLES:-}" ]; then
        cp "$FLITTER_EXAMPLES/$ex.fl" "$tmp/$ex.fl" 2>/dev/null || continue
    elif ! git -C "$repo" show "$rev:examples/$ex.fl" >"$tmp/$ex.fl" 2>/dev/null; then
        echo "$ex: no Flitter examples (set FLITTER_EXAMPLES=DIR or FLITTER_REPO=GIT_DIR): left out" >&2
        continue
    fi
    scene "$ex" "$tmp/$ex.fl" --physics upstream
done
exit $status
