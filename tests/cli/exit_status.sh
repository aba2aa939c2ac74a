#!/bin/sh
# exit_status.sh FLITTER SCRIPT: exit statuses that tell the truth
# (issue 28, item 6):
#   1. --dump-state, --dump-tree, --dump-tokens and --dump-ast into a full
#      disk (/dev/full) exit 1 with a message (they exited 0, dump lost);
#   2. an output that cannot be written (--view, --state, --trace-file,
#      --record into a directory that does not exist; --state naming a
#      device) is refused before the first frame: exit 2, a message naming
#      the option, and the run never starts (a 10^9-frame run would
#      otherwise take for ever; --view used to fail only after the run).
# (A script's !record into a folder that cannot be made: record_atomic.sh,
# with the other tests of files a !record writes.)
set -u
flitter=$1 script=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail=0
bad() { echo "exit_status: $*" >&2; fail=1; }

for opt in --dump-state --dump-tree --dump-tokens --dump-ast; do
    "$flitter" run --frames 2 $opt "$script" >/dev/full 2>"$dir/err"
    rc=$?
    [ $rc -eq 1 ] || bad "$opt into /dev/full: exit $rc, not 1"
    grep -q '^flitter run: the output is incomplete: a write to it failed' "$dir/err" ||
        bad "$opt into /dev/full: message: $(cat "$dir/err")"
done
# the same output to a file that can be written: 0
"$flitter" run --frames 2 --dump-state "$script" >"$dir/ok.out" || bad "--dump-state to a file failed"
grep -q '^# frame 1 ' "$dir/ok.out" || bad "--dump-state to a file: no frame 1"

for case in "--view $dir/none/v.png" "--state $dir/none/s.state" "--trace-file $dir/none/t.csv" \
            "--record $dir/none/r.png" "--state /dev/null"; do
    set -- $case
    timeout 20 "$flitter" run --frames 1000000000 "$@" "$script" >/dev/null 2>"$dir/err"
    rc=$?
    [ $rc -eq 2 ] || bad "$case: exit $rc, not 2"
    grep -q "^flitter run: $1 $2 cannot be written (.*); nothing was run\$" "$dir/err" ||
        bad "$case: message: $(cat "$dir/err")"
done
[ -c /dev/null ] || bad "/dev/null was replaced"

exit $fail
