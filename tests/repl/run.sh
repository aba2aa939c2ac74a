#!/bin/sh
# run.sh: the scripted REPL session test.
# usage: run.sh FLITTER SESSION.in SESSION.out PETRI.fl NODES.fl [STATUS]
# Builds a scratch directory holding tests/golden/petri.fl and
# tests/lang/nodes.fl (so every path the session prints, and the state file
# its :save writes, are relative and stay out of the source tree), pipes
# SESSION.in into `FLITTER repl tests/golden/petri.fl` there, and compares
# what it prints, stdout and stderr together (the REPL keeps their lines in
# order), byte for byte with SESSION.out. On a mismatch prints a unified
# diff and exits 1. The REPL must exit with STATUS (default 0; a scripted
# session that met an error exits 1).
set -u
flitter=$1 session=$2 expected=$3 petri=$4 nodes=$5 status=${6:-0}
case $flitter in /*) ;; *) flitter=$(pwd)/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
mkdir -p "$dir/tests/golden" "$dir/tests/lang" || exit 2
cp "$petri" "$dir/tests/golden/petri.fl" && cp "$nodes" "$dir/tests/lang/nodes.fl" || exit 2
(cd "$dir" && "$flitter" repl tests/golden/petri.fl) <"$session" >"$dir/out" 2>&1
rc=$?
if [ $rc -ne "$status" ]; then
    echo "flitter repl exited with status $rc, expected $status" >&2
    cat "$dir/out" >&2
    exit 1
fi
if cmp -s "$expected" "$dir/out"; then
    exit 0
fi
echo "session output differs from $expected:" >&2
diff -u "$expected" "$dir/out" | head -60 >&2
exit 1
