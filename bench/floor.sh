#!/bin/sh
# bench/floor.sh [BUILD_DIR] [RUNS]: the floors under discs20k's load on
# this machine (issue 24: "loading in less than one frame"), measured
# beside the load and the frame themselves. Medians and the slowest of
# RUNS rounds (default 9); a round runs every measurement once, as a
# process of its own, so that a slow spell of the machine falls on all of
# them alike. Milliseconds:
#   - writing memory (bench/fresh_memory.c, compiled here with cc):
#     100,000 blocks of 64 bytes from malloc (the node tree's blocks:
#     20,000 nodes and their 80,000 attribute vectors), fresh and taken
#     again after being freed (as a live reload finds them); and 3.2 MB
#     in one mapping (20,000 nodes of 160 bytes: a kind, four attribute
#     names and values and six numbers, in no allocator's blocks at all),
#     in 4 KB pages and with transparent huge pages asked for;
#   - flitter's load (`stats: load`, --frames 0) of an empty script, of
#     bench/draws20k.fl (discs20k's random numbers, without nodes) and of
#     bench/discs20k.fl;
#   - discs20k's frame (`stats: per frame`: eval, physics and the rest,
#     averaged over 300 frames, the first two included).
# Not part of the test suite: timings vary with the machine and its load.
set -u
build=${1:-build}
runs=${2:-9}
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
flitter=$(cd "$(dirname "$flitter")" && pwd)/flitter   # the same binary after the cd below
cd "$(dirname "$0")/.." || exit 2
tmp=$(mktemp -d) || exit 2
trap 'rm -rf "$tmp"' EXIT
cc -O2 -std=c17 -Wall -Wextra -o "$tmp/fresh_memory" bench/fresh_memory.c || exit 2
: > "$tmp/empty.fl"

memory() { "$tmp/fresh_memory" "$@" | awk '{print $1}'; }
load() { "$flitter" run --frames 0 --stats "$1" 2>&1 | awk '/^stats: load/ {print $3}'; }
frame() {
    "$flitter" run --frames 300 --stats "$1" 2>&1 |
        awk '/^stats: per frame/ {print $5 + $8 + $11}'
}

i=0
while [ "$i" -lt "$runs" ]; do
    memory malloc 100000 64 >> "$tmp/1"
    memory reuse 100000 64 >> "$tmp/2"
    memory pages 20000 160 >> "$tmp/3"
    memory huge 20000 160 >> "$tmp/4"
    load "$tmp/empty.fl" >> "$tmp/5"
    load bench/draws20k.fl >> "$tmp/6"
    load bench/discs20k.fl >> "$tmp/7"
    frame bench/discs20k.fl >> "$tmp/8"
    i=$((i + 1))
done

n=1
for what in "memory: 100,000 blocks of 64 B from malloc, fresh" \
            "memory: the same, taken again after being freed" \
            "memory: 3.2 MB in one mapping, 4 KB pages" \
            "memory: 3.2 MB in one mapping, huge pages asked for" \
            "load: an empty script" \
            "load: bench/draws20k.fl" \
            "load: bench/discs20k.fl" \
            "frame: discs20k (average of 300)"; do
    sort -n "$tmp/$n" | awk -v what="$what" '{v[NR] = $1}
        END {printf "%-52s %8.3f ms median %8.3f ms slowest\n", what, v[int((NR + 1) / 2)], v[NR]}'
    n=$((n + 1))
done
