"""bench/fixedpath.py: the binaries a benchmark compares, copied to paths of
one length.

The length of a program's path (and of its environment) moves where its
stack starts, and so the alignment of everything on it: one build measured
20% slower on a scene from a path a few characters longer than another's
(bench/PROFILE.md, issue 62 part 4). The benchmarks run copies at
TMP/v0/flitter, TMP/v1/flitter, ... instead, so that two builds compared
differ in their code alone. The copies are removed when the benchmark ends.
"""
import atexit
import os
import shutil
import tempfile


def fixed_copies(exes):
    """{name: path} of executables -> {name: path of a copy}, each copy's
    path as long as the others' (at most ten)."""
    if len(exes) > 10:
        raise ValueError("fixed_copies: at most ten executables")
    top = tempfile.mkdtemp(prefix="flitter-bench-")
    atexit.register(shutil.rmtree, top, True)
    out = {}
    for k, (name, exe) in enumerate(exes.items()):
        folder = os.path.join(top, f"v{k}")
        os.mkdir(folder)
        out[name] = os.path.join(folder, "flitter")
        shutil.copy2(exe, out[name])
    return out
