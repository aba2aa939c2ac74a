#!/bin/sh
# clock.sh FLITTER: a live run follows the wall clock as Flitter's does
# (issue 59): a window whose frames take longer than 1/fps to evaluate
# (about 7 a second here, at --fps 30), run by Flitter's command line with
# --runtime 4, ends after about 4 s of wall clock (not after 120 frames),
# and its !record video, whose frames are stamped with their time, lasts
# about 4 s too (ffprobe); so does the same run --offscreen, which is
# realtime unless --lockstep. In lockstep --runtime 1 is 30 frames, all recorded.
. "$(dirname "$0")/common.sh"
command -v ffprobe >/dev/null 2>&1 || { echo "skipped: ffprobe is missing"; exit 77; }
cat >slow.fl <<'FL'
let n = 2000000
    s = sum(sin(i/n + time) for i in ..n)
!window size=160;120 title="clock test"
    !record filename=OUT
    !canvas
        !path
            !rect point=0;0 size=160;120
            !fill color=(s/n+1)/2;0;0
FL
# within(VALUE LOW HIGH): LOW <= VALUE <= HIGH
within() { awk -v v="$1" -v a="$2" -v b="$3" 'BEGIN { exit !(v >= a && v <= b) }'; }
for mode in window offscreen; do
    extra=""; [ $mode = offscreen ] && extra=--offscreen
    start=$(date +%s.%N)
    "$flitter" $extra --runtime 4 --fps 30 --stats -D OUT=$mode.mp4 slow.fl >out 2>err || fail "$mode: exit $?"
    took=$(elapsed "$start")
    frames=$(sed -n 's/^stats: \([0-9]*\) frames in .*/\1/p' err)
    echo "$mode: $frames frames in $took s of wall clock"
    [ -n "$frames" ] && [ "$frames" -lt 100 ] || fail "$mode: $frames frames: the frames were not slow enough to tell"
    within "$took" 3.5 7 || fail "$mode: --runtime 4 ran $took s"
    dur=$(ffprobe -v error -show_entries format=duration -of default=nw=1:nk=1 $mode.mp4) ||
        fail "$mode: ffprobe $mode.mp4"
    echo "$mode: the video lasts $dur s"
    within "$dur" 3 5 || fail "$mode: the video lasts $dur s, not 4 +- 1"
done
# lockstep: --runtime 1 at 30 fps is 30 frames, and so is the video
"$flitter" --offscreen --lockstep --runtime 1 --fps 30 --stats -D OUT=lock.mp4 slow.fl >out 2>err ||
    fail "lockstep: exit $?"
grep -q '^stats: 30 frames in ' err || fail "lockstep: $(grep 'frames in' err)"
[ "$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames \
      -of default=nw=1:nk=1 lock.mp4)" = 30 ] || fail "lockstep: the video has not 30 frames"
echo "ok: realtime runs end on the clock and their videos last as long"
