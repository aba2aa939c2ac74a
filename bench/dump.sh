#!/bin/sh
# bench/dump.sh [BUILD_DIR]: the dumps: wall and user seconds and peak
# RSS, best of 3 (by wall), of
#   --dump-tokens  one line of 200,001 tokens (`!n x=1+1+...`),
#   --dump-ast     one node with 50,000 attributes on one line (issue 28
#                  item 4: each token's line and column were once counted
#                  from the start of the file, quadratic in the line's
#                  length), and
#   --dump-state   two frames of bench/discs100k.fl, whose last dump has
#                  200,001 lines of computed numbers (shortest round-trip
#                  text, sorted by key),
# the output sent to /dev/null.
# Not part of the test suite: timings vary with the machine.
set -u
build=${1:-build}
flitter="$build/src/flitter"
[ -x "$flitter" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
gen=$(mktemp -d) || exit 2
trap 'rm -rf "$gen"' EXIT
# 3 tokens (!, n, x), then = and 1, then 99,998 times + 1: 200,001 before the newline
python3 -c "import sys; open(sys.argv[1], 'w').write('!n x=' + '+'.join(['1'] * 99999) + '\n')" \
    "$gen/tokens200k.fl" || exit 2
python3 -c "import sys; open(sys.argv[1], 'w').write('!n ' + ' '.join('a%d=%d' % (i, i) for i in range(50000)) + '\n')" \
    "$gen/attrs50k.fl" || exit 2
here=$(cd "$(dirname "$0")" && pwd)
for job in tokens ast state; do
    case $job in   # (paths kept out of word splitting)
    tokens) opt=--dump-tokens file=$gen/tokens200k.fl ;;
    ast) opt=--dump-ast file=$gen/attrs50k.fl ;;
    state) opt=--dump-state file=$here/discs100k.fl ;;
    esac
    best=""
    for _ in 1 2 3; do
        if [ "$job" = state ]; then
            r=$(/usr/bin/time -f '%e %U %M' "$flitter" run --frames 2 "$opt" "$file" 2>&1 >/dev/null | tail -1)
        else
            r=$(/usr/bin/time -f '%e %U %M' "$flitter" run "$opt" "$file" 2>&1 >/dev/null | tail -1)
        fi
        w=${r%% *}
        if [ -z "$best" ] || awk -v w="$w" -v b="${best%% *}" 'BEGIN { exit !(w < b) }'; then best=$r; fi
    done
    set -- $best
    printf '%7s s wall %6s s user %8s KB  %s %s\n' "$1" "$2" "$3" "$opt" "$(basename "$file")"
done
