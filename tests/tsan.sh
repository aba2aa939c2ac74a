#!/usr/bin/env bash
# tsan.sh BUILD_DIR: the physics engine's threads, and the evaluator's loop
# kernels on them, under ThreadSanitizer.
# BUILD_DIR is a build configured with clang and -Db_sanitize=thread (made
# here when missing). Runs the differential tests of the pair routes (1, 2
# and 4 threads against the reference loop) and of the particle pass (a
# sample of 2,000 systems, 8 of them big enough to be split over threads),
# every physics golden, the loop kernels' route tests (1 to 3 threads),
# the window's two-thread row split (halves.h), the
# benchmark scenes for a few frames on 2 threads, the decoding threads of
# pictures and videos (test_media), a video's writer thread, a memory
# budget and a symbol table shared by two threads (test_budget), pictures
# drawn beside the frame loop (test_pictures_thread), and the live
# window's three threads under Xvfb (a physics view; a !window drawn by
# the render graph on the drawing thread, with the two OpenGL contexts,
# in 2D and in 3D with a shader, and with a !record writing a file), each
# as one test that fails on any report.
# tests/tsan.supp leaves out the reports inside Mesa, LLVM and FFmpeg,
# whose threads synchronise by means TSan cannot see. Ends with `N passed,
# M failed`.
set -uo pipefail
cd "$(dirname "$0")/.."
build=$1
# (CSG_OBJECT: a CGAL unit built by another build of this checkout, linked
# instead of compiling it again; lib/meson.build, csg_object)
[ -f "$build/build.ninja" ] ||
    CC=${TSAN_CC:-clang-14} meson setup "$build" -Db_sanitize=thread -Db_lundef=false \
        ${CSG_OBJECT:+-Dcsg_object="$CSG_OBJECT"} >/dev/null ||
    { echo "0 passed, 1 failed"; exit 1; }
ninja -C "$build" src/flitter src/flitter-window.so tests/test_physics_routes tests/test_particle_pass \
    tests/test_halves tests/test_kernel tests/test_media tests/test_budget tests/test_pictures_thread >/dev/null ||
    { echo "0 passed, 1 failed"; exit 1; }
export TSAN_OPTIONS="halt_on_error=1 exitcode=66 suppressions=$PWD/tests/tsan.supp"
passed=0 failed=0
check() {   # check NAME CMD...
    local name=$1 log
    shift
    log=$(mktemp)
    if "$@" >/dev/null 2>"$log" && ! grep -q "ThreadSanitizer" "$log"; then
        passed=$((passed + 1))
        echo "ok   $name"
    else
        failed=$((failed + 1))
        echo "FAIL $name"
        head -40 "$log"
    fi
    rm -f "$log"
}
check physics_routes "$build/tests/test_physics_routes"
check particle_pass env FLITTER_PROPTEST_SYSTEMS=2000 "$build/tests/test_particle_pass"
check halves "$build/tests/test_halves"
check kernel "$build/tests/test_kernel"
check media "$build/tests/test_media"
check budget "$build/tests/test_budget"
check pictures_thread "$build/tests/test_pictures_thread"
# a !bloom of a 2D canvas, drawn offscreen: its passes and the sRGB
# encoding split over two threads (halves.h)
tmpd=$(mktemp -d)
printf '%s\n' '!window size=256;256' '    !record filename=OUTPUT' '        !bloom radius=16' \
    '            !canvas' '                !fill color=1;0.5;0.25' '                    !rect point=64;64 size=128;128' \
    >"$tmpd/bloom.fl"
bloom_picture() {
    "$build/src/flitter" --offscreen --lockstep --fps=1 --runtime=1 --define "OUTPUT=$tmpd/bloom.png" \
        "$tmpd/bloom.fl" && [ -s "$tmpd/bloom.png" ]
}
check window/bloom bloom_picture
# a video's writer thread (lib/render/output/video.c): every frame queued
# and waited for in lockstep; stamped on the wall clock and dropped on a
# full queue when realtime
video() {   # video MODE
    rm -f "$tmpd/v.mp4"
    "$build/src/flitter" --offscreen "--$1" --fps=30 --runtime=1 --define "OUTPUT=$tmpd/v.mp4" \
        "$tmpd/bloom.fl" && [ -s "$tmpd/v.mp4" ]
}
check video/lockstep video lockstep
check video/realtime video realtime
rm -rf "$tmpd"
while read -r script opts; do
    case "$script" in ''|'#'*) continue ;; esac
    # shellcheck disable=SC2086
    check "golden/$script" "$build/src/flitter" run --threads 2 $opts --dump-state "tests/golden/$script"
done < tests/golden/MANIFEST
for s in "petri200 60" "discs2k 20" "charges1k 3" "discs20k 3" "canvas10k 3"; do
    set -- $s
    check "bench/$1" "$build/src/flitter" run --threads 2 --frames "$2" "bench/$1.fl"
done
# the live window: the frame loop's thread and the display's, under a
# private Xvfb (skipped without xvfb-run): lockstep (every picture handed
# over) and realtime (pictures dropped while the display is busy)
if command -v xvfb-run >/dev/null 2>&1; then
    check window/lockstep xvfb-run -a "$build/src/flitter" run --window --lockstep --frames 60 samples/petri.fl
    check window/realtime xvfb-run -a "$build/src/flitter" run --window --realtime --runtime 2 samples/petri.fl
    tmpd=$(mktemp -d)
    printf '%s\n' '!window size=320;240' '    !bloom radius=8' '        !canvas' \
        '            !rect point=40;40 size=(frame%100)*2;80 fill=true color=1;0.5;0.25' >"$tmpd/gl.fl"
    check window/gl-lockstep xvfb-run -a "$build/src/flitter" run --window --lockstep --frames 60 "$tmpd/gl.fl"
    check window/gl-realtime xvfb-run -a "$build/src/flitter" run --window --realtime --runtime 2 "$tmpd/gl.fl"
    # the drawing thread in 3D, with engine names read by a shader, and a
    # !record writing a file every tenth frame (drawn while the frame loop waits)
    q="'''"
    printf '%s\n' "let frag = $q\${HEADER}" 'in vec2 coord;' 'out vec4 color;' 'uniform float beat;' \
        'void main() { color = vec4(fract(beat), coord, 1.0) * 0.5; }' "$q" \
        '!window size=240;180' "    !record filename=(\"$tmpd/r.png\" if frame % 10 == 0 else null)" \
        '        !bloom radius=4' '            !canvas3d viewpoint=0;0;5 samples=2' \
        '                !light color=1 position=sin(frame/9);1;2 radius=0.1' \
        '                !sphere position=(frame%30)/15-1;0;0 size=0.8 color=1;0.3;0.2' \
        '                !box size=0.6 position=0;-1;0 rotation=frame/100' \
        '    !shader fragment=frag' >"$tmpd/gl3d.fl"
    check window/gl3d-realtime xvfb-run -a "$build/src/flitter" run --window --realtime --runtime 2 "$tmpd/gl3d.fl"
    check window/gl3d-lockstep xvfb-run -a "$build/src/flitter" run --window --lockstep --frames 40 "$tmpd/gl3d.fl"
    rm -rf "$tmpd"
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
