#!/usr/bin/env python3
"""bench/ratios.py [--reps N] [--base FLITTER] [BUILD_DIR]: issue 24's table.

The scenes of issue 24 (canvas10k 30 frames, petri200 600, discs2k 120,
charges1k 30, discs20k 3), each run as a whole `flitter run --frames F`
process (start, load, frames, exit: wall time from spawn to exit) by this
build and, with --base, by an older flitter, interleaved scene by scene
and run by run; with FLITTER_REF set, also the reference Flitter's frame
loop: FLITTER_REF is a command that runs `$FLITTER_REF SCENE.fl FRAMES`
headless in lockstep in its default (simplifying) mode, its garbage
collector off as its EngineController.run() has it, and prints
`loop=SECONDS` (as for bench/frames.sh). Prints the medians in
milliseconds and, against Flitter's loop, the ratios the issue sets
targets for (20x, 20x, 100x, 15x).

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
import time

from fixedpath import fixed_copies

SCENES = [("canvas10k", 30, 20), ("petri200", 600, 20), ("discs2k", 120, 100),
          ("charges1k", 30, 15), ("discs20k", 3, None)]


def whole(cmd):
    """Seconds from spawn to exit of [cmd] (an argument vector)."""
    t = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - t


def flitter_loop(ref, script, frames):
    """The reference's frame loop in seconds (its `loop=` line)."""
    out = subprocess.run(shlex.split(ref) + [script, str(frames)], capture_output=True,
                         text=True, check=True).stdout
    found = re.findall(r"loop=([0-9.eE+-]+)", out)
    if not found:
        sys.exit(f"ratios.py: no loop= line from FLITTER_REF for {script}")
    return float(found[-1])


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build", nargs="?", default=os.path.join(here, "..", "build"))
    ap.add_argument("--reps", type=int, default=11)
    ap.add_argument("--base", help="an older flitter binary to run alongside")
    a = ap.parse_args()
    variants = {"now": os.path.join(a.build, "src", "flitter")}
    if a.base:
        variants = {"base": a.base, **variants}
    for name, exe in variants.items():
        if not os.access(exe, os.X_OK):
            sys.exit(f"ratios.py: {name}: {exe} is not an executable (build first)")
    variants = fixed_copies(variants)   # (paths of one length: bench/fixedpath.py)
    ref = os.environ.get("FLITTER_REF")
    times = {}
    for _ in range(a.reps):
        for scene, frames, _target in SCENES:
            script = os.path.join(here, scene + ".fl")
            if ref:
                times.setdefault((scene, "flitter"), []).append(flitter_loop(ref, script, frames))
            for name, exe in variants.items():
                times.setdefault((scene, name), []).append(
                    whole([exe, "run", "--frames", str(frames), script]))
    cols = (["flitter"] if ref else []) + list(variants)
    print(f"medians of {a.reps} interleaved runs, ms (flitter: its frame loop; the others: "
          "whole processes)")
    print(f"{'scene':10} {'frames':>6} " + " ".join(f"{c:>9}" for c in cols) +
          ("".join(f" {c + ' x':>9}" for c in variants) + "   target" if ref else ""))
    for scene, frames, target in SCENES:
        med = {c: statistics.median(times[(scene, c)]) * 1e3 for c in cols}
        line = f"{scene:10} {frames:6} " + " ".join(f"{med[c]:9.1f}" for c in cols)
        if ref:
            line += "".join(f" {med['flitter'] / med[c]:8.1f}x" for c in variants)
            line += f"   {target}x" if target else "   -"
        print(line)


if __name__ == "__main__":
    main()
