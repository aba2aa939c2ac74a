#!/usr/bin/env python3
"""Run a dish from Python, plot its trajectories, sweep `strength`.

    PYTHONPATH=build/python python3 samples/python/dish_sweep.py [OUT.png]

(or after `pip install --no-build-isolation .`, without PYTHONPATH). Writes
a PNG (default dish_sweep.png) with two plots: the cells' trajectories over
3 seconds of samples/python/dish.fl at strength 120, and the dish's mean
distance from the centre after 3 s against the electrostatic `strength`
(5 values, 3 runs each: the run number seeds the !random force).
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import flitter_c  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DISH = os.path.join(HERE, "dish.fl")
FRAMES = 180   # 3 s at 60 fps


def trajectories(strength: float, run: int = 0) -> np.ndarray:
    """Positions of every cell at every frame: shape (frames, n, 2)."""
    sim = flitter_c.load(DISH, defines={"strength": strength, "run": run}, fps=60)
    frames = []
    for _ in range(FRAMES):
        sim.step()
        ids, pos = sim.positions("dish")
        if len(ids):
            cells = [k for k, i in enumerate(ids) if isinstance(i, int)]   # not the anchor
            frames.append(pos[cells])
    return np.stack(frames)


def spread(strength: float, run: int) -> float:
    """Mean distance of the cells from the centre after FRAMES frames."""
    sim = flitter_c.load(DISH, defines={"strength": strength, "run": run})
    sim.step(FRAMES)
    ids, pos = sim.positions("dish")
    cells = [k for k, i in enumerate(ids) if isinstance(i, int)]
    return float(np.linalg.norm(pos[cells], axis=1).mean())


def main() -> None:
    out = sys.argv[1] if len(sys.argv) > 1 else "dish_sweep.png"
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5))

    tr = trajectories(120.0)
    for c in range(tr.shape[1]):
        ax1.plot(tr[:, c, 0], tr[:, c, 1], lw=0.8)
        ax1.plot(tr[-1, c, 0], tr[-1, c, 1], "k.", ms=4)
    ax1.set_aspect("equal")
    ax1.set_title(f"dish.fl, strength 120: {tr.shape[1]} cells, {FRAMES} frames")
    ax1.set_xlabel("x")
    ax1.set_ylabel("y")

    strengths = [30, 120, 480, 1920, 7680]   # not 0: the script reads 0 as "not given"
    runs = 3
    spreads = np.array([[spread(s, r) for r in range(runs)] for s in strengths])
    for r in range(runs):
        ax2.plot(strengths, spreads[:, r], "o", alpha=0.5, label=f"run {r}")
    ax2.plot(strengths, spreads.mean(axis=1), "k-", label="mean")
    ax2.set_xscale("log")
    ax2.set_xlabel("electrostatic strength")
    ax2.set_ylabel(f"mean distance from centre after {FRAMES / 60:g} s")
    ax2.set_title("sweep of strength")
    ax2.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")
    for s, row in zip(strengths, spreads):
        print(f"strength {s:4g}: spread {' '.join(f'{x:.3f}' for x in row)}")


if __name__ == "__main__":
    main()
