#!/bin/sh
# bench/window.sh [BUILD_DIR] [SECONDS]: the live window's frame budget.
# Runs scenes in a window under a private Xvfb server, realtime at 60
# frames/s for SECONDS (default 10) each, with --stats:
#   petri      samples/petri.fl: no !window, so the window shows the
#              physics view (--window-size 1920x1080)
#   canvas10k  bench/canvas10k.fl: a !window size=1920;1080 of 10,000
#              !ellipse nodes
#   blank      an empty !window size=1920;1080: what presenting a picture
#              of that size costs by itself (the display's floor)
#   shader     a !window size=1920;1080 of a moving !shader under a !bloom:
#              work for the GPU (llvmpipe here) and none for the evaluator
#   physics3d  Flitter's examples/physics.fl (1080x1080 !canvas3d, 500
#              spheres, samples=4, under a !bloom), read at run time from a
#              Flitter git repository as bench/canvas3d.sh reads it
#              (FLITTER_REPO, FLITTER_REV, or FLITTER_EXAMPLES=DIR); left
#              out when there is none
# each by two routes (ROUTES, default "gl readback"):
#   gl         the pictures drawn by the render graph in the frame loop's
#              OpenGL context and drawn from its texture into the window by
#              the display's context, never read back
#   readback   FLITTER_WINDOW_READBACK=1: the pictures read back into
#              memory (fl_draw_window) and copied into the window through
#              SDL's renderer, as before the render graph (a build older
#              than it ignores the variable: its only route is this one)
# and prints, per scene and route: frames/s, the per-frame milliseconds of
# evaluation, physics, drawing on the frame loop (the render graph, with
# the copy of each window's texture for the display or the read-back into
# the pixels; fl_draw_view for a 3D view, or the snapshot of a flat physics
# view), painting on the display's thread (a flat physics view drawn from
# its snapshot, fl_view_painter_draw; per picture painted) and presenting
# (texture upload or draw, present; per frame shown),
# the frame loop's busy milliseconds per frame (its wall time less its
# waits: eval, physics and drawing, the drawing only for frames shown),
# the milliseconds to spare in a 60 frames/s frame (1000/60 minus the
# frame loop's busy time; a build whose frame loop also presents, which
# prints no busy line, 1000/60 minus eval + physics + draw + present), the
# display thread's own spare time (1000/60 minus paint and present), and
# the frames dropped (pictures skipped). Painting and presenting run on the
# display's own thread, beside the frame loop: their cost shows in the
# frames shown a second (frames/s less dropped ones) and in the display's
# spare time, not in the frame loop's. On llvmpipe the two OpenGL contexts
# take turns (src/window_gl.h), so there the display's drawing also waits
# for the frame loop's.
# The Xvfb screen is 2048x1152 so that a 1920x1080 window fits in 95% of
# it (windows larger than that are shrunk, as Flitter does). Xvfb draws in
# software: a real display presents faster.
# Not part of the test suite: timings vary with the machine.
set -u
build=${1:-build}
seconds=${2:-10}
case $build in /*) ;; *) build=$PWD/$build ;; esac
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
command -v xvfb-run >/dev/null 2>&1 || { echo "bench/window.sh needs xvfb-run (Debian: xvfb)" >&2; exit 2; }
cd "$(dirname "$0")/.." || exit 2
out=$(mktemp -d) || exit 2
trap 'rm -rf "$out"' EXIT

routes=${ROUTES:-gl readback}
repo=${FLITTER_REPO:-/work/.mirror/jonathanhogg+flitter/repo}
rev=${FLITTER_REV:-v1.0.0b28}

run_scene() {   # NAME SCRIPT [OPTIONS...]: the scene by each route
    for route in $routes; do
        run_route "$route" "$@" || return 1
    done
}

run_route() {   # ROUTE NAME SCRIPT [OPTIONS...]
    route=$1 name=$2 script=$3
    shift 3
    readback=0
    [ "$route" = readback ] && readback=1
    FLITTER_WINDOW_READBACK=$readback xvfb-run -a -s "-screen 0 2048x1152x24" \
        "$flitter" run --window --realtime --fps 60 --runtime "$seconds" --stats "$@" "$script" \
        >/dev/null 2>"$out/$name.err"
    rc=$?
    if [ "$rc" != 0 ] || ! grep -q '^stats: window:' "$out/$name.err"; then
        echo "bench/window.sh: $name: no window run (exit $rc):" >&2
        sed 's/^/  /' "$out/$name.err" >&2
        return 1
    fi
    awk -v name="$name" -v route="$route" '
    /^stats: [0-9]+ frames in/ { fps = $7 }
    /^stats: per frame: eval/ { ev = $5; ph = $8 }
    /^stats: window: per frame shown: draw/ { dr = $7; pr = $10 }
    /^stats: window: [0-9]+ frames shown/ { dropped = $6 }
    /^stats: window: frame loop busy/ { busy = $6 }
    /^stats: window: physics view painted by the display/ { pa = $9 }
    END {
      spare = busy != "" ? 1000 / 60 - busy : 1000 / 60 - (ev + ph + dr + pr)
      printf "%-10s %-9s %9.1f %8.3f %11.3f %8.3f %8.3f %11.3f %8s %9.3f %12.3f %8d\n", name, route, fps, ev, ph, dr,
             pa, pr, busy != "" ? sprintf("%.3f", busy) : "-", spare, 1000 / 60 - pa - pr, dropped
    }' "$out/$name.err"
}

printf "%-10s %-9s %9s %8s %11s %8s %8s %11s %8s %9s %12s %8s\n" scene route "frames/s" "eval ms" "physics ms" \
    "draw ms" "paint ms" "present ms" "loop ms" "spare ms" "display spare" dropped
status=0
run_scene petri samples/petri.fl --window-size 1920x1080 || status=1
run_scene canvas10k bench/canvas10k.fl || status=1
printf '!window size=1920;1080\n    !canvas\n' >"$out/blank.fl"
run_scene blank "$out/blank.fl" || status=1
cat >"$out/shader.fl" <<'FL'
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
run_scene shader "$out/shader.fl" || status=1
if [ -n "${FLITTER_EXAMPLES:-}" ] && cp "$FLITTER_EXAMPLES/physics.fl" "$out/physics.fl" 2>/dev/null ||
    git -C "$repo" show "$rev:examples/physics.fl" >"$out/physics.fl" 2>/dev/null; then
    run_scene physics3d "$out/physics.fl" || status=1
else
    echo "physics3d: no Flitter examples (set FLITTER_EXAMPLES=DIR or FLITTER_REPO=GIT_DIR): left out" >&2
fi
exit $status
