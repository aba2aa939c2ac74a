#!/bin/sh
# bench/load.sh [BUILD_DIR]: load time (parse, simplify, resolve; no frame:
# --frames 0) of the load benchmarks (issue 24: canvas10k, discs20k;
# issue 28 item 4: one `let` of 40,000 bindings, 50,000 unbound names, flat
# scripts of 10,000 `let` lines and 10,000 `func`s, written by loadgen.sh),
# with and without the simplifier: wall, user and system seconds and peak
# RSS, best of 3 (by wall). Not part of the test suite: timings vary with
# the machine; on a busy machine compare user time or instruction counts
# (valgrind --tool=callgrind) instead.
set -u
build=${1:-build}
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
cd "$(dirname "$0")/.." || exit 2
gen=$(mktemp -d) || exit 2
trap 'rm -rf "$gen"' EXIT
sh bench/loadgen.sh "$gen"
for script in bench/canvas10k.fl bench/discs20k.fl "$gen/bindings40k.fl" "$gen/names50k.fl" \
              "$gen/lets10k.fl" "$gen/funcs10k.fl"; do
    for mode in "" --nosimplify; do
        best=""
        for _ in 1 2 3; do
            # shellcheck disable=SC2086
            r=$(/usr/bin/time -f '%e %U %S %M' "$flitter" run --frames 0 $mode "$script" 2>&1 >/dev/null | tail -1)
            w=${r%% *}
            if [ -z "$best" ] || awk -v w="$w" -v b="${best%% *}" 'BEGIN { exit !(w < b) }'; then best=$r; fi
        done
        set -- $best
        printf '%7s s wall %6s s user %6s s sys %8s KB  %s %s\n' "$1" "$2" "$3" "$4" "$(basename "$script")" "$mode"
    done
done
