#!/bin/sh
# bench/physics.sh [BUILD_DIR] [BASELINE_BINARY] [REPEATS]: the physics
# scenes of bench/, each run headless (lockstep, one step a frame) with
#   naive-1   --pairs naive --threads 1  (the reference all-pairs loop)
#   fast-1    --pairs fast  --threads 1  (neighbour grid / gather, 1 thread)
#   fast-N    --pairs fast               (every available core)
#   base      BASELINE_BINARY, if given (an older flitter with the same CLI)
#   flitter   the reference Flitter, if FLITTER_REF names a command that
#             runs `$FLITTER_REF SCENE.fl FRAMES` headless in lockstep (its
#             default, simplifying mode) and prints `loop=SECONDS`, its frame
#             loop; it comes first, so the speedups are against it
# Variants are interleaved and each figure is the best of REPEATS (default
# 3) runs. `loop` is the frame loop as `--stats` measures it (evaluation,
# collection, physics and state writes of every frame; loading excluded, as
# in Flitter's own figures), `wall` the whole process. Prints a table of
# both, frames/s, steps/s (frame 0 makes no step) and all-pairs-equivalent
# pairs/s (N(N-1)/2 pairs per step) of the loop; speedup is of the loop,
# against the first variant. A baseline binary without --stats gets its wall
# time as its loop time.
# The all-pairs variants (flitter, base, naive-1) are left out above 50,000
# particles (minutes a step). Not part of the test suite: timings vary.
set -u
build=${1:-build}
base=${2:-}
reps=${3:-3}
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
cd "$(dirname "$0")/.." || exit 2
out=$(mktemp) || exit 2
trap 'rm -f "$out"' EXIT

# scene frames particles
scenes="petri200 600 201
discs2k 120 2000
charges1k 20 1001
discs20k 10 20000
discs100k 10 100000"

now() { date +%s.%N; }
variants="naive-1 fast-1 fast-N"
[ -n "$base" ] && variants="base $variants"
[ -n "${FLITTER_REF:-}" ] && variants="flitter $variants"

echo "$scenes" | while read -r scene frames n; do
    for _ in $(seq "$reps"); do
        for v in $variants; do
            if [ "$n" -gt 50000 ] && { [ "$v" = base ] || [ "$v" = naive-1 ] || [ "$v" = flitter ]; }; then
                continue
            fi
            if [ "$v" = flitter ]; then
                s=$(now)
                st=$($FLITTER_REF "bench/$scene.fl" "$frames" 2>&1)
                e=$(now)
                loop=$(echo "$st" | sed -n 's/.*loop=\([0-9.]*\).*/\1/p' | tail -1)
                echo "$scene $frames $n $v ${loop:-nan} $(awk -v e="$e" -v s="$s" 'BEGIN { printf "%.9f", e - s }')" >>"$out"
                continue
            fi
            case $v in
            base) cmd="$base run" ;;
            naive-1) cmd="$flitter run --pairs naive --threads 1" ;;
            fast-1) cmd="$flitter run --pairs fast --threads 1" ;;
            fast-N) cmd="$flitter run --pairs fast" ;;
            esac
            s=$(now)
            st=$($cmd --stats --frames "$frames" "bench/$scene.fl" 2>&1 >/dev/null)
            e=$(now)
            wall=$(awk -v e="$e" -v s="$s" 'BEGIN { printf "%.9f", e - s }')
            loop=$(echo "$st" | sed -n 's/^stats: [0-9]* frames in \([0-9.]*\) s.*/\1/p')
            echo "$scene $frames $n $v ${loop:-$wall} $wall" >>"$out"
        done
    done
done
awk '
{ k = $1 " " $4; if (!(k in best) || $5 < best[k]) best[k] = $5;
  if (!(k in bwall) || $6 < bwall[k]) bwall[k] = $6;
  fr[$1] = $2; np[$1] = $3; if (!($1 in seen)) { seen[$1] = 1; order[++ns] = $1 }
  if (!($4 in vseen)) { vseen[$4] = 1; vorder[++nv] = $4 } }
END {
  printf "%-10s %-8s %8s %8s %9s %9s %12s %8s\n", "scene", "variant", "loop s", "wall s", "frames/s", "steps/s", "pairs/s", "speedup"
  for (i = 1; i <= ns; i++) {
    s = order[i]; ref = ""
    for (j = 1; j <= nv; j++) {
      v = vorder[j]; if (!((s " " v) in best)) continue
      t = best[s " " v]; if (ref == "") ref = t
      printf "%-10s %-8s %8.3f %8.3f %9.1f %9.1f %12.3g %7.1fx\n", s, v, t, bwall[s " " v], fr[s] / t, (fr[s] - 1) / t,
             np[s] * (np[s] - 1) / 2 * (fr[s] - 1) / t, ref / t
    }
  }
}' "$out"
