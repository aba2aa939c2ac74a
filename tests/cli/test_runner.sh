#!/bin/sh
# test_runner.sh FLITTER SAMPLES_DIR: `flitter test` passes on a copy of a
# sample, and fails with a unified diff and a ULP figure when one number of
# the expected file is changed in its last digit; a test whose file name
# holds quotes and `$(...)` shows its diff without running that command
# (diff is spawned with an argument vector, never through a shell).
set -u
flitter=$1 samples=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
cp "$samples/wire.fl" "$samples/wire.state" "$samples/MANIFEST" "$dir/"
"$flitter" test "$dir" >"$dir/out" || { cat "$dir/out" >&2; exit 1; }
grep -qx "1 passed, 0 failed" "$dir/out" || { cat "$dir/out" >&2; exit 1; }
# change the last digit of the first velocity value
awk 'BEGIN{done=0} /;:velocity = / && !done && $3 ~ /[0-9]$/ {d=substr($3,length($3),1); $3=substr($3,1,length($3)-1) (d=="9"?"8":d+1); done=1} {print}' \
    "$dir/wire.state" >"$dir/changed" && mv "$dir/changed" "$dir/wire.state"
"$flitter" test "$dir" >"$dir/out"
rc=$?
[ $rc -eq 1 ] || { echo "expected exit 1, got $rc" >&2; cat "$dir/out" >&2; exit 1; }
grep -q "^FAIL " "$dir/out" && grep -q "^@@ " "$dir/out" && grep -qx "0 passed, 1 failed" "$dir/out" \
    && grep -Eq "largest numeric difference: [1-9][0-9]* ULP" "$dir/out" \
    || { echo "missing diff, ULP figure or summary:" >&2; cat "$dir/out" >&2; exit 1; }
# the same failing test under a hostile name
evil="$dir/evil"
mkdir "$evil" || exit 2
name="x'\$(touch PWNED)'\`touch PWNED2\`"
cp "$dir/wire.fl" "$evil/$name.fl" && cp "$dir/wire.state" "$evil/$name.state" || exit 2
sed -n 's/^wire\.fl *//p' "$samples/MANIFEST" | sed "s|^|$name.fl |" >"$evil/MANIFEST"
(cd "$evil" && "$flitter" test . >"$dir/out")
rc=$?
[ $rc -eq 1 ] || { echo "hostile name: expected exit 1, got $rc" >&2; cat "$dir/out" >&2; exit 1; }
for f in PWNED PWNED2; do
    [ ! -e "$evil/$f" ] || { echo "hostile name: the file name ran a command ($f)" >&2; exit 1; }
done
grep -qF -- "--- ./$name.state (expected)" "$dir/out" && grep -q "^@@ " "$dir/out" \
    || { echo "hostile name: no diff:" >&2; cat "$dir/out" >&2; exit 1; }
exit 0
