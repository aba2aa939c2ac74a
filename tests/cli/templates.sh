#!/bin/sh
# templates.sh FLITTER TESTS_DIR BENCH_DIR: unrolled loops simplified by
# template passes (lib/eval/simplify_template.c) against the one copy at a
# time route (FLITTER_NOTEMPLATES=1), for cli/templates.fl (loops whose
# copies differ in shape) and every golden, language and bench script:
# - with FLITTER_TEMPLATE_CHECK=1 (every templated copy compared with its
#   iteration simplified alone, abort on a difference; copies are made,
#   not loops) the simplified program (--dump-simplified) and the load's
#   messages must be byte for byte the same; cli/templates.fl must have all
#   its loops templated, and the benches' unrolled loops too;
# - by default (runs of alike copies become loops over hidden names) the
#   state dumps and node trees they evaluate to, and their messages, must
#   be byte for byte the same; canvas10k must have become such a loop, and
#   a group of one member must have been simplified with its own values.
set -u
flitter=$1 tests=$2 bench=$3
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail=0 count=0
check() {   # check FILE: compare the routes; print the number of templated loops
    f=$1
    FLITTER_NOTEMPLATES=1 "$flitter" run --frames 0 --dump-simplified "$f" >"$dir/one" 2>"$dir/one.err"
    rc1=$?
    env -u FLITTER_NOTEMPLATES FLITTER_TEMPLATE_CHECK=1 "$flitter" run --frames 0 --dump-simplified "$f" \
        >"$dir/tmpl" 2>"$dir/tmpl.all"
    rc2=$?
    grep -v '^flitter: template check: ' "$dir/tmpl.all" >"$dir/tmpl.err"
    count=$((count + 1))
    if [ $rc1 -ne $rc2 ] || ! cmp -s "$dir/one" "$dir/tmpl" || ! cmp -s "$dir/one.err" "$dir/tmpl.err"; then
        echo "template and one-copy routes differ: $f (exit $rc1 / $rc2)" >&2
        diff "$dir/one" "$dir/tmpl" | head -10 >&2
        diff "$dir/one.err" "$dir/tmpl.err" | head -10 >&2
        fail=1
    fi
    templated=$(grep -c '^flitter: template check: ' "$dir/tmpl.all")
}
check "$tests/cli/templates.fl"
# its 22 loops (and, as the check simplifies copies alone, their nested ones) over ..N or literal lists, each with a handful of shapes
[ "$templated" -ge 22 ] || { echo "cli/templates.fl: only $templated loops templated" >&2; fail=1; }
for f in "$tests"/golden/*.fl "$tests"/lang/*.fl; do
    check "$f"
done
for f in canvas10k discs2k discs20k charges1k petri200; do
    check "$bench/$f.fl"
    [ "$templated" -ge 1 ] || { echo "bench/$f.fl: its loop was not templated" >&2; fail=1; }
done
run() {   # run NAME ARGS...: the evaluated outputs of the two routes
    name=$1
    shift
    FLITTER_NOTEMPLATES=1 "$flitter" run "$@" >"$dir/one" 2>"$dir/one.err"
    rc1=$?
    env -u FLITTER_NOTEMPLATES -u FLITTER_TEMPLATE_CHECK "$flitter" run "$@" >"$dir/loop" 2>"$dir/loop.err"
    rc2=$?
    count=$((count + 1))
    if [ $rc1 -ne $rc2 ] || ! cmp -s "$dir/one" "$dir/loop" || ! cmp -s "$dir/one.err" "$dir/loop.err"; then
        echo "template and one-copy routes evaluate differently: $name ($*)" >&2
        diff "$dir/one" "$dir/loop" | head -10 >&2
        diff "$dir/one.err" "$dir/loop.err" | head -10 >&2
        fail=1
    fi
}
run templates --frames 3 --dump-every 1 --dump-tree "$tests/cli/templates.fl"
for f in "$tests"/golden/*.fl; do
    run "$f" --frames 60 --dump-every 20 --dump-state "$f"
done
for f in "$tests"/lang/*.fl; do
    run "$f" --frames 2 --dump-tree "$f"
done
run canvas10k --frames 2 --dump-tree "$bench/canvas10k.fl"
run petri200 --frames 30 --dump-state "$bench/petri200.fl"
env -u FLITTER_NOTEMPLATES -u FLITTER_TEMPLATE_CHECK "$flitter" run --frames 0 --dump-simplified \
    "$bench/canvas10k.fl" >"$dir/loop" 2>&1
grep -q "for ⟨t0⟩" "$dir/loop" || { echo "bench/canvas10k.fl: its loop was copied, not run as a loop" >&2; fail=1; }
# templates.fl's loop of !nest: its member i=0 is a group of one, simplified
# with its own values, so its loop over j is a loop form of its own
env -u FLITTER_NOTEMPLATES -u FLITTER_TEMPLATE_CHECK "$flitter" run --frames 0 --dump-simplified \
    "$tests/cli/templates.fl" >"$dir/loop" 2>/dev/null
grep -q "for ⟨t0⟩;⟨t1⟩ in 0.25;0;0.5;0;0.75;0;" "$dir/loop" ||
    { echo "cli/templates.fl: the member alone of the !nest loop was not simplified with its own values" >&2; fail=1; }
# the check with nested copies past half the unroll limit (2^20): each copy
# alone counts them from where one copy at a time would; a second count on
# top of the templates' made the check stop with "template copy 2 differs".
# Too slow under valgrind (its preload library in LD_PRELOAD), so left to
# the other phases there.
case "${LD_PRELOAD:-}" in
*vgpreload*) ;;
*)
    printf '!window size=10;10\n    for i in ..4\n        for j in ..150000\n            !u a=j b=i\n' >"$dir/big.fl"
    count=$((count + 1))
    if ! env -u FLITTER_NOTEMPLATES FLITTER_TEMPLATE_CHECK=1 "$flitter" run --frames 0 --dump-simplified \
        "$dir/big.fl" >"$dir/tmpl" 2>/dev/null ||
        ! FLITTER_NOTEMPLATES=1 "$flitter" run --frames 0 --dump-simplified "$dir/big.fl" >"$dir/one" 2>/dev/null ||
        ! cmp -s "$dir/one" "$dir/tmpl"; then
        echo "the template check of a loop with 600,000 nested copies failed or differs" >&2
        fail=1
    fi
    ;;
esac
[ $count -ge 60 ] || { echo "only $count scripts compared" >&2; exit 1; }
exit $fail
