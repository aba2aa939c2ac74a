#!/usr/bin/env bash
# clock_limit.sh FLITTER: the clock stops where a state file can still hold
# it (issue 59): a state saved at frame 2^53 - 1 runs one more frame, then
# the run ends with `SCRIPT: error: frame 9007199254740992: the clock is at
# its limit ...` and exit 1; the state it saves (frame 2^53) loads again
# and the next run says the same, never "out of range".
set -uo pipefail
flitter=$1
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
printf '!foo t=time\n' >"$dir/a.fl"
# a version 2 state file at frame 2^53 - 1, its checksum FNV-1a 64 of the
# bytes before the checksum line (docs: FORMATS.md §4, --state)
python3 - "$dir/big.state" <<'PY'
import sys
body = "flitter-state 2\nclock 9007199254740991 5 4.98 9.96 0.5 4 0\nend 0\n"
h = 0xcbf29ce484222325
for b in body.encode():
    h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
open(sys.argv[1], "w").write(body + "checksum %016x\n" % h)
PY
"$flitter" run --frames 3 --state "$dir/big.state" --dump-state "$dir/a.fl" >"$dir/out" 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] || fail "exit $rc, not 1: $(cat "$dir/err")"
grep -qx "# frame 9007199254740991 time 5" "$dir/out" || fail "the one frame left did not run: $(cat "$dir/out")"
grep -q "a.fl: error: frame 9007199254740992: the clock is at its limit" "$dir/err" || fail "message: $(cat "$dir/err")"
grep -q '^clock 9007199254740992 ' "$dir/big.state" || fail "state not saved at frame 2^53: $(cat "$dir/big.state")"
"$flitter" run --frames 1 --state "$dir/big.state" "$dir/a.fl" >/dev/null 2>"$dir/err2"
rc=$?
[ $rc -eq 1 ] && grep -q "the clock is at its limit" "$dir/err2" && ! grep -q "out of range" "$dir/err2" ||
    fail "the saved state at 2^53: exit $rc: $(cat "$dir/err2")"
echo "clock_limit: all checks passed"
