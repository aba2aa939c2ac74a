#!/bin/sh
# max_memory.sh FLITTER PETRI.fl: the memory budget (issue 23 item 5, issue
# 28 item 5). Every path that input can make huge ends cleanly, with a
# message, inside the budget (--max-memory, or by default half of the
# address-space limit of `ulimit -v`), instead of aborting (status 134):
#   1. the issue's huge-vector script (a 2^26-element range copied into a
#      long composition, folded at load time): exit 1 with
#      `PATH:1:1: error: out of memory`, within seconds, both under
#      `ulimit -v 4000000` and with `--max-memory 200M`;
#   2. a huge range and a huge zip() at run time: null and an execution
#      error naming out of memory; the run goes on and exits 0;
#   3. a !physics system of dimensions=1048576: a physics error, exit 0;
#   4. a ~120 MB state file of 60 million numbers: refused with a message
#      (exit 1) past a small budget, loaded (exit 0) under ulimit -v 4000000
#      (it is parsed into one array: 8 bytes a number, not an object each);
#   5. a 26 MB script under ulimit -v 4000000: refused at load, exit 1 (the
#      parser's cost per byte, config.h PARSE_BYTES_PER_BYTE, is charged
#      before parsing; measured at 126-144 bytes per byte of source);
#   6. the REPL: a huge expression is reported and the session goes on with
#      its state (the next :step continues from the same frame);
#   7. bad --max-memory values are refused (exit 2);
#   8. a 50 MB budget under ulimit -v 70000 runs a script whose range holds
#      3 million numbers (24 MB): the heap prefaulting of `flitter run`
#      stays off under the limit.
#   9. template passes (lib/eval/simplify_template.c) at budgets too small
#      for their columns: a loop whose members' vectors of two numbers are
#      taken apart by position (`(i;5)+time`) runs or says out of memory at
#      8K to 64K, never crashes; members' compositions of a long range,
#      20,000 of them under ulimit -v 4000000 and 200 under a 400M budget
#      within ulimit -v 800000: exit 1, the load's out of memory.
set -u
flitter=$1 petri=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail=0
bad() { echo "max_memory: $*" >&2; fail=1; }
# run [ULIMIT_KB|-] ARGS...: flitter with its output in $dir/out and $dir/err,
# its status in $rc and its wall time in $secs
run() {
    lim=$1
    shift
    t0=$(date +%s)
    if [ "$lim" = - ]; then
        "$flitter" "$@" >"$dir/out" 2>"$dir/err"
    else
        (ulimit -v "$lim" && exec "$flitter" "$@") >"$dir/out" 2>"$dir/err"
    fi
    rc=$?
    secs=$(($(date +%s) - t0))
}

# 1. the huge-vector script
printf 'let a=..67108863\n!foo n=len(a;a;a;a;a;a;a;a;a;a)\n' >"$dir/huge.fl"
for how in ulimit budget; do
    if [ $how = ulimit ]; then run 4000000 run --frames 1 --dump-tree "$dir/huge.fl"
    else run - run --max-memory 200M --frames 1 --dump-tree "$dir/huge.fl"; fi
    [ $rc -eq 1 ] || bad "huge vectors ($how): exit $rc, not 1: $(cat "$dir/err")"
    grep -q "^$dir/huge.fl:1:1: error: out of memory" "$dir/err" ||
        bad "huge vectors ($how): message: $(cat "$dir/err")"
    [ $secs -le 60 ] || bad "huge vectors ($how): took $secs s"
done

# 2. a huge range and a huge zip at run time (not folded: they depend on
# `frame`): null, logged, and the frame goes on
printf '!foo n=len(..(frame+67108863)) m=1\n' >"$dir/range.fl"
run - run --max-memory 200M --frames 2 --dump-tree "$dir/range.fl"
[ $rc -eq 0 ] || bad "huge range: exit $rc: $(cat "$dir/err")"
grep -q 'Out of memory' "$dir/err" || bad "huge range: no message: $(cat "$dir/err")"
grep -q '!foo n=0 m=1' "$dir/out" || bad "huge range: tree: $(cat "$dir/out")"
printf 'let r=..(frame+10000000)\n!foo n=len(zip(r, r, r)) m=1\n' >"$dir/zip.fl"
run - run --max-memory 200M --frames 2 --dump-tree "$dir/zip.fl"
[ $rc -eq 0 ] || bad "huge zip: exit $rc: $(cat "$dir/err")"
grep -q 'zip.*out of memory' "$dir/err" || bad "huge zip: no message: $(cat "$dir/err")"
grep -q '!foo n=0 m=1' "$dir/out" || bad "huge zip: tree: $(cat "$dir/out")"
# a node tree built by a loop stops at the budget
printf '!group\n    for i in ..(frame+10000000)\n        !node x=i y=i;i\n' >"$dir/nodes.fl"
run - run --max-memory 100M --frames 1 "$dir/nodes.fl"
[ $rc -eq 0 ] || bad "huge node tree: exit $rc: $(cat "$dir/err")"
grep -q 'Out of memory' "$dir/err" || bad "huge node tree: no message: $(cat "$dir/err")"

# 3. an oversized !physics system
{
    printf '!physics state=:big dimensions=1048576\n'
    printf '    for i in ..100\n        !particle id=i position=i\n'
} >"$dir/phys.fl"
for how in ulimit budget; do
    if [ $how = ulimit ]; then run 4000000 run --frames 2 "$dir/phys.fl"
    else run - run --max-memory 1G --frames 2 "$dir/phys.fl"; fi
    [ $rc -eq 0 ] || bad "dimensions=1048576 ($how): exit $rc: $(cat "$dir/err")"
    grep -q '^Physics error: system too large for the memory budget' "$dir/err" ||
        bad "dimensions=1048576 ($how): message: $(cat "$dir/err")"
done

# 4. a ~120 MB state file: one key whose value is 60 million numbers
python3 - "$dir/big.state" <<'EOF' || exit 2
import sys
with open(sys.argv[1], 'wb') as f:
    f.write(b'flitter-state 1\nclock 0 0 0 0 0.5 4 0\n:big = ')
    f.write(b'1;' * (60_000_000 - 1) + b'1\n')
    f.write(b'end 1\n')
EOF
printf '!foo n=len($(:big))\n' >"$dir/state.fl"
cp "$dir/big.state" "$dir/keep.state"
run - run --max-memory 200M --frames 1 --state "$dir/big.state" "$dir/state.fl"
[ $rc -eq 1 ] || bad "state file past the budget: exit $rc: $(cat "$dir/err")"
grep -q 'big.state:3: error: out of memory.*state file refused' "$dir/err" ||
    bad "state file past the budget: message: $(cat "$dir/err")"
cmp -s "$dir/big.state" "$dir/keep.state" || bad "a refused state file was changed"
run 4000000 run --frames 1 --dump-tree --state "$dir/big.state" "$dir/state.fl"
[ $rc -eq 0 ] || bad "120 MB state file under ulimit -v 4000000: exit $rc: $(cat "$dir/err")"
grep -q '!foo n=60000000' "$dir/out" || bad "120 MB state file: tree: $(head -c 300 "$dir/out")"
rm -f "$dir/big.state" "$dir/keep.state"

# 5. a 26 MB script
python3 - "$dir/long.fl" <<'EOF' || exit 2
import sys
line = b'!n x=1;2;3;4;5;6;7;8;9 y=10\n'
with open(sys.argv[1], 'wb') as f:
    f.write(line * (26_000_000 // len(line)))
EOF
run 4000000 run --frames 1 "$dir/long.fl"
[ $rc -eq 1 ] || bad "26 MB script: exit $rc, not 1: $(head -c 300 "$dir/err")"
grep -q "^$dir/long.fl:1:1: error: out of memory" "$dir/err" ||
    bad "26 MB script: message: $(head -c 300 "$dir/err")"
rm -f "$dir/long.fl"

# 6. the REPL keeps its session and state
cp "$petri" "$dir/petri.fl"
printf ':step 3\nlet a=..(frame+60000000)\nlen(a;a;a)\n1+2\n:step 1\n' |
    (cd "$dir" && "$flitter" repl --max-memory 200M petri.fl) >"$dir/out" 2>&1
grep -q 'Out of memory' "$dir/out" || bad "repl: no message: $(cat "$dir/out")"
grep -qx 3 "$dir/out" || bad "repl: the session did not go on: $(cat "$dir/out")"
grep -q '^frame 3 ' "$dir/out" || bad "repl: the state was not kept: $(cat "$dir/out")"

# 7. bad values
for v in 0 -1 12X 1.5G '' 99999999999999999999G; do
    run - run --max-memory "$v" --frames 1 "$dir/range.fl"
    [ $rc -eq 2 ] || bad "--max-memory '$v': exit $rc, not 2"
done
run - run --max-memory 64k --frames 1 "$dir/range.fl"
[ $rc -eq 0 ] || bad "--max-memory 64k: exit $rc: $(cat "$dir/err")"

# 8. a budget well inside a tight ulimit -v: the 3-million-number range fits
# both (flitter run's heap prefaulting, src/prefault.h, stays off under the
# limit: its padding and larger heap blocks made this abort)
printf 'let big=..3000000\n!foo x=big[..5] n=len(big)\n' >"$dir/hog.fl"
run 70000 run --frames 2 --dump-tree --max-memory 50M "$dir/hog.fl"
[ $rc -eq 0 ] || bad "50M budget under ulimit -v 70000: exit $rc: $(head -c 300 "$dir/err")"
grep -q 'n=3000000' "$dir/out" || bad "50M budget under ulimit -v 70000: tree: $(head -c 300 "$dir/out")"
# 9. template passes past the budget
printf '!window size=100;100\n    !canvas\n        for i in ..200\n            !ellipse point=(i;5)+time\n' >"$dir/split.fl"
for k in 8K 16K 24K 32K 64K; do
    run - run --max-memory $k --frames 1 --dump-tree "$dir/split.fl"
    [ $rc -eq 0 ] || [ $rc -eq 1 ] || bad "template pass at --max-memory $k: exit $rc: $(head -c 300 "$dir/err")"
done
printf 'let N=20000\n!window size=100;100\n    !canvas\n        for i in ..N\n            !p a=len((i;..100000))\n' >"$dir/cols.fl"
run 4000000 run --frames 0 "$dir/cols.fl"
[ $rc -eq 1 ] || bad "long compositions under ulimit -v: exit $rc, not 1: $(head -c 300 "$dir/err")"
grep -q "^$dir/cols.fl:1:1: error: out of memory" "$dir/err" ||
    bad "long compositions under ulimit -v: message: $(head -c 300 "$dir/err")"
# (within ulimit -v 800000: a budget overrun to twice the budget aborts)
sed 's/N=20000/N=200/; s/100000/1000000/' "$dir/cols.fl" >"$dir/cols2.fl"
run 800000 run --frames 0 --max-memory 400M "$dir/cols2.fl"
[ $rc -eq 1 ] || bad "long compositions past 400M: exit $rc, not 1: $(head -c 300 "$dir/err")"
grep -q "^$dir/cols2.fl:1:1: error: out of memory" "$dir/err" ||
    bad "long compositions past 400M: message: $(head -c 300 "$dir/err")"
exit $fail
