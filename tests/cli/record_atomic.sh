#!/bin/sh
# record_atomic.sh FLITTER: a reader never sees a half-written !record file
# (lib/io/outfile.c: a temporary in the same directory renamed over the
# target).
#   1. a script rewrites a 320x320 PNG of 1,024 random squares (several
#      kilobytes; libpng writes each chunk's length, data and CRC in
#      separate calls) every frame for 400 frames while a
#      reader reads it in a loop: every read is a whole PNG (signature, each
#      chunk's CRC, IEND last and nothing after); the same reader run on a
#      file rewritten in place finds partial reads, so the check can fail;
#   2. the animated GIF of the same run is absent while it runs and
#      complete (trailer byte 0x3B) at the end;
#   3. a target that is a symbolic link is written through (the link stays
#      a link; the file it names is the PNG); a FIFO and a directory named
#      like a PNG are refused with a message, and left as they were;
#   4. a file that is not a picture of the kind written (a text file named
#      by `codec=:gif`, text in a .png, a script named as a video) is left
#      byte for byte as it was, with a message; a PNG over a PNG is fine;
#   5. a !record into a folder that cannot be made (a file of that name is
#      in the way): the run goes on to its last frame (--dump-state
#      printed), then exits 1 saying so; a missing folder is made, as
#      Flitter makes it.
set -u
flitter=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
command -v python3 >/dev/null 2>&1 || { echo "record_atomic: python3 not installed, skipped" >&2; exit 77; }
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "record_atomic: $*" >&2; exit 1; }

# the reader: read FILE until the file DONE exists (or, with tSECONDS
# instead, for that long); print "whole partial" counts
cat >"$dir/reader.py" <<'PY'
import os, struct, sys, time, zlib
path, until = sys.argv[1], sys.argv[2]
def whole(b):
    if not b.startswith(b"\x89PNG\r\n\x1a\n"):
        return False
    i = 8
    while i + 12 <= len(b):
        n, kind = struct.unpack(">I4s", b[i:i + 8])
        end = i + 12 + n
        if end > len(b) or zlib.crc32(b[i + 4:end - 4]) != struct.unpack(">I", b[end - 4:end])[0]:
            return False
        if kind == b"IEND":
            return end == len(b)
        i = end
    return False
good = bad = 0
stop = time.time() + float(until[1:]) if until.startswith("t") else None
def running():
    return time.time() < stop if stop is not None else not os.path.exists(until)
while running():
    try:
        with open(path, "rb") as f:
            b = f.read()
    except FileNotFoundError:
        continue
    if whole(b):
        good += 1
    else:
        bad += 1
print(good, bad)
PY

cat >"$dir/squares.fl" <<'FL'
let r = uniform(frame)
!window size=320;320
    !record filename="live.png"
        !canvas
            for i in ..1024
                !rect point=(i % 32) * 10;(i // 32) * 10 size=10;10 fill=true color=r[i*3];r[i*3+1];r[i*3+2]
    !record filename="anim.gif" codec=:gif
        !canvas
            !rect point=frame % 300;0 size=20;20 fill=true color=1
FL
(cd "$dir" && "$flitter" run --frames 400 squares.fl 2>err; echo $? >status) &
pid=$!
# wait for the first picture, then read until the run ends
waited=0
until [ -f "$dir/live.png" ] || [ -f "$dir/status" ] || [ $waited -ge 300 ]; do
    sleep 0.1
    waited=$((waited + 1))
done
[ -f "$dir/anim.gif" ] && [ ! -f "$dir/status" ] && fail "anim.gif is visible while the run writes it"
read good bad <<EOF
$(python3 "$dir/reader.py" "$dir/live.png" "$dir/status")
EOF
wait $pid
[ "$(cat "$dir/status")" = 0 ] || fail "squares.fl: exit status $(cat "$dir/status"): $(cat "$dir/err")"
[ -s "$dir/err" ] && fail "unexpected messages: $(cat "$dir/err")"
[ "$bad" -eq 0 ] || fail "$bad of $((good + bad)) reads of live.png were partial"
echo "live.png: $good whole reads during the run"
[ "$good" -ge 20 ] || fail "only $good reads of live.png during the run (too few to tell)"
size=$(wc -c <"$dir/live.png")
[ "$size" -ge 4096 ] || fail "live.png is only $size bytes (meant to take many writes)"
[ "$(tail -c 1 "$dir/anim.gif" | od -An -tx1 | tr -d ' ')" = 3b ] || fail "anim.gif has no trailer"
[ "$(head -c 6 "$dir/anim.gif")" = GIF89a ] || fail "anim.gif is not a GIF89a"
[ -z "$(ls -A "$dir" | grep '^\.')" ] || fail "temporary files left: $(ls -A "$dir" | grep '^\.')"

# the control: the same reader against a file rewritten in place
cp "$dir/live.png" "$dir/src.png"
python3 - "$dir/src.png" "$dir/inplace.png" <<'PY' &
import sys, time
data = open(sys.argv[1], "rb").read()
stop = time.time() + 3
while time.time() < stop:
    with open(sys.argv[2], "wb") as f:
        for k in range(0, len(data), 4096):
            f.write(data[k:k + 4096])
            f.flush()
PY
writer=$!
read good bad <<EOF
$(python3 "$dir/reader.py" "$dir/inplace.png" t2.5)
EOF
wait $writer
echo "control, rewritten in place: $bad partial reads of $((good + bad))"
[ "$bad" -gt 0 ] || fail "the reader found no partial read of a file rewritten in place ($good whole)"

# links, FIFOs, directories
mkdir "$dir/real" "$dir/dir.png"
ln -s real/target.png "$dir/link.png"
mkfifo "$dir/fifo.png"
printf '!window size=16;8\n    !record filename="link.png"\n        !canvas\n            !rect size=16;8 fill=true color=1;0;0\n    !record filename="fifo.png"\n        !canvas\n    !record filename="dir.png"\n        !canvas\n' \
    >"$dir/links.fl"
# (the FIFO and the directory are refused: the run exits 1 at the end)
(cd "$dir" && "$flitter" run --frames 2 links.fl) 2>"$dir/err"
[ $? -eq 1 ] || fail "links.fl: exit status not 1: $(cat "$dir/err")"
[ -L "$dir/link.png" ] || fail "link.png is no longer a symbolic link"
[ "$(od -An -tx1 -j12 -N12 "$dir/real/target.png" | tr -d ' \n')" = "494844520000001000000008" ] ||
    fail "real/target.png is not the 16x8 PNG"
grep -qx 'fifo.png: not a regular file (a FIFO); not replaced' "$dir/err" || fail "fifo.png: $(cat "$dir/err")"
grep -qx 'dir.png: not a regular file (a directory); not replaced' "$dir/err" || fail "dir.png: $(cat "$dir/err")"
[ -p "$dir/fifo.png" ] && [ -d "$dir/dir.png" ] || fail "the FIFO or the directory was replaced"
[ -z "$(ls -A "$dir/real" | grep '^\.')" ] || fail "temporary files left in real/"

# files of another kind
printf 'my notes\n' >"$dir/notes.txt"
printf 'text\n' >"$dir/text.png"
printf '!window\n' >"$dir/clip.mp4"
for f in notes.txt text.png clip.mp4; do cp "$dir/$f" "$dir/$f.orig"; done
printf '!window size=8;8\n    !record filename="notes.txt" codec=:gif\n        !canvas\n    !record filename="text.png"\n        !canvas\n    !record filename="clip.mp4"\n        !canvas\n    !record filename="good.png"\n        !canvas\n' \
    >"$dir/kinds.fl"
# (each run refuses three files, so exits 1 at the end: it was 0)
for run in 1 2; do
    (cd "$dir" && "$flitter" run --frames 2 kinds.fl) 2>>"$dir/err"
    [ $? -eq 1 ] || fail "kinds.fl run $run: exit status not 1: $(cat "$dir/err")"
done
for f in notes.txt text.png clip.mp4; do
    cmp -s "$dir/$f" "$dir/$f.orig" || fail "$f was replaced"
done
# (codec=:gif makes an animation of a .gif name only, as in Flitter: a
# text file's name is no picture's, refused by name)
grep -q '^notes.txt: only .png, .jpg and .gif pictures' "$dir/err" || fail "notes.txt: $(cat "$dir/err")"
grep -q '^text.png: exists and is not a PNG picture; not replaced' "$dir/err" || fail "text.png: $(cat "$dir/err")"
grep -q '^clip.mp4: exists and is not a video; not replaced' "$dir/err" || fail "clip.mp4: $(cat "$dir/err")"
grep -q 'good.png' "$dir/err" && fail "good.png (a PNG over our own PNG) was refused: $(cat "$dir/err")"
[ "$(od -An -tx1 -N4 "$dir/good.png" | tr -d ' \n')" = "89504e47" ] || fail "good.png is not a PNG"

printf 'not a folder\n' >"$dir/none"
printf '!window size=8;8\n    !record filename="none/a.png"\n        !canvas\n' >"$dir/rec.fl"
(cd "$dir" && "$flitter" run --frames 3 --dump-state rec.fl) >"$dir/rec.out" 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] || fail "!record into a folder that is a file: exit $rc, not 1"
grep -q '^# frame 2 ' "$dir/rec.out" || fail "!record: the run did not reach frame 2"
grep -qx 'none/a.png: cannot create a file in none: Not a directory' "$dir/err" ||
    fail "!record: no message for the file: $(cat "$dir/err")"
tail -n 1 "$dir/err" | grep -qx 'flitter run: a !record file could not be written (the error is above)' ||
    fail "!record: no closing message: $(cat "$dir/err")"
[ "$(cat "$dir/none")" = "not a folder" ] || fail "!record: the file in the way was changed"
printf '!window size=8;8\n    !record filename="made/deeper/a.png"\n        !canvas\n' >"$dir/mk.fl"
(cd "$dir" && "$flitter" run --frames 1 mk.fl) 2>"$dir/err" || fail "!record into missing folders: $(cat "$dir/err")"
[ -f "$dir/made/deeper/a.png" ] || fail "!record: missing folders not made"
exit 0
