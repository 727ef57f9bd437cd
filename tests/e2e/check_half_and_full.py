#!/usr/bin/env python3
"""half_and_full_lists.part: one set of Verlet lists, both sums right.

    check_half_and_full.py PROGRAM WORKDIR

Runs 100 steps. The driver's search report must list exactly one search, the
lists, built at most once a step and walked twice a step (the force's half
lists and the weighted count's full lists); then the final state's f and c
must agree with a brute-force sum over every pair (minimum image in the box
of side 6, cutoff 2.5) to 1e-10 of their scale.
"""
import csv
import os
import re
import subprocess
import sys

BOX, RC, STEPS = 6.0, 2.5, 100


def main():
    program, work = sys.argv[1:3]
    os.makedirs(work, exist_ok=True)
    state = os.path.join(work, "state.csv")
    out = subprocess.run([program, "--steps", str(STEPS), "--output", state], check=True,
                         capture_output=True, text=True).stdout
    rows = re.findall(r"^  (.+?): (.*); built (\d+) times?, walked (\d+) times?$", out,
                      re.MULTILINE)
    failures = []
    for serves, structure, builds, walks in rows:
        print(f"{serves}: {structure}; built {builds}, walked {walks}")
    if len(rows) != 1:
        failures.append(f"{len(rows)} searches in the report, expected one set of lists")
    elif "and full" not in rows[0][1]:
        failures.append("the lists do not hold half and full lists both")
    elif not (2 <= int(rows[0][2]) <= STEPS + 1) or int(rows[0][3]) != 2 * STEPS:
        failures.append("built or walked other than expected: at least twice (the motion "
                        f"outruns the skin), at most {STEPS + 1}, walked {2 * STEPS}")

    state_rows = list(csv.DictReader(open(state)))
    p = [[float(r[f"p_{k}"]) for k in range(3)] for r in state_rows]
    w = [float(r["w"]) for r in state_rows]
    n = len(p)
    f = [[0.0] * 3 for _ in range(n)]
    c = [0.0] * n
    for i in range(n):
        for j in range(n):
            dx = [p[j][k] - p[i][k] for k in range(3)]
            dx = [d - BOX * round(d / BOX) for d in dx]
            r2 = sum(d * d for d in dx)
            if r2 >= RC * RC:
                continue
            c[i] += w[j] * (1 - r2**0.5 / RC)
            if j != i:
                g = 24 * (2 * r2**-7 - r2**-4)
                for k in range(3):
                    f[i][k] -= g * dx[k]
    for name, mine, theirs in (
            ("f", [x for fi in f for x in fi],
             [float(r[f"f_{k}"]) for r in state_rows for k in range(3)]),
            ("c", c, [float(r["c"]) for r in state_rows])):
        scale = max(abs(x) for x in mine)
        worst = max(abs(a - b) for a, b in zip(mine, theirs))
        print(f"{name}: largest difference {worst:.3g} of largest value {scale:.3g}")
        if worst > 1e-10 * scale:
            failures.append(f"{name} differs from the brute-force sum by {worst} (scale {scale})")
    if failures:
        sys.exit("FAILED: " + "; ".join(failures))


if __name__ == "__main__":
    main()
