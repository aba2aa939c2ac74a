#!/bin/sh
# flitter_cli.sh FLITTER WIRE: --version, help, `flitter test` without
# tests, `run --view/--trace-file` (and --view-axes) wiring on the wire
# sample WIRE (pictures and rows are checked in tests/unit/test_view.c).
# (Flitter's own command line drawing a figure: flitter_figures.sh.)
set -u
flitter=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
wire=$2
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "$*" >&2; exit 1; }

"$flitter" --version >"$dir/out" || fail "--version failed"
grep -Eqx 'flitter-c [0-9]+\.[0-9]+\.[0-9]+' "$dir/out" || fail "--version printed: $(cat "$dir/out")"
"$flitter" help run >"$dir/out" || fail "help run failed"
grep -q -- '--runtime T' "$dir/out" || fail "help run lacks --runtime"
"$flitter" run --runtime 1e300 --fps 60 x.fl 2>"$dir/err"
[ $? -eq 2 ] && grep -q 'runtime 1e+300 is too long' "$dir/err" || fail "--runtime 1e300: $(cat "$dir/err")"
"$flitter" help bogus 2>/dev/null
[ $? -eq 2 ] || fail "help bogus should exit 2"

# `flitter test` in a directory without tests says so (and exits 2)
mkdir "$dir/empty" && (cd "$dir/empty" && "$flitter" test) >"$dir/out" 2>"$dir/err"
[ $? -eq 2 ] || fail "flitter test in an empty directory should exit 2"
grep -q "no tests in '.' (no MANIFEST there" "$dir/err" || fail "flitter test, no tests: $(cat "$dir/err")"

# --trace-file every 2nd frame of 3: frames 0 and 2, 12 bodies each, after a
# header; frame 2's row for particle 3 holds the state dump's numbers
"$flitter" run --frames 3 --trace-file "$dir/t.csv" --trace-every 2 --dump-state "$wire" >"$dir/dump" \
    || fail "run --trace-file failed"
[ "$(wc -l <"$dir/t.csv")" -eq 25 ] || fail "trace rows: $(wc -l <"$dir/t.csv")"
head -1 "$dir/t.csv" | grep -qx 'frame,time,system,id,kind,x,vx' || fail "trace header: $(head -1 "$dir/t.csv")"
x=$(sed -n 's/^:wire;3 = //p' "$dir/dump") v=$(sed -n 's/^:wire;3;:velocity = //p' "$dir/dump")
[ -n "$x" ] && [ -n "$v" ] || fail "no :wire;3 in the dump"
grep -qx "2,0.03333333333333333,wire,3,particle,$x,$v" "$dir/t.csv" \
    || fail "frame 2 row of particle 3 is not $x,$v: $(grep '^2,.*,wire,3,' "$dir/t.csv")"
"$flitter" run --frames 2 --trace-file "$dir/t.jsonl" "$wire" || fail "run --trace-file .jsonl failed"
[ "$(grep -c '^{"frame":1,.*"system":"wire",.*"position":\[.*\],"velocity":\[.*\]}$' "$dir/t.jsonl")" -eq 12 ] \
    || fail "jsonl: $(cat "$dir/t.jsonl")"
# --view: a PNG 480 wide (IHDR), a GIF, and a usage error for another extension
"$flitter" run --frames 5 --view "$dir/v.png" "$wire" || fail "run --view png failed"
[ "$(od -An -tx1 -j16 -N4 "$dir/v.png" | tr -d ' \n')" = "000001e0" ] || fail "v.png is not 480 wide"
"$flitter" run --frames 5 --view "$dir/v.gif" --view-every 2 "$wire" || fail "run --view gif failed"
[ "$(head -c 6 "$dir/v.gif")" = "GIF89a" ] || fail "v.gif is not a GIF89a"
"$flitter" run --frames 5 --view "$dir/v.jpg" "$wire" 2>"$dir/err"
[ $? -eq 2 ] && grep -q 'v.jpg: a view is written to a .png, .svg or .gif file' "$dir/err" || fail "--view v.jpg: $(cat "$dir/err")"
# --view-axes: a 3D system drawn flat on x;z (no OpenGL needed, nothing
# said), and a usage error for a bad pair
printf '!physics state=:b dimensions=3\n    !particle id=1 position=0;0;5 radius=1\n' >"$dir/b3.fl"
"$flitter" run --frames 2 --view "$dir/b3.png" --view-axes 'x;z' "$dir/b3.fl" 2>"$dir/err" || fail "--view-axes x;z failed"
# (LeakSanitizer's report of the suppressions it used may follow a run in
# the sanitizer build: it is no message of flitter's)
said=$(grep -v -e '^-*$' -e '^Suppressions used:' -e '^ *count  *bytes  *template$' \
    -e '^ *[0-9][0-9]*  *[0-9][0-9]*  *[^ ]*$' "$dir/err")
[ -s "$dir/b3.png" ] && [ -z "$said" ] || fail "--view-axes x;z: $(cat "$dir/err")"
"$flitter" run --frames 2 --view "$dir/b3.png" --view-axes 'z;z' "$dir/b3.fl" 2>"$dir/err"
[ $? -eq 2 ] && grep -q "bad value 'z;z' for option '--view-axes'" "$dir/err" || fail "--view-axes z;z: $(cat "$dir/err")"
exit 0
