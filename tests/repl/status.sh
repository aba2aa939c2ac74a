#!/bin/sh
# status.sh FLITTER PETRI.fl: the exit status of scripted REPL sessions.
set -u
flitter=$1 petri=$2
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "$*" >&2; exit 1; }

printf ':step 3\n1+2\n' | "$flitter" repl "$petri" >"$dir/out" 2>&1
[ $? -eq 0 ] || fail "a clean session should exit 0: $(cat "$dir/out")"
grep -qx 3 "$dir/out" || fail "no result: $(cat "$dir/out")"

# :view draws the systems as they are now
printf ':step 2\n:view %s\n' "$dir/v.png" | "$flitter" repl "$petri" >"$dir/out" 2>&1
[ $? -eq 0 ] || fail ":view failed: $(cat "$dir/out")"
grep -qx "drew 1 system to $dir/v.png" "$dir/out" && [ "$(head -c 4 "$dir/v.png" | tail -c 3)" = PNG ] \
    || fail ":view: $(cat "$dir/out")"

printf '1+2\n' | "$flitter" repl "$dir/missing.fl" >"$dir/out" 2>&1
[ $? -eq 1 ] || fail "a script that fails to load should give exit 1"
grep -q 'missing.fl: error:' "$dir/out" || fail "no load error: $(cat "$dir/out")"
grep -qx 3 "$dir/out" || fail "the session should go on after a load error: $(cat "$dir/out")"

printf '1+2\n(1+\n' | "$flitter" repl "$petri" >"$dir/out" 2>&1
[ $? -eq 1 ] || fail "an unclosed bracket at the end should give exit 1"
grep -q 'input ended early' "$dir/out" || fail "unclosed bracket not reported: $(cat "$dir/out")"

# :set stores an expression's value; a value with an unbound name is refused
printf ':set :x 2*3\n$(:x)\n:set :x nosuch\n$(:x)\n' | "$flitter" repl "$petri" >"$dir/out" 2>&1
[ $? -eq 1 ] || fail "a refused :set should give exit 1: $(cat "$dir/out")"
[ "$(grep -cx 6 "$dir/out")" -eq 2 ] && grep -qx ':x = 6' "$dir/out" \
    && grep -q 'state unchanged' "$dir/out" && [ "$(tail -1 "$dir/out")" = 6 ] \
    || fail ":set: $(cat "$dir/out")"

printf ':bogus\n:step\n' | "$flitter" repl "$petri" >"$dir/out" 2>&1
[ $? -eq 1 ] || fail "an unknown command should give exit 1"
exit 0
