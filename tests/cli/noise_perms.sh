#!/bin/sh
# noise_perms.sh FLITTER TESTS_DIR: noise()'s permutation tables kept by
# the runtime (lib/builtins/noise.c, NoisePerms) give what tables made for
# every call give. cli/noise_perms.fl calls noise and octnoise with more
# seeds than the memo holds, interleaved. The simplifier folds every call
# at load (their arguments are literal), without a memo; with
# --nosimplify every call runs in every frame, through the memo (the
# second frame's tables were kept from the first, or made again where
# they were replaced). The second frame's node trees must be byte for
# byte the same, and the same as the tree FLITTER_NOFAST=1 gives.
set -u
flitter=$1 tests=$2
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
f=$tests/cli/noise_perms.fl
fail=0
"$flitter" run --frames 2 --dump-tree "$f" >"$dir/simplified" 2>&1 || fail=1
"$flitter" run --frames 2 --dump-tree --nosimplify "$f" >"$dir/plain" 2>&1 || fail=1
FLITTER_NOFAST=1 "$flitter" run --frames 2 --dump-tree --nosimplify "$f" >"$dir/generic" 2>&1 || fail=1
for other in plain generic; do
    if ! cmp -s "$dir/simplified" "$dir/$other"; then
        echo "noise with the simplifier and $other differ:" >&2
        diff "$dir/simplified" "$dir/$other" | head -6 >&2
        fail=1
    fi
done
# the script's 60 nodes, each with its four noises
n=$(grep -c '!n a=.* b=.* c=.* d=' "$dir/plain")
[ "$n" -eq 60 ] || { echo "expected 60 !n nodes, got $n" >&2; fail=1; }
grep -q 'a=null\|b=null\|c=null' "$dir/plain" && { echo "a noise came out null" >&2; fail=1; }
exit $fail
