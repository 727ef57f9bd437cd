#!/usr/bin/env python3
"""Figure 1 of the accuracy figures: the fast sum's measured error against
its time, beside the vectorised direct sum, from bench_fast_sum's CSV.

    plot_fast_sum.py BENCH.csv OUT.png [--expect-shape]

One panel per kernel (1/r, a multiquadric, a Gaussian); a line per point
distribution and N, each point labelled with the tolerance asked; the direct
sum's time as a vertical line per N. A tolerance no order is predicted to
meet (the model's prediction at the highest order above it) is one a model
run refuses (fast_sum/contract.hpp): drawn with a cross, not checked.
Rows whose measured error exceeds the tolerance are always listed;
--expect-shape makes them, and an error that rises as the tolerance falls,
failures (exit 4).
"""
import csv
import statistics
import sys
from collections import defaultdict

KERNELS = {"coulomb": "1/r", "mq1": "multiquadric sqrt(1 + r^2)",
           "mq3": "multiquadric sqrt(1 + (3r)^2)", "gauss3": "Gaussian exp(-(3r)^2)"}


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for key in ("n", "order"):
            r[key] = int(r[key])
        for key in ("tol", "predicted", "rel_l2", "plan_s", "eval_s", "direct_s"):
            r[key] = float(r[key])
    return rows


def refused(r):
    """A tolerance the plan's highest order is predicted to miss: a run stops there."""
    return r["predicted"] > r["tol"]


def check_shape(rows):
    """The contract and the knob's direction, nothing about speed."""
    failures = []
    series = defaultdict(list)
    for r in rows:
        if refused(r):
            continue
        if r["rel_l2"] > r["tol"]:
            failures.append(f"{r['kernel']} {r['distribution']} N = {r['n']}: measured "
                            f"{r['rel_l2']:.2e} above tol {r['tol']:.0e} (predicted "
                            f"{r['predicted']:.2e} at order {r['order']})")
        series[(r["kernel"], r["distribution"], r["n"])].append(r)
    for key, points in series.items():
        points.sort(key=lambda r: -r["tol"])
        for a, b in zip(points, points[1:]):
            # Rounding's floor (1e-13) and equal orders may keep the error flat.
            if b["rel_l2"] > max(a["rel_l2"] * 1.5, 1e-13) and b["order"] > a["order"]:
                failures.append(f"{key}: the error rose from {a['rel_l2']:.2e} at tol "
                                f"{a['tol']:.0e} to {b['rel_l2']:.2e} at {b['tol']:.0e}")
    return failures


def plot(rows, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kernels = [k for k in KERNELS if any(r["kernel"] == k for r in rows)]
    fig, axes = plt.subplots(1, len(kernels), figsize=(6 * len(kernels), 5.2), sharey=True,
                             squeeze=False)
    for ax, kernel in zip(axes[0], kernels):
        mine = [r for r in rows if r["kernel"] == kernel]
        series = defaultdict(list)
        for r in mine:
            series[(r["distribution"], r["n"])].append(r)
        for (dist, n), points in sorted(series.items()):
            points.sort(key=lambda r: -r["tol"])
            t = [r["plan_s"] + r["eval_s"] for r in points]
            e = [max(r["rel_l2"], 1e-16) for r in points]
            line, = ax.loglog(t, e, "o-" if dist == "uniform" else "s--",
                              label=f"{dist}, N = {n:.0e}")
            for r, x, y in zip(points, t, e):
                ax.annotate(f"{r['tol']:.0e}", (x, y), textcoords="offset points", xytext=(4, 3),
                            fontsize=6, color=line.get_color())
                if refused(r):
                    ax.plot([x], [y], "x", color="black", ms=9)
        for n in sorted({r["n"] for r in mine}):
            direct = statistics.median(r["direct_s"] for r in mine if r["n"] == n)
            ax.axvline(direct, color="grey", ls=":", lw=1)
            ax.text(direct, 3e-16, f" direct sum\n N = {n:.0e}", fontsize=7, color="grey",
                    va="bottom")
        ax.set_title(KERNELS[kernel])
        ax.set_xlabel("plan + evaluation time [s], 1 thread")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    axes[0][0].set_ylabel("measured relative L2 error (500 targets vs the direct sum)")
    fig.suptitle("Fast sum (black-box FMM): error against time, each point labelled with the "
                 "tolerance asked; dotted: the vectorised direct sum; x: a tol no order meets "
                 "(a model run refuses it)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 2:
        sys.exit(__doc__)
    rows = read(args[0])
    plot(rows, args[1])
    failures = check_shape(rows)
    strict = "--expect-shape" in sys.argv
    for f in failures:
        print(("expectation failed: " if strict else "above its tolerance or rising: ") + f)
    if strict and failures:
        sys.exit(4)
    print(f"{len(rows)} rows, {sum(refused(r) for r in rows)} refused (no order meets tol), "
          f"{len(failures)} not within tol or rising")


if __name__ == "__main__":
    main()
