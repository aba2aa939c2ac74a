#!/bin/sh
# bench/frames.sh [BUILD_DIR] [BASELINE_BINARY] [REPEATS]: the two scenes
# of "frames that cost little" (issue 10), each run headless in lockstep:
#   petri200   600 frames (200 cells: evaluation, collection, all-pairs
#              electrostatics and collisions, !random, state writes)
#   canvas10k   30 frames (10,000 !ellipse nodes whose every attribute
#              depends on time: the evaluator)
# with the variants
#   flitter    the reference Flitter, if FLITTER_REF names a command that
#              runs `$FLITTER_REF SCENE.fl FRAMES` headless in lockstep (its
#              default, simplifying mode) and prints `loop=SECONDS`, its
#              frame loop; it comes first, so the speedups are against it
#   base       BASELINE_BINARY, if given (an older flitter with --stats)
#   default    this build, Flitter's default mode (simplifier on)
#   nosimplify this build with --nosimplify
# interleaved, each figure the best of REPEATS (default 5) runs. `loop` is
# the frame loop (`--stats`: evaluation, physics and state writes of every
# frame; loading excluded, as in Flitter's own figures). Also prints the
# allocation and eval/physics split lines of `--stats` for this build.
# Not part of the test suite: timings vary with the machine.
set -u
build=${1:-build}
base=${2:-}
reps=${3:-5}
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
cd "$(dirname "$0")/.." || exit 2
out=$(mktemp) || exit 2
trap 'rm -f "$out"' EXIT

scenes="petri200 600
canvas10k 30"
variants="default nosimplify"
[ -n "$base" ] && variants="base $variants"
[ -n "${FLITTER_REF:-}" ] && variants="flitter $variants"

echo "$scenes" | while read -r scene frames; do
    for _ in $(seq "$reps"); do
        for v in $variants; do
            if [ "$v" = flitter ]; then
                st=$($FLITTER_REF "bench/$scene.fl" "$frames" 2>&1)
                loop=$(echo "$st" | sed -n 's/.*loop=\([0-9.]*\).*/\1/p' | tail -1)
                echo "$scene $frames $v ${loop:-nan}" >>"$out"
                continue
            fi
            case $v in
            base) cmd="$base run" ;;
            default) cmd="$flitter run" ;;
            nosimplify) cmd="$flitter run --nosimplify" ;;
            esac
            st=$($cmd --stats --frames "$frames" "bench/$scene.fl" 2>&1 >/dev/null)
            loop=$(echo "$st" | sed -n 's/^stats: [0-9]* frames in \([0-9.]*\) s.*/\1/p')
            echo "$scene $frames $v ${loop:-nan}" >>"$out"
        done
    done
done
awk '
{ k = $1 " " $3; if (!(k in best) || $4 < best[k]) best[k] = $4;
  fr[$1] = $2; if (!($1 in seen)) { seen[$1] = 1; order[++ns] = $1 }
  if (!($3 in vseen)) { vseen[$3] = 1; vorder[++nv] = $3 } }
END {
  printf "%-10s %-10s %9s %11s %9s %8s\n", "scene", "variant", "loop s", "ms/frame", "frames/s", "speedup"
  for (i = 1; i <= ns; i++) {
    s = order[i]; ref = ""
    for (j = 1; j <= nv; j++) {
      v = vorder[j]; if (!((s " " v) in best)) continue
      t = best[s " " v]; if (ref == "") ref = t
      printf "%-10s %-10s %9.4f %11.3f %9.1f %7.1fx\n", s, v, t, 1000 * t / fr[s], fr[s] / t, ref / t
    }
  }
}' "$out"
echo
for scene in petri200 canvas10k; do
    echo "== $scene, this build, --stats over 600 frames"
    "$flitter" run --stats --frames 600 "bench/$scene.fl" 2>&1 >/dev/null | sed 's/^stats: /  /'
done
