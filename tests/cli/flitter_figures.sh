#!/bin/sh
# flitter_figures.sh FLITTER: Flitter's own command line (`flitter
# [options] SCRIPT` as in Flitter's documentation Makefiles) drawing a
# figure: --runtime frames, --define OUTPUT, the !record PNG written; a
# skipped drawing node named once, with or without --debug; a !record name
# of no kind we write refused (exit 1); a JPEG written. The pictures are
# drawn by the OpenGL render graph (suite gl).
set -u
flitter=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "$*" >&2; exit 1; }

# --runtime=1 at --fps=4 runs round(1*4) = 4 frames: the last is frame 3,
# the one the script records (run_time is the planned run time).
cat >"$dir/fig.fl" <<'FL'
!window size=20;10
    !record filename=OUTPUT if frame == run_time*fps - 1
        !canvas
            !rect size=20;10 fill=true color=1
    !gizmo
    !gizmo
FL
(cd "$dir" && "$flitter" --offscreen --lockstep --fps=4 --runtime=1 --nosimplify \
    --define "OUTPUT=fig.png" --debug --dump-state fig.fl) >"$dir/out" 2>"$dir/err" \
    || fail "flitter fig.fl failed: $(cat "$dir/err")"
grep -qx '# frame 3 time 0.75' "$dir/out" || fail "expected 4 frames, got: $(cat "$dir/out")"
[ -f "$dir/fig.png" ] || fail "fig.png not written"
# PNG signature, then the IHDR width 20 and height 10 (big-endian)
[ "$(od -An -tx1 -j12 -N12 "$dir/fig.png" | tr -d ' \n')" = "49484452000000140000000a" ] ||
    fail "fig.png header: $(od -An -tx1 -N24 "$dir/fig.png")"
[ "$(grep -c 'skipping unsupported !gizmo' "$dir/err")" -eq 1 ] || fail "debug messages: $(cat "$dir/err")"
# without --debug it is said all the same, once: a picture missing a part
# never comes silently (issue 25); run without a display (one named but
# unusable would add its own notice, cli/modules)
(cd "$dir" && env -u DISPLAY -u WAYLAND_DISPLAY "$flitter" --lockstep --fps=4 --runtime=1 -D OUTPUT=fig2.png fig.fl) \
    2>"$dir/err" >/dev/null
[ "$(cat "$dir/err")" = "window: skipping unsupported !gizmo" ] || fail "stderr without --debug: $(cat "$dir/err")"
[ -f "$dir/fig2.png" ] || fail "fig2.png not written (-D)"

# a !record name of no kind we write is reported once, not written, and
# the run exits 1 (it exited 0 with the picture missing)
printf '!window size=8;8\n    !record filename="fig.tiff"\n        !canvas\n' >"$dir/tiff.fl"
(cd "$dir" && "$flitter" run --frames 3 tiff.fl) 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] || fail "tiff.fl: exit status $rc (1 expected)"
grep -qx 'flitter run: a !record file could not be written (the error is above)' "$dir/err" \
    || fail "tiff.fl: no closing message: $(cat "$dir/err")"
[ "$(grep -c 'fig.tiff: only .png, .jpg and .gif pictures and .gif animations are written' "$dir/err")" -eq 1 ] \
    || fail "fig.tiff: $(cat "$dir/err")"
[ -e "$dir/fig.tiff" ] && fail "fig.tiff was written"
# a .jpg is a JPEG, replaced each frame (its SOI marker and JFIF/8-bit frame)
printf '!window size=8;8\n    !record filename="fig.jpg" quality=90\n        !canvas\n            !rect size=8;8\n            !fill color=1;0;0\n' >"$dir/jpg.fl"
(cd "$dir" && "$flitter" run --frames 3 jpg.fl) 2>"$dir/err" || fail "jpg.fl: $(cat "$dir/err")"
[ "$(od -An -tx1 -N3 "$dir/fig.jpg" | tr -d ' ')" = ffd8ff ] || fail "fig.jpg header: $(od -An -tx1 -N4 "$dir/fig.jpg")"
ls "$dir" | grep -q '^fig.jpg.' && fail "a temporary file was left: $(ls "$dir")"

exit 0
