#!/usr/bin/env python3
"""bench/examples.py --examples DIR [--examples DIR]... [--frames N] [--reps R]
[BUILD_DIR]: the evaluator against Flitter's on Flitter's own examples.

For each script DIR/*.fl of each DIR given (Flitter's examples folder:
bauble.fl ... video.fl; and its documentation's scripts: docs/diagrams and
docs/tutorial_images), run from its own folder so that its includes and files resolve, the
milliseconds a steady frame spends evaluating the program into a tree (the
frames after the first two), by this build (`flitter run --frames N --stats`
with FLITTER_NODRAW=1, its `per steady frame` line) and, with FLITTER_REF set, by Flitter: a command
that runs `$FLITTER_REF SCRIPT N` headless in lockstep in its default
(simplifying) mode, garbage collector as its EngineController.run() has it,
and prints `eval_ms=` and `physics_ms=` for the same frames. Drawing is
excluded (neither side draws a picture: a !record would make flitter-c draw
every frame, and the GL's threads would run beside the evaluation); physics
is reported apart. The
runs are interleaved example by example and repetition by repetition; the
table has medians, the ratio Flitter / flitter-c, and their median and
worst.

Not part of the test suite: timings vary with the machine and its load.
Scripts and paths reach the programs as argument vectors, never a shell.
"""
import argparse
import os
import re
import shlex
import statistics
import subprocess
import sys

from fixedpath import fixed_copies

NUM = r"([0-9.eE+-]+)"


def ours(exe, script, frames):
    """(eval ms, physics ms) of a steady frame of this build, or None."""
    r = subprocess.run([exe, "run", "--frames", str(frames), "--stats", os.path.basename(script)],
                       cwd=os.path.dirname(script), capture_output=True, text=True,
                       env=dict(os.environ, FLITTER_NODRAW="1"))
    m = re.search(r"per steady frame: eval " + NUM + " ms, physics " + NUM + " ms", r.stderr)
    return (float(m.group(1)), float(m.group(2))) if r.returncode == 0 and m else None


def reference(ref, script, frames):
    """(eval ms, physics ms) of a steady frame of Flitter, or None."""
    r = subprocess.run(shlex.split(ref) + [os.path.basename(script), str(frames)],
                       cwd=os.path.dirname(script), capture_output=True, text=True)
    e = re.findall(r"eval_ms=" + NUM, r.stdout)
    p = re.findall(r"physics_ms=" + NUM, r.stdout)
    return (float(e[-1]), float(p[-1])) if r.returncode == 0 and e and p else None


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build", nargs="?", default=os.path.join(here, "..", "build"))
    ap.add_argument("--examples", required=True, action="append",
                    help="a folder of Flitter's scripts (examples/, docs/diagrams/, docs/tutorial_images/); "
                         "may be repeated")
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--reps", type=int, default=5)
    a = ap.parse_args()
    exe = os.path.abspath(os.path.join(a.build, "src", "flitter"))   # (run from each script's folder)
    if not os.access(exe, os.X_OK):
        sys.exit(f"examples.py: {exe} is not an executable (build first)")
    exe = fixed_copies({"c": exe})["c"]   # (a path of a fixed length: bench/fixedpath.py)
    scripts, names = [], {}
    for folder in a.examples:
        found = sorted(os.path.join(os.path.abspath(folder), f) for f in os.listdir(folder) if f.endswith(".fl"))
        if not found:
            sys.exit(f"examples.py: no .fl script in {folder}")
        for s in found:
            # the examples by their names, the others by folder and name
            # (docs/diagrams/petri.fl as diagrams/petri.fl)
            parent = os.path.basename(os.path.dirname(s))
            names[s] = os.path.basename(s) if parent == "examples" else parent + "/" + os.path.basename(s)
        scripts += found
    ref = os.environ.get("FLITTER_REF")
    got = {}
    for _ in range(a.reps):
        for s in scripts:
            for side, run in (("flitter", lambda: reference(ref, s, a.frames) if ref else None),
                              ("c", lambda: ours(exe, s, a.frames))):
                got.setdefault((s, side), []).append(run())
    print(f"medians of {a.reps} interleaved runs of {a.frames} frames; ms per steady frame")
    print(f"{'script':28} {'Flitter eval':>12} {'flitter-c':>10} {'ratio':>7} "
          f"{'Flitter phys':>12} {'flitter-c':>10}")
    ratios = []
    for s in scripts:
        row = {}
        for side in ("flitter", "c"):
            runs = [r for r in got[(s, side)] if r]
            row[side] = (statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs)) \
                if runs and len(runs) == len(got[(s, side)]) else None
        f, c = row["flitter"], row["c"]
        ratio = f[0] / c[0] if f and c and c[0] > 0 else None
        if ratio:
            ratios.append((ratio, names[s]))
        cell = lambda v, w: f"{v:{w}.4f}" if v is not None else f"{'-':>{w}}"
        print(f"{names[s]:28} {cell(f and f[0], 12)} {cell(c and c[0], 10)} "
              f"{(f'{ratio:6.1f}x' if ratio else '      -'):>7} {cell(f and f[1], 12)} {cell(c and c[1], 10)}")
    if ratios:
        print(f"ratio: median {statistics.median(r for r, _ in ratios):.1f}x, worst "
              f"{min(ratios)[0]:.1f}x ({min(ratios)[1]}), over {len(ratios)} scripts")
    return 0


if __name__ == "__main__":
    sys.exit(main())
