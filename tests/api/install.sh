#!/usr/bin/env bash
# `meson install` into a staging tree, then build samples/embed/embed.c
# against the installed library through pkg-config only and run it on the
# petri dish: its output must equal tests/api/embed_petri.out exactly (the
# position is the one in samples/petri.state after 120 frames).
# Also checks the installed files: the flitter binary and its window and
# REPL modules (which it must find and load), libflitter.so
# with its soname, libflitter.a, flitter.h, libflitter.pc and flitter(1); then
# builds the sample again against libflitter.a alone (static), which must
# define no global symbol but the fl_ functions.
# usage: install.sh BUILD_DIR SOURCE_ROOT VERSION CC [CFLAGS...]
set -euo pipefail
build=$1 src=$2 version=$3 cc=$4
shift 4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
root=$tmp/root
fail() { echo "install: $*"; exit 1; }

meson install -C "$build" --no-rebuild --destdir "$root" >"$tmp/install.log" 2>&1 ||
    { cat "$tmp/install.log"; fail "meson install failed"; }

# where things went (prefix and libdir as configured)
find_one() { find "$root" -name "$1" -print -quit; }
bin=$(find "$root" -type f -name flitter -print -quit)   # not LIBDIR/flitter/
pc=$(find_one libflitter.pc)
so=$(find_one libflitter.so)
[ -n "$bin" ] && [ -x "$bin" ] || fail "no flitter binary installed"
[ -n "$pc" ] || fail "no libflitter.pc installed"
[ -n "$so" ] || fail "no libflitter.so installed"
libdir=$(dirname "$so")
[ -f "$libdir/libflitter.a" ] || fail "no libflitter.a beside libflitter.so"
[ -f "$libdir/libflitter.so.$version" ] || fail "no libflitter.so.$version"
soname=$(readelf -d "$so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
[ "$soname" = "libflitter.so.${version%%.*}" ] || fail "soname is '$soname'"
[ -n "$(find_one flitter.h)" ] || fail "no flitter.h installed"
man=$(find_one flitter.1)
[ -n "$man" ] && [ "$(basename "$(dirname "$man")")" = man1 ] || fail "no man1/flitter.1 installed"
"$bin" --version | grep -q "$version" || fail "installed flitter --version"
# the window and REPL modules (src/module.h) in LIBDIR/flitter, which the
# installed flitter finds from where it is (here the staging tree) and
# loads when asked for a window (SDL's own refusal of a video driver that
# does not exist shows that it did) or a REPL
[ -f "$libdir/flitter/flitter-window.so" ] || fail "no flitter/flitter-window.so in $libdir"
[ -f "$libdir/flitter/flitter-repl.so" ] || fail "no flitter/flitter-repl.so in $libdir"
printf ':step\n' | "$bin" repl "$src/samples/petri.fl" >"$tmp/repl.out" 2>&1 ||
    fail "installed flitter repl: $(cat "$tmp/repl.out")"
grep -q '^frame 0 ' "$tmp/repl.out" || fail "installed flitter repl did not step: $(cat "$tmp/repl.out")"
DISPLAY=:none SDL_VIDEODRIVER=nodriver "$bin" run --window --frames 1 "$src/samples/petri.fl" \
    >/dev/null 2>"$tmp/window.err" || fail "installed flitter run --window: $(cat "$tmp/window.err")"
# its message alone (a sanitizer's report of the suppressions it used may follow)
[ "$(grep '^flitter: ' "$tmp/window.err")" = 'flitter: cannot open the display: nodriver not available: running headless' ] ||
    fail "the installed flitter did not load its window module: $(cat "$tmp/window.err")"

# the sample, through pkg-config against the staging tree
export PKG_CONFIG_PATH=$(dirname "$pc") PKG_CONFIG_SYSROOT_DIR=$root
flags=$(pkg-config --cflags libflitter)
libs=$(pkg-config --libs libflitter)
case " $flags " in *" -I$root"*) ;; *) fail "pkg-config --cflags: $flags" ;; esac
# shellcheck disable=SC2086
$cc -std=c17 -Wall -Wextra -Wpedantic -Werror "$@" $flags -o "$tmp/embed" \
    "$src/samples/embed/embed.c" $libs || fail "cannot build samples/embed against the installed library"
readelf -d "$tmp/embed" | grep -q 'Shared library: \[libflitter.so' ||
    fail "embed is not linked to libflitter.so"

LD_LIBRARY_PATH=$libdir "$tmp/embed" "$src/samples/petri.fl" 120 ':dish;0' >"$tmp/out" ||
    fail "embed exited with status $?"
sed "s/@VERSION@/$version/" "$src/tests/api/embed_petri.out" >"$tmp/expected"
diff -u "$tmp/expected" "$tmp/out" || fail "embed output differs"

# the same sample linked statically: the installed libflitter.a with the
# libraries `pkg-config --static` names; it defines only fl_ symbols, so
# none of its internals can clash with a host's
bad=$(nm -g --defined-only "$libdir/libflitter.a" | awk 'NF == 3 {print $3}' | grep -v '^fl_' || true)
[ -z "$bad" ] || fail "libflitter.a defines non-fl_ globals: $(echo $bad | head -c 200)"
slibs=$(pkg-config --static --libs libflitter | sed 's/-lflitter\b//')
# shellcheck disable=SC2086
$cc -std=c17 -Wall -Wextra -Wpedantic -Werror "$@" $flags -o "$tmp/embed-static" \
    "$src/samples/embed/embed.c" "$libdir/libflitter.a" $slibs ||
    fail "cannot build samples/embed against the installed libflitter.a"
readelf -d "$tmp/embed-static" | grep -q 'Shared library: \[libflitter.so' &&
    fail "embed-static is linked to libflitter.so"
"$tmp/embed-static" "$src/samples/petri.fl" 120 ':dish;0' >"$tmp/out-static" ||
    fail "embed-static exited with status $?"
diff -u "$tmp/expected" "$tmp/out-static" || fail "embed-static output differs"
echo "installed and embedded: $(cat "$tmp/out" | tail -1)"
