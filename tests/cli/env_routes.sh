#!/bin/sh
# env_routes.sh FLITTER: the flitter command maps its FLITTER_* route
# variables onto fl_options.debug (the library reads no environment):
# FLITTER_NOPOOL=1 makes a steady frame allocate (`--stats`), and
# FLITTER_NOTEMPLATES=1 unrolls a literal loop one copy at a time
# (`--dump-simplified` shows no templated loop); unset, neither happens.
# Set to "" (NOPOOL) or "0" (NOTEMPLATES) they leave the defaults.
# FLITTER_NODRAW=1 leaves a !record's file unwritten; "0" writes it.
set -u
flitter=$1
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail=0
unset FLITTER_NOPOOL FLITTER_NOTEMPLATES FLITTER_NODRAW
printf 'for i in ..30\n    !a x=i*time\n' >"$dir/loop.fl"

steady() {   # steady ENV...: the --stats line of a 6-frame run's last frame
    env "$@" "$flitter" run --frames 6 --stats "$dir/loop.fl" 2>&1 >/dev/null |
        sed -n 's/.*last frame \([0-9]*\) mallocs.*/\1/p'
}
n=$(steady)
[ "$n" = 0 ] || { echo "pooled run: last frame made '$n' mallocs, not 0" >&2; fail=1; }
n=$(steady FLITTER_NOPOOL=1)
case $n in '' | 0) echo "FLITTER_NOPOOL=1: last frame made '$n' mallocs" >&2; fail=1 ;; esac
n=$(steady FLITTER_NOPOOL=)
[ "$n" = 0 ] || { echo "FLITTER_NOPOOL empty: last frame made '$n' mallocs, not 0" >&2; fail=1; }

templated() {   # templated ENV...: how many templated loops the program has
    env "$@" "$flitter" run --frames 1 --dump-simplified "$dir/loop.fl" 2>/dev/null | grep -c '^for ⟨t0⟩'
}
[ "$(templated)" -gt 0 ] || { echo "default: no templated loop" >&2; fail=1; }
[ "$(templated FLITTER_NOTEMPLATES=1)" = 0 ] || { echo "FLITTER_NOTEMPLATES=1: a templated loop" >&2; fail=1; }
[ "$(templated FLITTER_NOTEMPLATES=0)" -gt 0 ] || { echo "FLITTER_NOTEMPLATES=0: no templated loop" >&2; fail=1; }

printf '!window size=8\n    !record filename="rec.png"\n        !canvas\n            !rect size=8\n            !fill\n' \
    >"$dir/rec.fl"
recorded() {   # recorded ENV...: whether a 2-frame run writes rec.png
    rm -f "$dir/rec.png"
    env "$@" "$flitter" run --frames 2 "$dir/rec.fl" >/dev/null 2>&1   # written beside the script
    [ -s "$dir/rec.png" ]
}
recorded || { echo "default: rec.png not written" >&2; fail=1; }
recorded FLITTER_NODRAW=1 && { echo "FLITTER_NODRAW=1: rec.png written" >&2; fail=1; }
recorded FLITTER_NODRAW=0 || { echo "FLITTER_NODRAW=0: rec.png not written" >&2; fail=1; }

exit $fail
