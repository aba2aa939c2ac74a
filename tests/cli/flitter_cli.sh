#!/bin/sh
# flitter_cli.sh FLITTER: Flitter's own command line (`flitter [options]
# SCRIPT` as in Flitter's documentation Makefiles), --version, help, and
# --debug naming a skipped drawing node once.
set -u
flitter=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "$*" >&2; exit 1; }

"$flitter" --version >"$dir/out" || fail "--version failed"
grep -Eqx 'flitter-c [0-9]+\.[0-9]+\.[0-9]+' "$dir/out" || fail "--version printed: $(cat "$dir/out")"
"$flitter" help run >"$dir/out" || fail "help run failed"
grep -q -- '--runtime T' "$dir/out" || fail "help run lacks --runtime"
"$flitter" help bogus 2>/dev/null
[ $? -eq 2 ] || fail "help bogus should exit 2"

# --runtime=1 at --fps=4 runs round(1*4) = 4 frames: the last is frame 3,
# the one the script records (run_time is the planned run time).
cat >"$dir/fig.fl" <<'FL'
!window size=20;10
    !record filename=OUTPUT if frame == run_time*fps - 1
        !canvas
            !rect size=20;10 fill=true color=1
    !shader
    !shader
FL
(cd "$dir" && "$flitter" --offscreen --lockstep --fps=4 --runtime=1 --nosimplify \
    --define "OUTPUT=fig.png" --debug --dump-state fig.fl) >"$dir/out" 2>"$dir/err" \
    || fail "flitter fig.fl failed: $(cat "$dir/err")"
grep -qx '# frame 3 time 0.75' "$dir/out" || fail "expected 4 frames, got: $(cat "$dir/out")"
[ -f "$dir/fig.png" ] || fail "fig.png not written"
# PNG signature, then the IHDR width 20 and height 10 (big-endian)
[ "$(od -An -tx1 -j12 -N12 "$dir/fig.png" | tr -d ' \n')" = "49484452000000140000000a" ] ||
    fail "fig.png header: $(od -An -tx1 -N24 "$dir/fig.png")"
[ "$(grep -c 'skipping unsupported !shader' "$dir/err")" -eq 1 ] || fail "debug messages: $(cat "$dir/err")"
# without --debug nothing is said about it
(cd "$dir" && "$flitter" --lockstep --fps=4 --runtime=1 -D OUTPUT=fig2.png fig.fl) 2>"$dir/err" >/dev/null
[ -s "$dir/err" ] && fail "unexpected stderr: $(cat "$dir/err")"
[ -f "$dir/fig2.png" ] || fail "fig2.png not written (-D)"
exit 0
