#!/usr/bin/env bash
# The shared library exports only the public interface: every dynamic
# symbol it defines starts with `fl_`, and every function declared FL_API
# in flitter.h is among them.
# usage: symbols.sh LIBFLITTER.so FLITTER.h
set -uo pipefail
lib=$1 header=$2
defined=$(nm -D --defined-only "$lib" | awk 'NF == 3 {print $3}' | sort)
[ -n "$defined" ] || { echo "no dynamic symbols in $lib"; exit 1; }
bad=$(grep -v '^fl_' <<<"$defined")
if [ -n "$bad" ]; then
    echo "exported symbols outside the fl_ interface:"
    echo "$bad"
    exit 1
fi
declared=$(grep -o '^FL_API [^(]*(' "$header" | sed -E 's/.*[ *]([a-z_0-9]+)\($/\1/' | sort)
missing=$(comm -23 <(echo "$declared") <(echo "$defined"))
extra=$(comm -13 <(echo "$declared") <(echo "$defined"))
if [ -n "$missing$extra" ]; then
    [ -z "$missing" ] || { echo "declared FL_API but not exported:"; echo "$missing"; }
    [ -z "$extra" ] || { echo "exported but not declared FL_API in $header:"; echo "$extra"; }
    exit 1
fi
echo "$(wc -l <<<"$defined") symbols, all fl_ and all declared FL_API"
