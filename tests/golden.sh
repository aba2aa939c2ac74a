#!/bin/sh
# golden.sh: run one golden-output test.
# usage: golden.sh FLITTER state|tree SCRIPT EXPECTED [flitter run options...]
# Runs `FLITTER run OPTIONS --dump-state|--dump-tree SCRIPT` and compares its
# stdout byte for byte with EXPECTED; on a mismatch prints the first lines of
# a unified diff and exits 1. When GOLDEN_SKIP is set (to the reason) the
# test is reported as skipped (exit 77) without running.
set -u
flitter=$1 kind=$2 script=$3 expected=$4
shift 4
if [ -n "${GOLDEN_SKIP:-}" ]; then
    echo "skipped: $GOLDEN_SKIP"
    exit 77
fi
out=$(mktemp) || exit 2
trap 'rm -f "$out"' EXIT
"$flitter" run "$@" "--dump-$kind" "$script" >"$out"
rc=$?
if [ $rc -ne 0 ]; then
    echo "flitter exited with status $rc" >&2
    exit 1
fi
if cmp -s "$expected" "$out"; then
    exit 0
fi
echo "output differs from $expected:" >&2
diff -u "$expected" "$out" | head -40 >&2
exit 1
