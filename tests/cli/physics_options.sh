#!/bin/sh
# physics_options.sh FLITTER SCRIPT EXPECTED OPTIONS...: `flitter run` with
# --threads 1, --threads 2, --threads 3, --pairs naive/fast and --particles
# literal/fast all write the EXPECTED state dump byte for byte; bad values of
# these options are usage errors (exit 2) naming the option.
set -u
flitter=$1 script=$2 expected=$3
shift 3
out=$(mktemp) || exit 2
trap 'rm -f "$out"' EXIT
for o in "--threads 1" "--threads 2" "--threads 3" "--pairs naive" "--pairs fast --threads 2" \
         "--particles literal" "--particles literal --pairs naive" "--particles fast --threads 2"; do
    # shellcheck disable=SC2086
    "$flitter" run $o "$@" --dump-state "$script" >"$out" || { echo "$o: exit $?" >&2; exit 1; }
    cmp -s "$expected" "$out" || { echo "$o: state differs" >&2; exit 1; }
done
for o in "--threads 0" "--threads x" "--pairs slow" "--particles naive"; do
    # shellcheck disable=SC2086
    "$flitter" run $o --frames 1 "$script" >/dev/null 2>"$out"
    rc=$?
    [ $rc -eq 2 ] || { echo "$o: expected exit 2, got $rc" >&2; exit 1; }
    grep -q "bad value" "$out" || { echo "$o: no message" >&2; cat "$out" >&2; exit 1; }
done
exit 0
