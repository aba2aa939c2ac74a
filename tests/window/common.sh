# common.sh: sourced by the tests/window/*.sh tests (`. common.sh FLITTER`
# from the test's own directory is not needed: each test sources it by
# path). The test re-runs itself under a private Xvfb server
# (`xvfb-run -a`, a 1280x1024 screen), bounded by a hard timeout, and is
# skipped (77) only when xvfb-run is missing. Helpers find the window by
# its title, take screenshots (ImageMagick `import -window root`) and read
# pixels; the screenshots are kept under $SHOTS (/tmp/window-shots).
set -u
if [ -z "${FLITTER_WINDOW_TEST_INNER:-}" ]; then
    command -v xvfb-run >/dev/null 2>&1 || { echo "skipped: xvfb-run is missing"; exit 77; }
    for tool in xdotool xwd import convert python3; do
        command -v $tool >/dev/null 2>&1 || { echo "FAIL: $tool is missing" >&2; exit 1; }
    done
    FLITTER_WINDOW_TEST_INNER=1 exec timeout -k 5 "${WINDOW_TEST_TIMEOUT:-40}" \
        xvfb-run -a -s "-screen 0 1280x1024x24" sh "$0" "$@"
fi
here=$(cd "$(dirname "$0")" && pwd)
flitter=$1
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
SHOTS=${SHOTS:-/tmp/window-shots}
mkdir -p "$SHOTS"
dir=$(mktemp -d)
pids=""
cleanup() {
    for p in $pids; do kill "$p" 2>/dev/null; done
    rm -rf "$dir"
}
trap cleanup EXIT
cd "$dir" || exit 1

fail() { echo "FAIL: $*" >&2; [ -f "$dir/err" ] && sed 's/^/  stderr: /' "$dir/err" >&2; exit 1; }

# wait_window TITLE: wait (10 s at most) for a window called TITLE; sets
# WID and its geometry X Y WIDTH HEIGHT, and gives it the keyboard focus.
wait_window() {
    WID=$(timeout 10 xdotool search --sync --onlyvisible --name "^$1\$" 2>/dev/null | head -n 1)
    [ -n "$WID" ] || fail "no window called '$1'"
    eval "$(xdotool getwindowgeometry --shell "$WID")"
    xdotool windowfocus --sync "$WID" 2>/dev/null || xdotool windowfocus "$WID"
}

# shot NAME: screenshot of the whole screen to $SHOTS/NAME.png, and of
# the window (X Y WIDTH HEIGHT) to $SHOTS/NAME-window.png.
shot() {
    import -window root "$SHOTS/$1.png" || fail "import failed"
    convert "$SHOTS/$1.png" -crop "${WIDTH}x${HEIGHT}+${X}+${Y}" +repage "$SHOTS/$1-window.png"
}

# pixel FILE X Y: "R,G,B" (0..255) of a pixel of FILE.
pixel() {
    convert "$1" -format "%[fx:round(255*p{$2,$3}.r)],%[fx:round(255*p{$2,$3}.g)],%[fx:round(255*p{$2,$3}.b)]" info:
}

# screen_pixel X Y: "R,G,B" of a pixel of the window WID (relative to its
# top left) as the X server shows it now.
screen_pixel() { python3 "$here/xpixel.py" "$WID" "$1" "$2" || fail "xwd failed"; }

# elapsed START: seconds since START (a `date +%s.%N` value).
elapsed() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }'; }
# over T LIMIT: true when T > LIMIT.
over() { awk -v t="$1" -v l="$2" 'BEGIN { exit !(t > l) }'; }

# wait_pixel X Y RGB SECONDS: wait until the window's pixel X,Y is RGB;
# sets TOOK to the seconds it took (fails after SECONDS).
wait_pixel() {
    TOOK=$(python3 "$here/xpixel.py" "$WID" "$1" "$2" "$3" "$4") ||
        fail "pixel $1,$2 is $TOOK, not $3, after $4 s"
}

# wait_exit PID SECONDS: wait for the run to end; sets RC and TOOK (the
# seconds it took); fails when it is still running after SECONDS.
wait_exit() {
    start=$(date +%s.%N)
    while kill -0 "$1" 2>/dev/null; do
        over "$(elapsed "$start")" "$2" && fail "still running after $2 s"
        sleep 0.02
    done
    wait "$1"
    RC=$?
    TOOK=$(elapsed "$start")
}
