#!/usr/bin/env python3
"""picdiff.py: how close a picture is to a reference picture.

usage: picdiff.py [--tolerance T] OURS.png THEIRS.png

The measure of the picture comparisons of bench/pictures.sh (issue 56):
the "foreground" is every pixel that differs from the reference picture's
most common colour in either picture; the figure is the fraction of those
whose every RGB channel is within T/255 (default 48) of the reference's.
Both pictures are read as 8-bit RGB over black (ImageMagick's `convert`),
and must have the same size. Prints "FRACTION FOREGROUND_PIXELS" and, with
--diff FILE, writes a picture of the pixels off by more than T (white).
"""
import subprocess
import sys

import numpy as np


def load(path):
    size = subprocess.run(["identify", "-format", "%w %h", path + "[0]"], check=True, capture_output=True, text=True)
    w, h = (int(x) for x in size.stdout.split())
    raw = subprocess.run(["convert", path + "[0]", "-background", "black", "-alpha", "remove", "-depth", "8",
                          "rgb:-"], check=True, capture_output=True).stdout
    return np.frombuffer(raw, dtype=np.uint8).reshape(h, w, 3).astype(np.int16)


def main():
    args = sys.argv[1:]
    tol, diff = 48, None
    while args and args[0].startswith("--"):
        if args[0] == "--tolerance":
            tol = int(args[1])
            args = args[2:]
        elif args[0] == "--diff":
            diff = args[1]
            args = args[2:]
        else:
            sys.exit(f"picdiff.py: unknown option {args[0]}")
    if len(args) != 2:
        sys.exit(__doc__)
    ours, theirs = load(args[0]), load(args[1])
    if ours.shape != theirs.shape:
        sys.exit(f"picdiff.py: sizes differ: {ours.shape[1]}x{ours.shape[0]} and {theirs.shape[1]}x{theirs.shape[0]}")
    flat = theirs.reshape(-1, 3)
    colours, counts = np.unique(flat, axis=0, return_counts=True)
    background = colours[np.argmax(counts)]
    fg = np.any(theirs != background, axis=2) | np.any(ours != background, axis=2)
    close = np.all(np.abs(ours - theirs) <= tol, axis=2)
    n = int(fg.sum())
    frac = float((close & fg).sum()) / n if n else 1.0
    print(f"{frac:.4f} {n}")
    if diff:
        bad = (fg & ~close).astype(np.uint8) * 255
        subprocess.run(["convert", "-size", f"{bad.shape[1]}x{bad.shape[0]}", "-depth", "8", "gray:-", diff],
                       input=bad.tobytes(), check=True)


if __name__ == "__main__":
    main()
