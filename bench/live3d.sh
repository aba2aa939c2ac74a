#!/bin/sh
# bench/live3d.sh [BUILD_DIR] [SECONDS]: Flitter's 3D physics examples live
# in the window, as a user runs them (`flitter --stats SCRIPT`: realtime,
# the examples' own 1080x1080 windows, Flitter's default 60 frames/s),
# under a private Xvfb server (a 2048x1152 screen, so that the windows are
# not shrunk), SECONDS (default 12) each.
#
# The scripts are Flitter's examples/physics.fl (500 lit bubbles under a
# bloom) and examples/bounce.fl (150 balls, each a point light, in a glass
# box with fog), read at run time from a Flitter git repository as
# bench/canvas3d.sh reads them (FLITTER_REPO, default
# /work/.mirror/jonathanhogg+flitter/repo, at FLITTER_REV, default
# v1.0.0b28; or FLITTER_EXAMPLES=DIR, a Flitter checkout's examples/):
# they are not copied into this repository.
#
# Each runs once per floor in MIN_SCALES (default "0.25 1": --min-scale,
# the live window's least fraction of pixels; 1 is always full size) and
# prints, from --stats: the simulation's frames a second, the pictures
# shown a second (frames shown / seconds), the milliseconds to draw a
# picture on the frame loop and to present it on the display's thread,
# the mean scale of the pictures drawn below full size and the share of
# them, and frames dropped. ROUNDS (default 1) repeats the whole table,
# interleaved. Not part of the test suite: timings vary with the machine
# and its load.
set -u
build=${1:-build}
seconds=${2:-12}
case $build in /*) ;; *) build=$PWD/$build ;; esac
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
command -v xvfb-run >/dev/null 2>&1 || { echo "bench/live3d.sh needs xvfb-run (Debian: xvfb)" >&2; exit 2; }
out=$(mktemp -d) || exit 2
trap 'rm -rf "$out"' EXIT
repo=${FLITTER_REPO:-/work/.mirror/jonathanhogg+flitter/repo}
rev=${FLITTER_REV:-v1.0.0b28}
for ex in physics bounce; do
    if [ -n "${FLITTER_EXAMPLES:-}" ]; then
        cp "$FLITTER_EXAMPLES/$ex.fl" "$out/$ex.fl" || exit 2
    elif ! git -C "$repo" show "$rev:examples/$ex.fl" >"$out/$ex.fl" 2>/dev/null; then
        echo "bench/live3d.sh: no Flitter examples (set FLITTER_EXAMPLES=DIR or FLITTER_REPO=GIT_DIR)" >&2
        exit 2
    fi
done

echo "live3d: $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg), $seconds s each"
printf "%-10s %-9s %9s %10s %9s %11s %11s %9s %8s\n" script min-scale "frames/s" "pictures/s" "draw ms" \
    "present ms" "mean scale" "scaled %" dropped
status=0
round=0
while [ "$round" -lt "${ROUNDS:-1}" ]; do
    round=$((round + 1))
    for ex in physics bounce; do
        for floor in ${MIN_SCALES:-0.25 1}; do
            (cd "$out" && xvfb-run -a -s "-screen 0 2048x1152x24" \
                "$flitter" --stats --runtime "$seconds" --min-scale "$floor" "$ex.fl" >/dev/null 2>"$out/err")
            rc=$?
            if [ "$rc" != 0 ] || ! grep -q '^stats: window:' "$out/err"; then
                echo "bench/live3d.sh: $ex.fl: no window run (exit $rc):" >&2
                sed 's/^/  /' "$out/err" >&2
                status=1
                continue
            fi
            awk -v ex="$ex" -v floor="$floor" -v secs="$seconds" '
            /^stats: [0-9]+ frames in/ { fps = $7 }
            /^stats: window: per frame shown: draw/ { dr = $7; pr = $10 }
            /^stats: window: [0-9]+ frames shown/ { shown = $3; dropped = $6 }
            /^stats: window: frame loop busy/ { drawn = $10 }
            /^stats: window: scale:/ { below = $4; mean = $11; sub(/\),$/, "", mean) }
            END {
              printf "%-10s %-9s %9.1f %10.1f %9.1f %11.1f %11s %9.0f %8d\n", ex ".fl", floor, fps, shown / secs,
                     dr, pr, (below > 0 ? mean : "1"), (drawn > 0 ? 100 * below / drawn : 0), dropped
            }' "$out/err"
        done
    done
done
exit $status
