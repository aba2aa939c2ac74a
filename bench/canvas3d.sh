#!/bin/sh
# bench/canvas3d.sh [--floors] [BUILD_DIR] [FRAMES]: milliseconds per frame of
# `!canvas3d` drawing for Flitter's own examples/physics.fl and
# examples/bounce.fl (1080x1080, samples=4, each inside a !bloom), as a
# front end draws the window after every frame, on whatever OpenGL EGL
# gives (Mesa's llvmpipe on a machine without a GPU).
#
# The two scripts are Flitter's (https://github.com/jonathanhogg/flitter,
# BSD 2-clause licence, copyright Jonathan Hogg); they are not copied into
# this repository but read at run time from a Flitter git repository
# (FLITTER_REPO, default /work/.mirror/jonathanhogg+flitter/repo, at
# FLITTER_REV, default v1.0.0b28) or, when FLITTER_EXAMPLES names a
# directory, from that directory (a Flitter checkout's examples/).
#
# Each runs as examples/Makefile renders it (10 frames a second, with
# --physics=upstream so that the particles are Flitter's own) for FRAMES
# frames (default 10) after one warm-up frame; printed: the mean drawing
# time (fl_draw_window: the 3D scene, the bloom, the compositing), the
# fastest frame's, the mean CPU time of drawing (all threads) and the
# mean evaluation+physics time. LP_NUM_THREADS
# (Mesa's llvmpipe rasteriser threads) and the other Mesa variables pass
# through.
#
# --floors also draws variants of the two with parts of the scene taken
# out, to show what each part costs (issue 25 asks for 30 frames a second,
# 33 ms a frame; a variant that draws strictly less than its example and
# still takes longer is a floor for the whole). The variants are made at
# run time by rules on the language, not by editing copies:
#
#   samples1        every `samples=4` made `samples=1` (no multisampling)
#   nomodels        every block headed by a model node (`!sphere`, `!box`,
#                   `!cylinder`, `!cone`) removed, and every `for` left
#                   without a body
#   nobloom         every `!bloom` removed, its block put in its place
#   notransparent   the models with a `transparency=` removed (physics.fl's
#                   enclosing sphere)
#   noradiuslights  every `for` block whose body makes a `!light` with a
#                   `radius=` removed (bounce.fl's 150 lights of the balls)
#   noglass         every `!material` block with a `transparency=` that
#                   holds a `!box` removed (bounce.fl's two glass boxes)
#
# FLOORS_KEEP=DIR copies the examples and their variants there, to be
# read or drawn.
# Not part of the test suite: timings vary with the machine and its load.
set -u
floors=false
build=
frames=
for arg in "$@"; do
    case $arg in
    --floors) floors=true ;;
    -*) echo "usage: $0 [--floors] [BUILD_DIR] [FRAMES]" >&2; exit 2 ;;
    *) if [ -z "$build" ]; then build=$arg; elif [ -z "$frames" ]; then frames=$arg; else
           echo "usage: $0 [--floors] [BUILD_DIR] [FRAMES]" >&2; exit 2
       fi ;;
    esac
done
build=${build:-build}
frames=${frames:-10}
case $build in /*) ;; *) build=$PWD/$build ;; esac
bench="$build/tests/bench_canvas3d"
[ -x "$bench" ] || { echo "build first: meson setup $build && ninja -C $build" >&2; exit 2; }
tmp=$(mktemp -d) || exit 2
trap 'rm -rf "$tmp"' EXIT
repo=${FLITTER_REPO:-/work/.mirror/jonathanhogg+flitter/repo}
rev=${FLITTER_REV:-v1.0.0b28}
for ex in physics bounce; do
    if [ -n "${FLITTER_EXAMPLES:-}" ]; then
        cp "$FLITTER_EXAMPLES/$ex.fl" "$tmp/$ex.fl" || exit 2
    elif ! git -C "$repo" show "$rev:examples/$ex.fl" >"$tmp/$ex.fl" 2>/dev/null; then
        echo "no Flitter examples: set FLITTER_EXAMPLES=DIR or FLITTER_REPO=GIT_DIR (see $0)" >&2
        exit 2
    fi
done
# variant NAME SOURCE RULE...: writes $tmp/NAME.fl, SOURCE with the rules
# applied in order (each rule must change something, or the variant would
# silently measure the example itself)
variant() {
    python3 - "$tmp" "$@" <<'EOF' || exit 2
import re, sys

tmp, name, source, rules = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
lines = open(f"{tmp}/{source}.fl").read().split("\n")

def indent(line):
    return len(line) - len(line.lstrip(" "))

def code(line):
    """whether [line] holds code (not blank, not a comment)"""
    return bool(line.strip()) and not line.lstrip().startswith("--")

def blocks(lines):
    """(start, end) of every line's block: the line and the lines below it
    up to the next line of code indented no deeper (blank and comment lines
    before that one go with the block only if code of it follows them)."""
    out = []
    for i, line in enumerate(lines):
        if not code(line):
            continue
        j = end = i + 1
        while j < len(lines) and (not code(lines[j]) or indent(lines[j]) > indent(line)):
            j += 1
            if code(lines[j - 1]):
                end = j
        out.append((i, end))
    return out

def drop(lines, pred):
    """lines without the blocks whose header and body satisfy pred"""
    gone = set()
    for i, j in blocks(lines):
        if i not in gone and pred(lines[i].strip(), [l.strip() for l in lines[i + 1:j]]):
            gone.update(range(i, j))
    return [l for k, l in enumerate(lines) if k not in gone]

MODEL = re.compile(r"^!(sphere|box|cylinder|cone)\b")
def empty_for(h, body):
    return h.startswith("for ") and not any(b and not b.startswith("--") for b in body)

def apply(lines, rule):
    text = "\n".join(lines)
    if rule == "samples1":
        return text.replace("samples=4", "samples=1").split("\n")
    if rule == "nobloom":
        # the first !bloom removed and its block moved up to its place, then
        # the next, until none is left
        for i, j in blocks(lines):
            if lines[i].strip().startswith("!bloom"):
                body = lines[i + 1:j]
                step = min((indent(l) for l in body if code(l)), default=indent(lines[i])) - indent(lines[i])
                return apply(lines[:i] + [l[min(step, indent(l)):] for l in body] + lines[j:], rule)
        return lines
    if rule == "nomodels":
        return drop(drop(lines, lambda h, b: bool(MODEL.match(h))), empty_for)
    if rule == "notransparent":
        return drop(lines, lambda h, b: bool(MODEL.match(h)) and "transparency=" in h)
    if rule == "noradiuslights":
        return drop(lines, lambda h, b: h.startswith("for ") and
                    any(x.startswith("!light") and "radius=" in x for x in b))
    if rule == "noglass":
        return drop(lines, lambda h, b: h.startswith("!material") and "transparency=" in h and
                    any(x.startswith("!box") for x in b))
    sys.exit(f"unknown rule {rule}")

for rule in rules:
    changed = apply(lines, rule)
    if changed == lines:
        sys.exit(f"{name}: rule {rule} changed nothing in {source}.fl")
    lines = changed
open(f"{tmp}/{name}.fl", "w").write("\n".join(lines))
EOF
}

scenes="physics bounce"
if $floors; then
    command -v python3 >/dev/null || { echo "--floors needs python3" >&2; exit 2; }
    variant physics-samples1 physics samples1
    variant physics-nomodels physics nomodels
    variant physics-nobloom physics nobloom
    variant physics-noouter physics notransparent
    variant bounce-noradiuslights bounce noradiuslights
    variant bounce-noglass bounce noglass
    variant bounce-noglass-samples1 bounce noglass samples1
    scenes="physics physics-samples1 physics-noouter physics-nobloom physics-nomodels
            bounce bounce-noradiuslights bounce-noglass bounce-noglass-samples1"
    if [ -n "${FLOORS_KEEP:-}" ]; then cp "$tmp"/*.fl "$FLOORS_KEEP"/ || exit 2; fi
fi
echo "canvas3d benchmark: $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)${LP_NUM_THREADS:+, LP_NUM_THREADS=$LP_NUM_THREADS}"
for ex in $scenes; do
    (cd "$tmp" && "$bench" --script "$ex.fl" --fps 10 --frames "$frames" --physics upstream -D OUTPUT=) || exit 1
done
