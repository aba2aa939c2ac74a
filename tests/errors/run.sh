#!/bin/sh
# run.sh FLITTER DIR CASE: run `FLITTER ARGS` inside DIR, where ARGS is the
# first line of DIR/CASE.args (split on spaces), and compare its stderr with
# DIR/CASE.err byte for byte, its exit status with DIR/CASE.rc and, when
# DIR/CASE.out exists, its stdout with that. A case
# whose args name a state file (`--state X`) works on a scratch copy of
# DIR/X and checks that the copy is left unchanged. `@SCRATCH@` in the args
# (and in the expected output) stands for a scratch directory, which
# DIR/CASE.pre (if any) is run to fill first (`sh CASE.pre SCRATCH`), e.g.
# with a sparse oversized file or generated scripts.
set -u
flitter=$1 dir=$2 case=$3
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
cd "$dir" || exit 2
scratch=$(mktemp -d) || exit 2
trap 'rm -rf "$scratch"' EXIT
args=$(head -n 1 "$case.args")
expected_rc=$(cat "$case.rc")
files=$scratch/files
mkdir "$files" || exit 2
args=$(printf '%s\n' "$args" | sed "s#@SCRATCH@#$files#g")
if [ -f "$case.pre" ]; then
    sh "$case.pre" "$files" || exit 2
fi
state=$(printf '%s\n' "$args" | sed -n 's/.*--state \([^ ]*\).*/\1/p')
if [ -n "$state" ]; then
    cp "$state" "$scratch/state"
    args=$(printf '%s\n' "$args" | sed "s#--state $state#--state $scratch/state#")
fi
# shellcheck disable=SC2086
"$flitter" $args >"$scratch/stdout" 2>"$scratch/stderr" </dev/null
rc=$?
# paths in the case's scratch directory read as @SCRATCH@
for f in stdout stderr; do
    sed "s#$files#@SCRATCH@#g" "$scratch/$f" >"$scratch/$f.named"
    mv "$scratch/$f.named" "$scratch/$f"
done
if [ -n "$state" ]; then
    # messages name the scratch copy: put the case's file name back
    sed "s#$scratch/state#$state#g" "$scratch/stderr" >"$scratch/stderr.named"
    mv "$scratch/stderr.named" "$scratch/stderr"
fi
fail=0
if [ "$rc" != "$expected_rc" ]; then
    echo "$case: exit status $rc, expected $expected_rc" >&2
    fail=1
fi
if ! cmp -s "$case.err" "$scratch/stderr"; then
    echo "$case: stderr differs from $case.err:" >&2
    diff -u "$case.err" "$scratch/stderr" | head -30 >&2
    fail=1
fi
if [ -f "$case.out" ] && ! cmp -s "$case.out" "$scratch/stdout"; then
    echo "$case: stdout differs from $case.out:" >&2
    diff -u "$case.out" "$scratch/stdout" | head -30 >&2
    fail=1
fi
if [ -n "$state" ] && ! cmp -s "$state" "$scratch/state"; then
    echo "$case: state file was changed" >&2
    fail=1
fi
exit $fail
