#!/usr/bin/env python3
"""Pictures of a field on an example's evaluation grid (a set of m x m points
whose id k sits at ((k mod m), (k // m)) / (m - 1), as in rbf_franke.part and
kansa_poisson.part).

    plot_grid.py GRID.csv OUT.png TITLE FIELD [FIELD ...]

One panel per field (a column of the CSV file the driver's --output wrote),
side by side, each with its colour bar.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    path, out, title, fields = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    with open(path, newline="") as f:
        rows = sorted(csv.DictReader(f), key=lambda r: int(r["id"]))
    m = int(round(len(rows) ** 0.5))
    if m * m != len(rows):
        sys.exit(f"plot_grid.py: {path} has {len(rows)} rows, not m x m")
    figure, axes = plt.subplots(1, len(fields), figsize=(4.6 * len(fields), 4), squeeze=False)
    for ax, field in zip(axes[0], fields):
        values = np.array([float(r[field]) for r in rows]).reshape(m, m)  # [y][x]
        image = ax.imshow(values, origin="lower", extent=(0, 1, 0, 1), cmap="viridis")
        ax.set_title(field)
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        figure.colorbar(image, ax=ax, shrink=0.85)
    figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
