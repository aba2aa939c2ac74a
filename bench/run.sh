#!/bin/sh
# bench/run.sh [BUILD_DIR]: --stats of the benchmark scenes, then wall time
# of headless runs, best of 5 each.
# Not part of the test suite: timings vary with the machine.
set -u
build=${1:-build}
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
cd "$(dirname "$0")/.." || exit 2
best() {
    b=""
    for _ in 1 2 3 4 5; do
        s=$(date +%s.%N)
        "$@" >/dev/null 2>&1
        e=$(date +%s.%N)
        t=$(awk -v e="$e" -v s="$s" 'BEGIN { printf "%.9f", e - s }')
        if [ -z "$b" ] || awk -v t="$t" -v b="$b" 'BEGIN { exit !(t < b) }'; then b=$t; fi
    done
    printf '%8.3f s  %s\n' "$b" "$*"
}
# The issue-10 scenes: frames/s, allocations per frame and the
# eval/physics/state split, as `flitter run --stats` reports them.
for scene in "bench/petri200.fl 600" "bench/canvas10k.fl 30"; do
    set -- $scene
    echo "== $1 ($2 frames)"
    "$flitter" run --stats --frames "$2" "$1" 2>&1 >/dev/null | sed 's/^stats: /  /'
done
best "$flitter" run --frames 600 bench/petri200.fl
best "$flitter" run --frames 30 bench/canvas10k.fl
best "$flitter" run --frames 600 samples/petri.fl
best "$flitter" run --frames 3000 samples/petri.fl
for f in tests/golden/*.fl; do
    opts=$(grep "^$(basename "$f") " tests/golden/MANIFEST | cut -d' ' -f2- | sed 's/--dump-every [0-9]*//')
    # shellcheck disable=SC2086
    best "$flitter" run $opts "$f"
done
