#!/bin/sh
# options_anywhere.sh FLITTER SCRIPT: Flitter's habits on the command line
# (issue 23, in part):
#   - options come before or after the SCRIPT, in `flitter run` and in
#     Flitter's own `flitter [options] SCRIPT` (headless here: --offscreen);
#   - an output option naming a script (`--trace-file a.fl b.fl`,
#     `--trace=x.fl`, `--view a.fl`) is refused with exit 2 and a message,
#     and both files stay byte for byte as they were (`flitter --trace a.fl
#     b.fl`, where --trace is Flitter's log level, is in flitter_options.sh:
#     it runs two pages since --trace took no file).
set -u
flitter=$1 script=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
"$flitter" run --frames 5 --dump-state "$script" >"$dir/before" || fail "options first"
"$flitter" run "$script" --frames 5 --dump-state >"$dir/after" || fail "options after the script"
cmp -s "$dir/before" "$dir/after" || fail "options after the script give another dump"
"$flitter" run --frames 2 "$script" --dump-state --frames 5 >"$dir/mixed" || fail "options on both sides"
cmp -s "$dir/before" "$dir/mixed" || fail "options on both sides give another dump"
"$flitter" "$script" --offscreen --lockstep --frames 5 --dump-state >"$dir/flitter" || fail "flitter SCRIPT OPTIONS"
cmp -s "$dir/before" "$dir/flitter" || fail "flitter SCRIPT OPTIONS gives another dump"
cp "$script" "$dir/a.fl" && cp "$script" "$dir/b.fl" || exit 2
cp "$dir/a.fl" "$dir/a.orig"
for args in "--trace-file $dir/a.fl $dir/b.fl" "run --view $dir/a.fl $dir/b.fl" \
            "run --frames 1 --record $dir/b.fl $dir/b.fl" "run --frames 1 --trace=$dir/x.fl $dir/a.fl"; do
    # shellcheck disable=SC2086
    "$flitter" $args >/dev/null 2>"$dir/err"
    rc=$?
    [ $rc -eq 2 ] || fail "$args: exit $rc, expected 2"
    grep -q "would write over a Flitter script; refused" "$dir/err" || fail "$args: no message: $(cat "$dir/err")"
    cmp -s "$dir/a.fl" "$dir/a.orig" && cmp -s "$dir/b.fl" "$dir/a.orig" || fail "$args: a script was changed"
    [ ! -e "$dir/x.fl" ] || fail "$args: created x.fl"
done
exit 0
