#!/usr/bin/env python3
"""fused_pass.part's energies and forces against a brute-force sum.

    check_fused_pass.py PROGRAM WORKDIR

Runs 20 steps and recomputes, from the state written at the end, every
pair's LJ and Coulomb terms within the cutoff 2.5 (minimum image in the
periodic box of side 8): the logged e_lj and e_coulomb of the last step and
each particle's force f must agree to 1e-10 of their scale. The model
computes all three in one pass, one pair walk; this computes them apart.
"""
import csv
import math
import os
import subprocess
import sys

BOX, RC = 8.0, 2.5


def main():
    program, work = sys.argv[1:3]
    os.makedirs(work, exist_ok=True)
    state, log = os.path.join(work, "state.csv"), os.path.join(work, "log.csv")
    subprocess.run([program, "--steps", "20", "--output", state, "--log", log, "--quiet",
                    "--log-every", "0"], check=True)
    rows = list(csv.DictReader(open(state)))
    last = list(csv.DictReader(open(log)))[-1]
    p = [[float(r[f"p_{k}"]) for k in range(3)] for r in rows]
    q = [float(r["q"]) for r in rows]
    n = len(p)
    e_lj = e_coulomb = 0.0
    f = [[0.0] * 3 for _ in range(n)]
    for i in range(n):
        for j in range(i + 1, n):
            dx = [p[j][k] - p[i][k] for k in range(3)]
            dx = [d - BOX * round(d / BOX) for d in dx]
            r2 = sum(d * d for d in dx)
            if r2 >= RC * RC:
                continue
            s = 1 / r2
            e_lj += 4 * s**6 - 4 * s**3
            e_coulomb += q[i] * q[j] / math.sqrt(r2)
            # The force on i: -dU/dr along -dx (dx points from i to j).
            g = (48 * s**7 - 24 * s**4) + q[i] * q[j] * s * math.sqrt(s)
            for k in range(3):
                f[i][k] -= g * dx[k]
                f[j][k] += g * dx[k]
    failures = []
    for name, mine in (("e_lj", e_lj), ("e_coulomb", e_coulomb)):
        theirs = float(last[name])
        print(f"{name}: model {theirs!r}, brute force {mine!r}")
        if abs(theirs - mine) > 1e-10 * abs(mine):
            failures.append(f"{name} differs: {theirs} against {mine}")
    scale = max(abs(c) for fi in f for c in fi)
    worst = max(abs(float(rows[i][f"f_{k}"]) - f[i][k]) for i in range(n) for k in range(3))
    print(f"forces: largest difference {worst:.3g} of largest component {scale:.3g}")
    if worst > 1e-10 * scale:
        failures.append(f"forces differ by {worst} (scale {scale})")
    if failures:
        sys.exit("\n".join(failures))


if __name__ == "__main__":
    main()
