#!/bin/sh
# localize.sh IN.a OUT.a: the static library to install. Links every object
# of IN.a into one relocatable object (ld -r), turns the symbols compiled
# with hidden visibility into local ones (objcopy --localize-hidden), so
# only the FL_API functions stay global, and archives it as OUT.a.
set -eu
in=$1 out=$2
tmp=$out.tmp.o
${LD:-ld} -r --whole-archive "$in" -o "$tmp"
${OBJCOPY:-objcopy} --localize-hidden "$tmp"
rm -f "$out"
${AR:-ar} rcs "$out" "$tmp"
rm -f "$tmp"
