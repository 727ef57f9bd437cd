#!/usr/bin/env python3
"""The SPH dam break: particles at one time, and the front against time.

    plot_dam_break.py SNAPSHOT_F.csv SNAPSHOT_W.csv LOG.csv PYSPH.csv OUT.png DX

Left: fluid particles coloured by pressure, walls in grey. Right: the front
Z = (x_front - dx) / a against T = t sqrt(2 g / a) (a = 1 m), beside PySPH's
dam_break_2d and Martin & Moyce's (1952) experiment (n^2 = 2, a = 2.25 in).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARTIN_MOYCE = [(0.832, 1.217), (1.219, 1.474), (1.997, 2.292), (2.547, 2.995),
                (3.345, 4.134)]


def rows(path):
    with open(path, newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    return list(csv.DictReader(lines))


def main():
    fluid, walls, log, pysph, out, dx = sys.argv[1:7]
    dx = float(dx)
    f, w = rows(fluid), rows(walls)
    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2),
                                         gridspec_kw={"width_ratios": [1.3, 1]})
    left.scatter([float(r["p_0"]) for r in w], [float(r["p_1"]) for r in w], s=2, c="0.6")
    points = left.scatter([float(r["p_0"]) for r in f], [float(r["p_1"]) for r in f], s=3,
                          c=[float(r["pr"]) / 1000 for r in f], cmap="viridis")
    figure.colorbar(points, ax=left, label="pressure (kPa)")
    left.set_aspect("equal")
    left.set_xlim(-0.2, 4.2)
    left.set_ylim(-0.2, 2.2)
    g = 9.81
    ours = rows(log)
    left.set_title(f"sph_dam_break at t = {float(ours[-1]['t']):.2f} s")
    right.plot([float(r["t"]) * math.sqrt(2 * g) for r in ours],
               [float(r["front"]) - dx for r in ours], label="partc")
    ref = rows(pysph)
    right.plot([float(r["T"]) for r in ref], [float(r["Z"]) for r in ref], "--",
               label="PySPH dam_break_2d")
    right.plot(*zip(*MARTIN_MOYCE), "o", label="Martin & Moyce (1952)")
    right.set_xlim(0, 3.5)
    right.set_ylim(1, 4.2)
    right.set_xlabel("T = t sqrt(2 g / a)")
    right.set_ylabel("Z = front / a")
    right.legend()
    figure.tight_layout()
    figure.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
