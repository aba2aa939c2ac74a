#!/bin/sh
# modules.sh FLITTER SCRIPT: the live window and the REPL are modules that
# flitter loads only when used (src/module.h): the executable links neither
# SDL2 nor libedit, a headless run loads neither, a run with a display loads
# the window module from the build tree (and SDL's own refusal then shows),
# a window module that is missing or broken (or SDL2) leaves the run
# headless with one clear message and the headless output (Flitter's
# command line says so where a display is named, silent where none is),
# and `flitter repl` runs from its module or says why it cannot.
set -u
flitter=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
script=$2
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
fail() { echo "$*" >&2; exit 1; }

# not linked: SDL2 and libedit are not among the executable's libraries
if command -v readelf >/dev/null; then
    readelf -d "$flitter" >"$dir/dyn" || fail "readelf failed"
    grep -q 'NEEDED.*libc\.so' "$dir/dyn" || fail "readelf shows no NEEDED libc: $(cat "$dir/dyn")"
    grep -q 'NEEDED.*libSDL2' "$dir/dyn" && fail "flitter links SDL2"
    grep -q 'NEEDED.*libedit' "$dir/dyn" && fail "flitter links libedit"
fi

# the reference: headless, 3 frames of the script's state
env -u DISPLAY -u WAYLAND_DISPLAY "$flitter" run --frames 3 --dump-state "$script" \
    >"$dir/headless" 2>"$dir/err" || fail "headless run failed: $(cat "$dir/err")"
[ -s "$dir/headless" ] || fail "headless run printed no state"

# not loaded: neither a headless run nor Flitter's command line without a
# display opens SDL2 (the dynamic loader's own record of the files it opens)
LD_DEBUG=files env -u DISPLAY -u WAYLAND_DISPLAY "$flitter" --frames 1 "$script" \
    >/dev/null 2>"$dir/ld" || fail "flitter SCRIPT without a display failed"
grep -q 'file=libc\.so' "$dir/ld" || fail "LD_DEBUG=files shows no libc: $(head -5 "$dir/ld")"
grep -q 'SDL2\|libedit\|flitter-window\|flitter-repl' "$dir/ld" &&
    fail "a run without a display loaded a module, SDL2 or libedit: $(grep 'SDL2\|edit\|flitter-' "$dir/ld" | head -3)"

# run ARGS... with a display named but an SDL video driver that does not
# exist, so SDL (in the module) refuses to start: $dir/out, $dir/err
window_run() {
    DISPLAY=:h4none SDL_VIDEODRIVER=nodriver "$@" "$flitter" run --window --frames 3 \
        --dump-state "$script" >"$dir/out" 2>"$dir/err"
    [ $? -eq 0 ] || fail "run --window ($*) failed: $(cat "$dir/err")"
    cmp -s "$dir/out" "$dir/headless" || fail "run --window ($*) differs from headless"
    # its message: one line (a sanitizer's report of suppressions may follow)
    grep '^flitter: ' "$dir/err" >"$dir/msg"
    [ "$(wc -l <"$dir/msg")" -eq 1 ] || fail "run --window ($*): not one message: $(cat "$dir/err")"
}

# the module found beside the executable (the build tree) and loaded: the
# reason it gives is SDL's
window_run env
[ "$(cat "$dir/msg")" = 'flitter: cannot open the display: nodriver not available: running headless' ] ||
    fail "the module was not loaded from the build tree: $(cat "$dir/err")"

# no module where FLITTER_WINDOW_MODULE says
window_run env FLITTER_WINDOW_MODULE="$dir/none.so"
[ "$(cat "$dir/msg")" = "flitter: no window module $dir/none.so (FLITTER_WINDOW_MODULE): running headless" ] ||
    fail "missing module: $(cat "$dir/err")"

# a module that cannot be loaded
printf 'not an ELF file\n' >"$dir/broken.so"
window_run env FLITTER_WINDOW_MODULE="$dir/broken.so"
case $(cat "$dir/msg") in
"flitter: cannot load the window module: $dir/broken.so: "*": running headless") ;;
*) fail "broken module: $(cat "$dir/err")" ;;
esac

# the module found, but SDL2 cannot be loaded (an unloadable libSDL2 first
# on the library path)
mkdir "$dir/lib" && printf 'not an ELF file\n' >"$dir/lib/libSDL2-2.0.so.0"
window_run env LD_LIBRARY_PATH="$dir/lib"
case $(cat "$dir/msg") in
"flitter: cannot load the window module: "*"libSDL2-2.0.so.0"*": running headless") ;;
*) fail "no SDL2: $(cat "$dir/err")" ;;
esac

# Flitter's command line (a window implied, stderr not a terminal): silent
# without a display, but where one is named and the window cannot open it
# says why (else the run would go on unseen); --quiet silences that
# (--lockstep: its own clock is the wall's, which a slow run under
# valgrind would let show in the state)
env -u DISPLAY -u WAYLAND_DISPLAY "$flitter" --lockstep --frames 3 --dump-state "$script" >"$dir/out" 2>"$dir/err" ||
    fail "flitter SCRIPT without a display failed: $(cat "$dir/err")"
cmp -s "$dir/out" "$dir/headless" || fail "flitter SCRIPT without a display differs from headless"
grep -q 'running headless' "$dir/err" && fail "flitter SCRIPT without a display spoke: $(cat "$dir/err")"
DISPLAY=:h4none SDL_VIDEODRIVER=nodriver "$flitter" --lockstep --frames 3 --dump-state "$script" >"$dir/out" 2>"$dir/err" ||
    fail "flitter SCRIPT with a display that refuses failed: $(cat "$dir/err")"
cmp -s "$dir/out" "$dir/headless" || fail "flitter SCRIPT with a display that refuses differs from headless"
[ "$(grep '^flitter: ' "$dir/err")" = 'flitter: cannot open the display: nodriver not available: running headless' ] ||
    fail "flitter SCRIPT with a display that refuses: $(cat "$dir/err")"
DISPLAY=:h4none SDL_VIDEODRIVER=nodriver "$flitter" --quiet --lockstep --frames 3 --dump-state "$script" >"$dir/out" 2>"$dir/err" ||
    fail "flitter --quiet SCRIPT failed: $(cat "$dir/err")"
grep -q 'running headless' "$dir/err" && fail "flitter --quiet SCRIPT spoke: $(cat "$dir/err")"

# the REPL's :window says why when the module is missing, and goes on
printf ':window\n:step\n' | DISPLAY=:h4none FLITTER_WINDOW_MODULE="$dir/none.so" \
    "$flitter" repl "$script" >"$dir/out" 2>"$dir/err"
grep -q "no window: no window module $dir/none.so (FLITTER_WINDOW_MODULE)" "$dir/out" "$dir/err" ||
    fail "repl :window without a module: $(cat "$dir/out" "$dir/err")"
grep -q '^frame 0 ' "$dir/out" || fail "repl did not step after :window failed: $(cat "$dir/out")"

# the REPL from its module (beside the executable), and without it
printf ':step\n' | "$flitter" repl "$script" >"$dir/out" 2>"$dir/err" ||
    fail "repl failed: $(cat "$dir/err")"
grep -q '^frame 0 ' "$dir/out" || fail "repl did not step: $(cat "$dir/out" "$dir/err")"
printf ':step\n' | FLITTER_REPL_MODULE="$dir/none.so" "$flitter" repl "$script" >"$dir/out" 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] || fail "repl without its module exited $rc"
[ ! -s "$dir/out" ] || fail "repl without its module printed: $(cat "$dir/out")"
[ "$(cat "$dir/err")" = "flitter: no REPL module $dir/none.so (FLITTER_REPL_MODULE)" ] ||
    fail "repl without its module: $(cat "$dir/err")"
exit 0
