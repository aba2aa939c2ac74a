#!/bin/sh
# test_frames.sh FLITTER SAMPLES_DIR: when a state golden fails, `flitter
# test` says how it differs. Frames that do not line up (the MANIFEST's
# --dump-every changed) are named as such, with both frame lists, and no
# "0 ULP" figure is printed as if numbers had been compared; a key missing
# from the output is named; one changed last digit gives a ULP figure with
# its key and frame.
set -u
flitter=$1 samples=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "$*" >&2; cat "$dir/out" >&2; exit 1; }
cp "$samples/wire.fl" "$samples/wire.state" "$dir/" || exit 2
echo 'wire.fl --frames 300 --dump-every 100' >"$dir/MANIFEST"
"$flitter" test "$dir" >"$dir/out" || fail "the copy should pass"

# frames that do not line up: dumps every 50 frames instead of every 100
echo 'wire.fl --frames 300 --dump-every 50' >"$dir/MANIFEST"
"$flitter" test "$dir" >"$dir/out"
[ $? -eq 1 ] || fail "other frames: expected exit 1"
grep -qx "frames do not line up: expected 3 dumps (frame 99, 199, 299), got 6 (frame 49, 99, 149, 199, 249, 299); numbers are compared only in frames both have" "$dir/out" \
    || fail "other frames: no clear message"
grep -q "0 ULP" "$dir/out" && fail "other frames: a 0 ULP figure"
grep -qx "no numeric difference in the [0-9]* numbers that line up" "$dir/out" \
    || fail "other frames: the matching frames should compare equal"

# no frame in common
echo 'wire.fl --frames 300 --dump-every 75' >"$dir/MANIFEST"
"$flitter" test "$dir" >"$dir/out"
grep -q "^frames do not line up: expected 3 dumps (frame 99, 199, 299), got 4 (frame 74, 149, 224, 299)" "$dir/out" \
    && grep -q "0 ULP" "$dir/out" && fail "no common frame... but 0 ULP"
grep -q "^frames do not line up" "$dir/out" || fail "frames 74..299: no message"

# a key missing from the expected file shows as a key only in the output
echo 'wire.fl --frames 300 --dump-every 100' >"$dir/MANIFEST"
grep -v '^:wire;0 = ' "$samples/wire.state" >"$dir/wire.state"
"$flitter" test "$dir" >"$dir/out"
grep -qx "keys that do not line up: 0 only in expected, 3 only in actual (first: :wire;0)" "$dir/out" \
    || fail "missing key: not named"
grep -q "frames do not line up" "$dir/out" && fail "missing key: frames said not to line up"
grep -qx "no numeric difference in the [0-9]* numbers that line up" "$dir/out" \
    || fail "missing key: the other numbers should compare equal"

# one last digit changed: a ULP figure at that key and frame
awk 'BEGIN{done=0} /^:wire;0;:velocity = / && !done {v=$3; d=substr(v,length(v),1); $3=substr(v,1,length(v)-1) (d=="9"?"8":d+1); done=1} {print}' \
    "$samples/wire.state" >"$dir/wire.state"
"$flitter" test "$dir" >"$dir/out"
grep -Eqx "largest numeric difference: [1-9][0-9]* ULP at :wire;0;:velocity \(frame 99 time [0-9.e+-]*\)" "$dir/out" \
    || fail "one digit: no ULP figure at the key and frame"
exit 0
