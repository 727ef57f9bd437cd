#!/usr/bin/env python3
"""A picture of logged observables against time (the CSV file of --log).

    plot_log.py LOG.csv OUT.png TITLE COLUMN [COLUMN ...] [--line SLOPE LABEL]...

Each COLUMN against t; each --line draws SLOPE * t, a reference to compare
with (6 D t for a mean squared displacement, say).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    path, out, title, rest = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    columns, lines = [], []
    while rest:
        if rest[0] == "--line":
            lines.append((float(rest[1]), rest[2]))
            rest = rest[3:]
        else:
            columns.append(rest.pop(0))
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    t = [float(r["t"]) for r in rows]
    figure, ax = plt.subplots(figsize=(6, 4))
    for column in columns:
        ax.plot(t, [float(r[column]) for r in rows], label=column)
    for slope, label in lines:
        ax.plot([t[0], t[-1]], [slope * t[0], slope * t[-1]], "--", label=label)
    ax.set_xlabel("t")
    ax.legend()
    ax.set_title(title)
    figure.tight_layout()
    figure.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
