#!/bin/sh
# fast_route.sh FLITTER TESTS_DIR BENCH_DIR: the compiled evaluation route
# (lib/eval/numexpr.c, lib/eval/evalcode.c), with its loop kernels
# (lib/eval/kernel.c) on every core and on one thread, and without them
# (FLITTER_NOKERNEL=1), against the generic tree walk (FLITTER_NOFAST=1),
# byte for byte: the state dumps of the golden scripts
# and the node trees of the language scripts, each with and without the
# simplifier, plus the stderr messages, and the bench scenes' trees.
set -u
flitter=$1 tests=$2 bench=$3
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail=0 count=0
compare() {   # compare NAME ARGS...
    name=$1
    shift
    FLITTER_NOFAST=1 "$flitter" run "$@" >"$dir/generic" 2>"$dir/generic.err"
    rc1=$?
    for route in fast nokernel onethread; do
        case $route in
        fast) env -u FLITTER_NOFAST -u FLITTER_NOKERNEL "$flitter" run "$@" ;;
        nokernel) env -u FLITTER_NOFAST FLITTER_NOKERNEL=1 "$flitter" run "$@" ;;
        onethread) env -u FLITTER_NOFAST -u FLITTER_NOKERNEL FLITTER_THREADS=1 "$flitter" run "$@" ;;
        esac >"$dir/$route" 2>"$dir/$route.err"
        rc2=$?
        count=$((count + 1))
        if [ $rc1 -ne $rc2 ] || ! cmp -s "$dir/generic" "$dir/$route" ||
            ! cmp -s "$dir/generic.err" "$dir/$route.err"; then
            echo "$route and generic routes differ: $name ($*)" >&2
            diff "$dir/generic" "$dir/$route" | head -10 >&2
            diff "$dir/generic.err" "$dir/$route.err" | head -10 >&2
            fail=1
        fi
    done
}
for mode in "" --nosimplify; do
    for f in "$tests"/golden/*.fl; do
        # shellcheck disable=SC2086
        compare "$f" $mode --frames 120 --dump-every 30 --dump-state "$f"
    done
    for f in "$tests"/lang/*.fl; do
        # shellcheck disable=SC2086
        compare "$f" $mode --frames 2 --dump-tree "$f"
    done
    # shellcheck disable=SC2086
    compare vector_names $mode --frames 2 --dump-tree -D 'V=1;2;3' "$tests/cli/vector_names.fl"
    # shellcheck disable=SC2086
    compare canvas10k $mode --frames 2 --dump-tree "$bench/canvas10k.fl"
    # shellcheck disable=SC2086
    compare petri200 $mode --frames 60 --dump-state "$bench/petri200.fl"
done
[ $count -ge 120 ] || { echo "only $count comparisons ran" >&2; exit 1; }
exit $fail
