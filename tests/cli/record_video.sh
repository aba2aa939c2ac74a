#!/bin/sh
# record_video.sh FLITTER: `!record filename=NAME.mp4|.webm` writes videos
# (lib/render/output/video.c), checked with ffprobe and ffmpeg:
#   1. a 2-second run (--frames 120 --fps 60) of a script drawing an orange
#      rectangle whose x is (7 * frame) % 200 over blue writes an H.264 .mp4
#      and a VP9 .webm of 120 frames, 256x128, 60/1 frames/s; frame 59
#      decoded from each matches the PNG that `!record` writes in frame 59
#      (every pixel within a lossy codec's tolerance; at four places the
#      colours exact within 12 levels: those places tell frame 59 from 58
#      and 60, so the frame index is checked too);
#   2. `--record FILE.mkv` records the first window (120 frames, its size);
#   3. a run stopped by SIGINT still finishes its video (readable, frames
#      up to the stop), and no temporary file is left next to it;
#   4. (first) a !record into a directory that does not exist is reported
#      with the file name and the reason, once per file (the run's exit
#      run carries on, and exits 1 at the end, saying why: a !record that
#      could not write used to exit 0).
set -u
flitter=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
for tool in ffprobe ffmpeg python3; do
    command -v "$tool" >/dev/null 2>&1 || { echo "record_video: $tool not installed, skipped" >&2; exit 77; }
done
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "record_video: $*" >&2; exit 1; }

# a folder that cannot be made (a file is in the way): reported, run
# carries on, status 1
printf 'x\n' >"$dir/nodir"
printf '!window size=8;8\n    !record filename="nodir/a.mp4"\n        !canvas\n    !record filename="nodir/b.png"\n        !canvas\n' \
    >"$dir/nodir.fl"
(cd "$dir" && "$flitter" run --frames 3 nodir.fl) 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] || fail "nodir.fl: exit status $rc, not 1"
grep -qx 'flitter run: a !record file could not be written (the error is above)' "$dir/err" \
    || fail "nodir.fl: no closing message: $(cat "$dir/err")"
grep -qx 'nodir/a.mp4: cannot create a file in nodir: Not a directory' "$dir/err" \
    || fail "nodir/a.mp4 message: $(cat "$dir/err")"
grep -qx 'nodir/b.png: cannot create a file in nodir: Not a directory' "$dir/err" \
    || fail "nodir/b.png message: $(cat "$dir/err")"
[ "$(wc -l <"$dir/err")" -eq 3 ] || fail "each file's error once, and the closing line, got: $(cat "$dir/err")"
# Under valgrind (the suite's memcheck phase) FFmpeg cannot be loaded:
# its libhwy runs RDTSCP at load time, which valgrind 3.19 does not
# emulate (SIGILL; lib/render/media/avlib.h), and ffprobe/ffmpeg would be traced
# too. Only the part above, which fails before FFmpeg is loaded, runs.
case "${LD_PRELOAD:-}" in
*vgpreload*) echo "record_video: under valgrind FFmpeg cannot load (RDTSCP in libhwy); videos skipped" >&2; exit 77 ;;
esac

# the picture: blue, an orange 40x80 rectangle at x = (7 * frame) % 200;
# frame 59 puts it at 13..53 (58: 6..46, 60: 20..60)
cat >"$dir/move.fl" <<'FL'
let x = (frame * 7) % 200
func picture()
    !canvas
        !rect size=256;128 fill=true color=0;0;1
        !rect point=x;24 size=40;80 fill=true color=1;0.5;0
!window size=256;128
    !record filename="move.mp4"
        picture()
    !record filename="move.webm"
        picture()
    !record filename=("frame59.png" if frame == 59 else null)
        picture()
FL
(cd "$dir" && "$flitter" run --frames 120 --fps 60 move.fl) 2>"$dir/err" || fail "run failed: $(cat "$dir/err")"
[ -s "$dir/err" ] && fail "unexpected messages: $(cat "$dir/err")"
for v in move.mp4 move.webm; do
    [ -f "$dir/$v" ] || fail "$v not written"
    ffprobe -v error -count_frames -select_streams v:0 \
        -show_entries stream=codec_name,nb_read_frames,width,height,r_frame_rate -of default=nw=1 \
        "$dir/$v" >"$dir/probe" 2>&1 || fail "ffprobe $v: $(cat "$dir/probe")"
    codec=h264
    [ "$v" = move.webm ] && codec=vp9
    printf 'codec_name=%s\nwidth=256\nheight=128\nr_frame_rate=60/1\nnb_read_frames=120\n' "$codec" \
        | diff - "$dir/probe" >&2 || fail "$v: unexpected stream properties"
    ffmpeg -v error -y -i "$dir/$v" -vf 'select=eq(n\,59)' -frames:v 1 "$dir/$v.59.png" \
        || fail "$v: frame 59 not decoded"
done
# compare the decoded frames with the PNG, as raw RGB from ffmpeg
for f in frame59.png move.mp4.59.png move.webm.59.png; do
    [ -f "$dir/$f" ] || fail "$f missing"
    ffmpeg -v error -y -i "$dir/$f" -f rawvideo -pix_fmt rgb24 "$dir/$f.rgb" || fail "$f: not decoded"
done
python3 - "$dir" <<'PY' || exit 1
import sys
d = sys.argv[1]
W, H = 256, 128
ref = open(f"{d}/frame59.png.rgb", "rb").read()
assert len(ref) == W * H * 3, "frame59.png is not 256x128"
def px(buf, x, y):
    i = (y * W + x) * 3
    return tuple(buf[i:i + 3])
BLUE, ORANGE = (0, 0, 255), (255, 128, 0)
# the reference picture itself: the rectangle spans x = 13..52 in frame 59
for (x, y), want in {(10, 60): BLUE, (16, 60): ORANGE, (50, 60): ORANGE, (56, 60): BLUE,
                     (30, 10): BLUE, (30, 110): BLUE}.items():
    assert px(ref, x, y) == want, f"frame59.png at {x},{y}: {px(ref, x, y)}, not {want}"
bad = 0
for name in ("move.mp4", "move.webm"):
    got = open(f"{d}/{name}.59.png.rgb", "rb").read()
    if len(got) != len(ref):
        print(f"{name} frame 59: {len(got)} bytes, not {len(ref)}", file=sys.stderr)
        bad = 1
        continue
    # x = 9 is orange in frame 58 only, x = 17 and 50 orange in 59 (not 60
    # and 58 respectively), x = 57 orange in 60 only
    for (x, y), want in {(9, 60): BLUE, (17, 60): ORANGE, (50, 60): ORANGE, (57, 60): BLUE}.items():
        p = px(got, x, y)
        if max(abs(a - b) for a, b in zip(p, want)) > 12:
            print(f"{name} frame 59 at {x},{y}: {p}, expected {want}", file=sys.stderr)
            bad = 1
    diffs = sorted(abs(a - b) for a, b in zip(got, ref))
    mean = sum(diffs) / len(diffs)
    p99 = diffs[int(len(diffs) * 0.99)]
    if mean > 3 or p99 > 40:
        print(f"{name} frame 59 differs from frame59.png: mean {mean:.2f}, 99th percentile {p99}",
              file=sys.stderr)
        bad = 1
sys.exit(bad)
PY

# --record: the first window to a Matroska file (H.264)
cat >"$dir/plain.fl" <<'FL'
!window size=96;64
    !canvas
        !rect size=96;64 fill=true color=0;1;0
!window size=32;32
    !canvas
FL
(cd "$dir" && "$flitter" run --frames 120 --fps 60 --record rec.mkv plain.fl) 2>"$dir/err" \
    || fail "--record run failed: $(cat "$dir/err")"
ffprobe -v error -count_frames -show_entries stream=nb_read_frames,width,height -of default=nw=1 \
    "$dir/rec.mkv" >"$dir/probe" 2>&1 || fail "ffprobe rec.mkv: $(cat "$dir/probe")"
printf 'width=96\nheight=64\nnb_read_frames=120\n' | diff - "$dir/probe" >&2 || fail "rec.mkv: unexpected stream"

# SIGINT: the video is finished on the way out (fl_outputs_close)
printf '!window size=64;64\n    !record filename="int.mp4"\n        !canvas\n            !rect point=frame%%64;0 size=8;8 fill=true color=1\n' \
    >"$dir/int.fl"
(cd "$dir" && exec "$flitter" run --realtime --fps 30 int.fl) 2>"$dir/err" &
pid=$!
sleep 2
kill -INT $pid
wait $pid || fail "interrupted run: exit status $?: $(cat "$dir/err")"
n=$(ffprobe -v error -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$dir/int.mp4" 2>&1) \
    || fail "int.mp4 unreadable: $n"
[ "$n" -ge 10 ] || fail "int.mp4: only $n frames after 2 s at 30 frames/s"
leftover=$(ls -A "$dir" | grep '^\.')
[ -z "$leftover" ] || fail "temporary files left: $leftover"

# 5. an option the encoder refuses is an error, never a quiet change of
#    encoder (issue 60: crf=-5 once gave an MPEG-4 video and exit 0), and
#    a video with no frame (limit=0) is not written
printf '!window size=64;64\n    !record filename=%s crf=-5\n    !canvas\n        !rect point=0;0 size=64;64 color=1\n' \
    '"crf.mp4"' >"$dir/crf.fl"
(cd "$dir" && "$flitter" --offscreen --lockstep --frames 3 crf.fl >/dev/null 2>"$dir/err")
rc=$?
[ $rc -eq 1 ] && grep -q 'crf.mp4: .*refused the options given' "$dir/err" ||
    fail "crf=-5: exit $rc: $(cat "$dir/err")"
[ ! -e "$dir/crf.mp4" ] || fail "crf=-5 wrote $(ffprobe -v error -show_entries stream=codec_name -of csv=p=0 "$dir/crf.mp4")"
printf '!window size=64;64\n    !record filename="zero.mp4" limit=0\n    !canvas\n        !rect point=0;0 size=64;64 color=1\n' \
    >"$dir/zero.fl"
(cd "$dir" && "$flitter" --offscreen --lockstep --frames 3 zero.fl >/dev/null 2>"$dir/err")
rc=$?
[ $rc -eq 1 ] && grep -q 'zero.mp4: no frame was recorded' "$dir/err" || fail "limit=0: exit $rc: $(cat "$dir/err")"
[ ! -e "$dir/zero.mp4" ] || fail "limit=0 wrote a video"

# 6. raw video in a QuickTime file is packed RGB, which QuickTime holds
#    (yuv420p rawvideo was once written into a .mov that no player can
#    read, exit 0): 5 frames decoded, the red square red
printf '!window size=64;64\n    !record filename="raw.mov" codec=:rawvideo\n        !canvas\n            !rect point=0;0 size=32;32\n            !fill color=1;0;0\n' \
    >"$dir/raw.fl"
(cd "$dir" && "$flitter" run --frames 5 raw.fl >/dev/null 2>"$dir/err") || fail "rawvideo .mov: $(cat "$dir/err")"
n=$(ffprobe -v error -count_frames -select_streams v -show_entries stream=nb_read_frames -of csv=p=0 "$dir/raw.mov" 2>&1)
[ "$n" = 5 ] || fail "raw.mov: '$n' frames decoded, not 5"
ffmpeg -v error -y -i "$dir/raw.mov" -frames:v 1 -f rawvideo -pix_fmt rgb24 "$dir/raw.rgb" || fail "raw.mov: no frame"
px=$(od -An -tu1 -j $(( (5 * 64 + 5) * 3 )) -N3 "$dir/raw.rgb" | tr -s ' ' | sed 's/^ //')
[ "$px" = "255 0 0" ] || fail "raw.mov: pixel 5,5 is '$px', not red"
# ... and a pixfmt= QuickTime's raw video cannot hold is refused, no file
# (yuv420p was written unreadable with exit 0: the re-probe)
sed 's/codec=:rawvideo/codec=:rawvideo pixfmt=:yuv420p/; s/raw.mov/rawyuv.mov/' "$dir/raw.fl" >"$dir/rawyuv.fl"
(cd "$dir" && "$flitter" run --frames 5 rawyuv.fl >/dev/null 2>"$dir/err")
rc=$?
[ $rc -eq 1 ] && grep -q "rawyuv.mov: a QuickTime file holds raw video as" "$dir/err" ||
    fail "rawvideo pixfmt=:yuv420p .mov: exit $rc: $(cat "$dir/err")"
[ ! -e "$dir/rawyuv.mov" ] || fail "rawvideo pixfmt=:yuv420p wrote rawyuv.mov"

# 7. an animated GIF stops at limit= as a video does (it took every frame),
#    limit=0 writes none (refused, exit 1); codec=:gif under a video's name
#    is a GIF-codec video, which an MP4 cannot hold (it was a GIF file named
#    .mp4, exit 0)
for spec in 'a3.gif limit=0.05:0:3' 'a0.gif limit=0:1:' 'g.mp4:1:'; do
    name=${spec%%:*}; want_rc=${spec#*:}; want_rc=${want_rc%%:*}; frames=${spec##*:}
    file=${name%% *}
    printf '!window size=16;16\n    !record filename="%s" codec=:gif %s\n        !canvas\n            !rect point=0;0 size=8;8\n            !fill color=1;0;0\n' \
        "$file" "${name#"$file"}" >"$dir/gl.fl"
    (cd "$dir" && "$flitter" run --frames 10 gl.fl >/dev/null 2>"$dir/err")
    rc=$?
    [ $rc -eq "$want_rc" ] || fail "$name codec=:gif: exit $rc, not $want_rc: $(cat "$dir/err")"
    if [ -n "$frames" ]; then
        n=$(ffprobe -v error -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$dir/$file" 2>&1)
        [ "$n" = "$frames" ] || fail "$name: '$n' frames, not $frames"
    else
        [ ! -e "$dir/$file" ] || fail "$name: a file was written"
    fi
done
grep -q 'g.mp4: a mp4 file cannot hold gif video' "$dir/err" || fail "g.mp4 codec=:gif: $(cat "$dir/err")"

exit 0
