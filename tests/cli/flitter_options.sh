#!/bin/sh
# flitter_options.sh FLITTER SCRIPT: Flitter 1.0.0b28's own options
# (engine/__main__.py), as a Flitter user types them (issue 23):
#   1. --trace, --debug, --verbose, --quiet are log levels taking no value:
#      `flitter --trace a.fl b.fl` runs two pages and leaves both files
#      byte for byte as they were (it replaced a.fl with a CSV); --trace
#      prints a line per frame; two different levels are refused (exit 2,
#      as Flitter's mutually exclusive group); --verbose prints the version;
#   2. the trajectory file is --trace-file FILE or --trace=FILE (with the
#      '=' only): the same CSV either way;
#   3. --runtime takes Flitter's time codes: 0:01 at --fps 5 is 5 frames,
#      0:00:00.6 is 3, 0.4 is 2; 1::2, 1:2:3:4 and -1 are refused;
#   4. --profile and --opengles are accepted with one note each; --modelcache T
#      is taken (a bad T refused)
#      each on stderr (none under --quiet); --vmstats prints --stats' lines;
#      the run's output is the same as without them;
#   5. -h and --help list the commands and then the options (Flitter's -h
#      lists its options), exit 0.
set -u
flitter=$1 script=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail=0
bad() { echo "flitter_options: $*" >&2; fail=1; }
cp "$script" "$dir/a.fl" && cp "$script" "$dir/b.fl" && cp "$script" "$dir/orig.fl" || exit 2

# 1. log levels
"$flitter" --trace "$dir/a.fl" "$dir/b.fl" --offscreen --lockstep --frames 3 >"$dir/out" 2>"$dir/err"
rc=$?
[ $rc -eq 0 ] || bad "flitter --trace a.fl b.fl: exit $rc: $(cat "$dir/err")"
cmp -s "$dir/a.fl" "$dir/orig.fl" && cmp -s "$dir/b.fl" "$dir/orig.fl" || bad "--trace a.fl b.fl changed a script"
[ "$(grep -c '^trace: frame [0-9]* time ' "$dir/err")" -eq 3 ] || bad "--trace: not 3 frame lines: $(cat "$dir/err")"
ls -A "$dir" | grep -qv '^\(a\|b\|orig\)\.fl$\|^out$\|^err$' && bad "--trace wrote a file: $(ls -A "$dir")"
"$flitter" run --frames 2 "$dir/a.fl" >/dev/null 2>"$dir/err" || bad "plain run failed"
[ -s "$dir/err" ] && bad "a plain run says something: $(cat "$dir/err")"
for pair in "--quiet --debug" "--trace --verbose" "--debug --trace"; do
    set -- $pair
    "$flitter" run --frames 1 "$@" "$dir/a.fl" >/dev/null 2>"$dir/err"
    rc=$?
    [ $rc -eq 2 ] || bad "$pair: exit $rc, not 2"
    grep -qx "flitter run: $1 and $2 are both log levels: give one" "$dir/err" || bad "$pair: $(cat "$dir/err")"
done
"$flitter" run --frames 1 --debug --debug "$dir/a.fl" >/dev/null 2>&1 || bad "--debug twice refused"
"$flitter" run --frames 1 --verbose "$dir/a.fl" >/dev/null 2>"$dir/err" || bad "--verbose failed"
grep -q '^flitter: flitter-c [0-9]' "$dir/err" || bad "--verbose: no version line: $(cat "$dir/err")"

# 2. the trajectory file
"$flitter" run --frames 3 --trace-file "$dir/t1.csv" "$dir/a.fl" || bad "--trace-file failed"
"$flitter" run --frames 3 "--trace=$dir/t2.csv" "$dir/a.fl" || bad "--trace=FILE failed"
[ "$(head -1 "$dir/t1.csv")" = "frame,time,system,id,kind,x,y,vx,vy" ] || bad "--trace-file: header $(head -1 "$dir/t1.csv")"
cmp -s "$dir/t1.csv" "$dir/t2.csv" || bad "--trace=FILE and --trace-file FILE differ"
"$flitter" run --frames 3 --trace "$dir/t3.csv" "$dir/a.fl" >/dev/null 2>"$dir/err"
[ $? -eq 2 ] && grep -q 'exactly one SCRIPT expected' "$dir/err" || bad "run --trace FILE SCRIPT: $(cat "$dir/err")"
[ -e "$dir/t3.csv" ] && bad "run --trace FILE wrote FILE"

# 3. time codes
for case in "0:01 5" "0:00:00.6 3" "0.4 2" "1:00 300"; do
    set -- $case
    "$flitter" run --fps 5 --runtime "$1" --dump-state "$dir/a.fl" >"$dir/out" 2>"$dir/err" || bad "--runtime $1 failed"
    last=$(sed -n 's/^# frame \([0-9]*\) .*/\1/p' "$dir/out" | tail -n 1)
    [ "$last" = $(($2 - 1)) ] || bad "--runtime $1 at 5 fps: last frame $last, not $(($2 - 1))"
done
for t in 1::2 1:2:3:4 -1 :5 1:x 'inf'; do
    "$flitter" run --runtime "$t" "$dir/a.fl" >/dev/null 2>"$dir/err"
    [ $? -eq 2 ] && grep -qx "flitter run: bad value '$t' for option '--runtime'" "$dir/err" || bad "--runtime $t: $(cat "$dir/err")"
done

# 4. options without effect here
"$flitter" run --frames 3 --dump-state "$dir/a.fl" >"$dir/plain" || bad "plain run failed"
"$flitter" run --profile --opengles --modelcache 5:00 --frames 3 --dump-state "$dir/a.fl" >"$dir/out" 2>"$dir/err" ||
    bad "--profile --opengles --modelcache failed: $(cat "$dir/err")"
cmp -s "$dir/plain" "$dir/out" || bad "--profile --opengles --modelcache changed the output"
[ "$(wc -l <"$dir/err")" -eq 2 ] && grep -q '^flitter: --profile has no effect' "$dir/err" &&
    grep -q '^flitter: --opengles has no effect' "$dir/err" ||
    bad "notes: $(cat "$dir/err")"
"$flitter" run --quiet --profile --frames 1 "$dir/a.fl" >/dev/null 2>"$dir/err"
[ -s "$dir/err" ] && bad "--quiet --profile: $(cat "$dir/err")"
"$flitter" run --modelcache soon --frames 1 "$dir/a.fl" >/dev/null 2>&1
[ $? -eq 2 ] || bad "--modelcache soon accepted"
"$flitter" run --modelcache -5 --frames 1 "$dir/a.fl" >/dev/null 2>&1
[ $? -eq 2 ] || bad "--modelcache -5 accepted"
"$flitter" run --vmstats --frames 2 "$dir/a.fl" >/dev/null 2>"$dir/err" || bad "--vmstats failed"
grep -q '^stats: 2 frames in ' "$dir/err" || bad "--vmstats: $(cat "$dir/err")"
# 5. -h lists the options as Flitter's does
for h in -h --help; do
    "$flitter" $h >"$dir/help" 2>"$dir/err" || bad "flitter $h: exit $?"
    grep -q '^  run    ' "$dir/help" && grep -q '^  --runtime T ' "$dir/help" &&
        grep -q '^  --offscreen ' "$dir/help" && grep -q '^  -D, --define NAME=VALUE' "$dir/help" ||
        bad "flitter $h does not list the commands and the options: $(head -3 "$dir/help")"
done
exit $fail
