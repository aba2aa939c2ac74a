#!/bin/sh
# run_stats.sh FLITTER SCRIPT: `flitter run --stats` reports the frame count,
# the eval/physics split, no allocations in the last (steady) frame and the
# load's milliseconds, on stderr, and leaves stdout (the state dump) unchanged.
set -u
flitter=$1 script=$2
unset FLITTER_NOPOOL   # the steady-frame figure is about the pooled runtime
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
"$flitter" run --frames 12 --dump-state "$script" >"$dir/plain" 2>/dev/null || exit 1
"$flitter" run --stats --frames 12 --dump-state "$script" >"$dir/out" 2>"$dir/err" || exit 1
cmp -s "$dir/plain" "$dir/out" || { echo "--stats changed stdout" >&2; exit 1; }
grep -Eq '^stats: 12 frames in [0-9.]+ s: [0-9.]+ frames/s$' "$dir/err" &&
    grep -Eq '^stats: per frame: eval [0-9.]+ ms, physics [0-9.]+ ms, other [0-9.]+ ms$' "$dir/err" &&
    grep -Eq 'last frame 0 mallocs 0 frees$' "$dir/err" &&
    grep -Eq '^stats: state per frame: [0-9.]+ reads, [0-9.]+ writes$' "$dir/err" &&
    grep -Eq '^stats: load [0-9]+\.[0-9]{3} ms$' "$dir/err" ||
    { echo "unexpected --stats report:" >&2; cat "$dir/err" >&2; exit 1; }
