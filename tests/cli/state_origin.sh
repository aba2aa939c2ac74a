#!/bin/sh
# state_origin.sh FLITTER SCRIPT: a state file names the script that saved
# it and carries a checksum (lib/io/statefile.h, version 2):
#   - resuming it with another script prints a warning naming both and
#     goes on (exit 0); the same script edited since resumes silently;
#   - one changed byte of the file is refused as damaged (exit 1) and the
#     file is left as it was;
#   - a state key holding ` = ` (a !counter key string) is saved and read
#     back (it used to be refused as malformed);
#   - saving through a symbolic link replaces the file it names (the link
#     stays) and keeps its permission bits; a FIFO given as the state file
#     is refused at once (no blocking open) and stays a FIFO.
set -u
flitter=$1 script=$2
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
cp "$script" "$dir/a.fl" && cp "$script" "$dir/b.fl" && echo '-- b' >>"$dir/b.fl" || exit 2
"$flitter" run --frames 5 --state "$dir/s" "$dir/a.fl" 2>"$dir/err" || { cat "$dir/err" >&2; exit 1; }
grep -q '^script ".*/a\.fl" [0-9a-f]\{16\}$' "$dir/s" || { echo "no script line:" >&2; head -3 "$dir/s" >&2; exit 1; }
grep -q '^checksum [0-9a-f]\{16\}$' "$dir/s" || { echo "no checksum line" >&2; exit 1; }
cp "$dir/s" "$dir/s.saved"
"$flitter" run --frames 1 --state "$dir/s" "$dir/b.fl" 2>"$dir/err"
rc=$?
[ $rc -eq 0 ] || { echo "another script: exit $rc, expected 0" >&2; cat "$dir/err" >&2; exit 1; }
grep -q "warning: state saved by .*/a\.fl, resumed by .*/b\.fl" "$dir/err" ||
    { echo "no warning naming both scripts:" >&2; cat "$dir/err" >&2; exit 1; }
cp "$dir/s.saved" "$dir/s"
echo '-- edited' >>"$dir/a.fl"
"$flitter" run --frames 1 --state "$dir/s" "$dir/a.fl" 2>"$dir/err" || exit 1
grep -q "state saved by" "$dir/err" && { echo "warning for the same script, edited" >&2; exit 1; }
# one byte changed in the middle of a number
sed '3s/\([0-9]\)\([0-9]\)/\2\1/' "$dir/s.saved" >"$dir/d"
cmp -s "$dir/d" "$dir/s.saved" && { echo "the test did not change the file" >&2; exit 2; }
cp "$dir/d" "$dir/d.orig"
"$flitter" run --frames 1 --state "$dir/d" "$dir/a.fl" 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] || { echo "damaged file: exit $rc, expected 1" >&2; exit 1; }
grep -q "state file damaged" "$dir/err" || { echo "no 'damaged' message:" >&2; cat "$dir/err" >&2; exit 1; }
cmp -s "$dir/d" "$dir/d.orig" || { echo "damaged state file was changed" >&2; exit 1; }
# a key holding ` = `
printf '!counter state="a = b" rate=1\n' >"$dir/c.fl"
"$flitter" run --frames 3 --state "$dir/cs" "$dir/c.fl" 2>"$dir/err" || { cat "$dir/err" >&2; exit 1; }
grep -q '^"a = b" = ' "$dir/cs" || { echo "no counter entry:" >&2; cat "$dir/cs" >&2; exit 1; }
"$flitter" run --frames 3 --state "$dir/cs" --dump-state "$dir/c.fl" >"$dir/out" 2>"$dir/err" ||
    { echo "resuming a key with ' = ':" >&2; cat "$dir/err" >&2; exit 1; }
# through a symbolic link, keeping the mode
cp "$dir/s.saved" "$dir/target"
chmod 600 "$dir/target"
ln -s target "$dir/link"
"$flitter" run --frames 2 --state "$dir/link" "$dir/a.fl" 2>"$dir/err" || { cat "$dir/err" >&2; exit 1; }
[ -L "$dir/link" ] || { echo "the symbolic link was replaced" >&2; exit 1; }
cmp -s "$dir/target" "$dir/s.saved" && { echo "the link's target was not updated" >&2; exit 1; }
[ "$(stat -c %a "$dir/target")" = 600 ] || { echo "mode $(stat -c %a "$dir/target"), not 600" >&2; exit 1; }
ls -a "$dir" | grep -q '^\.target\.' && { echo "a temporary file was left" >&2; exit 1; }
# a FIFO: refused without blocking, before the run (an output that cannot
# be written: exit 2; it was 1 when the refusal came from the read)
mkfifo "$dir/fifo" || exit 2
timeout 10 "$flitter" run --frames 1 --state "$dir/fifo" "$dir/a.fl" 2>"$dir/err"
rc=$?
[ $rc -eq 2 ] || { echo "FIFO state file: exit $rc, expected 2" >&2; cat "$dir/err" >&2; exit 1; }
grep -q "not a regular file" "$dir/err" || { echo "FIFO: no message:" >&2; cat "$dir/err" >&2; exit 1; }
[ -p "$dir/fifo" ] || { echo "the FIFO was replaced" >&2; exit 1; }
exit 0
