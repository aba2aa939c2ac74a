#!/bin/sh
# state_resume.sh FLITTER SCRIPT: a run stopped after 150 frames and resumed
# for 150 more (--state) ends bit-identical to a 300-frame run; a truncated
# state file is refused (exit 1, message) and left unchanged.
set -u
flitter=$1 script=$2
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
"$flitter" run --frames 300 --dump-state "$script" >"$dir/full" || exit 1
"$flitter" run --frames 150 --state "$dir/s" "$script" || exit 1
"$flitter" run --frames 150 --state "$dir/s" --dump-state "$script" >"$dir/resumed" || exit 1
if ! cmp -s "$dir/full" "$dir/resumed"; then
    echo "150+150 frames differ from 300 frames:" >&2
    diff -u "$dir/full" "$dir/resumed" | head -20 >&2
    exit 1
fi
head -c 200 "$dir/s" >"$dir/t"
cp "$dir/t" "$dir/t.orig"
"$flitter" run --frames 1 --state "$dir/t" "$script" 2>"$dir/err"
rc=$?
if [ $rc -ne 1 ]; then echo "truncated state file: exit $rc, expected 1" >&2; exit 1; fi
grep -q "state file refused" "$dir/err" || { echo "no refusal message:" >&2; cat "$dir/err" >&2; exit 1; }
cmp -s "$dir/t" "$dir/t.orig" || { echo "truncated state file was changed" >&2; exit 1; }
exit 0
