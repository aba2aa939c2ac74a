#!/bin/sh
# flat_scripts.sh FLITTER LOADGEN: flat scripts of any length load, in both
# modes (issue 28: the parser's limit counted statements, so 3,332 `let`
# lines or 1,000 top-level `func`s were refused as "program nested too
# deeply"); only real nesting is limited.
set -u
flitter=$1 loadgen=$2
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
sh "$loadgen" "$dir" || exit 2
fail=0
# check NAME EXPECTED-TREE-LINE: the last frame's node tree, both modes
check() {
    for mode in "" --nosimplify; do
        # shellcheck disable=SC2086
        "$flitter" run --frames 1 --dump-tree $mode "$dir/$1.fl" >"$dir/out" 2>"$dir/err"
        status=$?
        if [ "$status" -ne 0 ]; then
            echo "FAIL $1 $mode: exit status $status" >&2; head -3 "$dir/err" >&2; fail=1; continue
        fi
        printf '!root\n%s\n' "$2" >"$dir/want"
        cmp -s "$dir/want" "$dir/out" || { echo "FAIL $1 $mode: tree" >&2; head -c 300 "$dir/out" >&2; fail=1; }
    done
}
# 10,000 `let` lines: x_i = x_(i-1) + i mod 7, so x_9999 = 29994 at time 0
check lets10k ' !n v=29994'
# 10,000 functions f_i(x) = x*(i mod 5) + time
check funcs10k ' !n v0=0 v1111=1111 v2222=4444 v3333=9999 v4444=17776 v5555=0 v6666=6666 v7777=15554 v8888=26664 v9999=39996'
# 40,000 bindings of one `let`: x_i = x_(i-1)*0.5 + i
check bindings40k ' !n v=79996'
# the other statement kinds that scope over the rest of a block, flat:
# `let x =` blocks, functions and plain lets alternating (5,000 each)
awk 'BEGIN {
    for (i = 0; i < 5000; i++) printf "let b%d =\n    !k id=%d\nfunc g%d(x)\n    x+%d\n", i, i, i, i;
    print "!n v=g4999(1)";
    print "b4999";
}' >"$dir/blocks.fl"
check blocks ' !n v=5000
 !k id=4999'
# `let` lines between nodes nest one level each (each scopes over the rest
# of the block, nodes included): 1,500 of them are within the depth limit
awk 'BEGIN {
    print "let x0=1";
    for (i = 1; i < 1500; i++) printf "!n v=x%d\nlet x%d=x%d+1\n", i - 1, i, i - 1;
}' >"$dir/interleaved.fl"
"$flitter" run --frames 1 --dump-tree "$dir/interleaved.fl" >"$dir/out" 2>"$dir/err" &&
    [ "$(grep -c '^ !n' "$dir/out")" = 1499 ] && grep -qx ' !n v=1499' "$dir/out" ||
    { echo "FAIL interleaved" >&2; head -3 "$dir/err" >&2; fail=1; }
# real nesting is still limited, with the message naming it
awk 'BEGIN { printf "!n v="; for (i = 0; i < 6000; i++) printf "(1+"; printf "1";
             for (i = 0; i < 6000; i++) printf ")"; print "" }' >"$dir/deep.fl"
"$flitter" run --frames 1 "$dir/deep.fl" >/dev/null 2>"$dir/err"
status=$?
[ "$status" -ne 0 ] && grep -q 'nested too deeply' "$dir/err" ||
    { echo "FAIL deep: status $status" >&2; head -2 "$dir/err" >&2; fail=1; }
exit $fail
