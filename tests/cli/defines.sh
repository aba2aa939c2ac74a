#!/usr/bin/env bash
# defines.sh FLITTER: `-D NAME=VALUE` values reach the script as Flitter's
# own command line reads them (issue 59): a sign, a suffix, a time code,
# several parts, a symbol, an empty text and plain text, through `flitter
# run` with both spellings of the option.
set -uo pipefail
flitter=$1
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
printf '!foo x=X twice=X*2 n=len(X)\n' >"$dir/d.fl"

check() {   # check VALUE WANT: the !foo line of the tree
    local got
    got=$("$flitter" run --frames 1 --dump-tree -D "X=$1" "$dir/d.fl" 2>&1 | sed -n 2p) ||
        fail "-D X=$1 exited $?"
    [ "$got" = " !foo $2" ] || fail "-D X=$1: got '$got', want ' !foo $2'"
    got=$("$flitter" run --frames 1 --dump-tree --define "X=$1" "$dir/d.fl" 2>&1 | sed -n 2p)
    [ "$got" = " !foo $2" ] || fail "--define X=$1: got '$got'"
}
check -3 'x=-3 twice=-6 n=1'
check +2.5 'x=2.5 twice=5 n=1'
check '-1;2' 'x=-1;2 twice=-2;4 n=2'
check '' 'x="" n=1'
check 1:30 'x=90 twice=180 n=1'
check -10k 'x=-10000 twice=-20000 n=1'
check -0.5e-1 'x=-0.05 twice=-0.1 n=1'
check inf 'x=inf twice=inf n=1'
check ' 7 ' 'x=7 twice=14 n=1'
check 1_000 'x=1000 twice=2000 n=1'
check abc 'x="abc" n=1'
check 'a;-1' 'x="a";-1 n=2'
got=$("$flitter" run --frames 1 --dump-tree -D X=:sym "$dir/d.fl" 2>&1 | sed -n 2p)
[[ "$got" == " !foo x=:sym twice="* ]] || fail "-D X=:sym: got '$got'"

# a define read once, used through a let
printf 'let v = X * 1\n!foo x=v\n' >"$dir/e.fl"
got=$("$flitter" run --frames 1 --dump-tree -D X=-3 "$dir/e.fl" 2>&1 | sed -n 2p)
[ "$got" = " !foo x=-3" ] || fail "let of a define: got '$got'"
echo "defines: all checks passed"
