#!/usr/bin/env python3
"""run_time_sharing.part: the run's radii choose between one search and two.

    check_run_time_sharing.py PROGRAM WORKDIR

Runs 20 steps at each pair of cutoffs below. In 2D, the density's sum at rc
walks the force's search at rf > rc while (rf / rc)^2 <= 1.2, and the other
way round; else each has a search of its own. The driver's search report
must show it: shared, the search at the larger radius built once a step and
walked twice, the other never built nor walked; apart, each built and walked
once a step. Then the final state's rho and f must agree with a brute-force
sum over every pair (minimum image in the periodic unit square) to 1e-10 of
their scale.
"""
import csv
import os
import re
import subprocess
import sys

STEPS = 20
DENSITY_LINE, FORCE_LINE = 27, 28
# (rc, rf, the line whose search every sum walks, or None: a search each)
RUNS = [(0.08, 0.082, FORCE_LINE),    # shared; the larger radius written second
        (0.082, 0.08, DENSITY_LINE),  # shared; the larger radius written first
        (0.1, 0.04, None),            # apart: (0.1 / 0.04)^2 = 6.25
        (0.03, 0.075, None)]          # apart: (0.075 / 0.03)^2 = 6.25


def search_rows(out):
    rows = re.findall(r"^  sums over A at line (\d+): (.*); built (\d+) times?, walked (\d+) times?$",
                      out, re.MULTILINE)
    return {int(line): (int(builds), int(walks)) for line, _, builds, walks in rows}


def brute_force(p, rc, rf):
    n = len(p)
    rho = [0.0] * n
    f = [[0.0, 0.0] for _ in range(n)]
    for i in range(n):
        for j in range(n):
            dx = [p[j][k] - p[i][k] for k in range(2)]
            dx = [d - round(d) for d in dx]
            s = (dx[0] ** 2 + dx[1] ** 2) ** 0.5
            if s < rc:
                rho[i] += 1 - s / rc
            if 0 < s < rf:
                for k in range(2):
                    f[i][k] += -(1 - s / rf) * dx[k] / s
    return rho, f


def check(program, work, rc, rf, shared_at):
    failures = []
    state = os.path.join(work, f"state_{rc}_{rf}.csv")
    out = subprocess.run([program, "--steps", str(STEPS), "--set", f"rc={rc}", "--set", f"rf={rf}",
                          "--output", state], check=True, capture_output=True, text=True).stdout
    searches = search_rows(out)
    print(f"rc = {rc}, rf = {rf}: (builds, walks) by line {searches}")
    if shared_at is None:
        want = {DENSITY_LINE: (STEPS, STEPS), FORCE_LINE: (STEPS, STEPS)}
    else:
        other = FORCE_LINE if shared_at == DENSITY_LINE else DENSITY_LINE
        want = {shared_at: (STEPS, 2 * STEPS), other: (0, 0)}
    if searches != want:
        failures.append(f"rc = {rc}, rf = {rf}: searches {searches}, expected {want}")

    rows = list(csv.DictReader(open(state)))
    p = [[float(r[f"p_{k}"]) for k in range(2)] for r in rows]
    rho, f = brute_force(p, rc, rf)
    for name, mine, theirs in (
            ("rho", rho, [float(r["rho"]) for r in rows]),
            ("f", [x for fi in f for x in fi], [float(r[f"f_{k}"]) for r in rows for k in range(2)])):
        scale = max(abs(x) for x in mine)
        worst = max(abs(a - b) for a, b in zip(mine, theirs))
        print(f"  {name}: largest difference {worst:.3g} of largest value {scale:.3g}")
        if worst > 1e-10 * scale:
            failures.append(f"rc = {rc}, rf = {rf}: {name} differs from the brute-force sum by "
                            f"{worst} (scale {scale})")
    return failures


def main():
    program, work = sys.argv[1:3]
    os.makedirs(work, exist_ok=True)
    failures = []
    for rc, rf, shared_at in RUNS:
        failures += check(program, work, rc, rf, shared_at)
    if failures:
        sys.exit("FAILED: " + "; ".join(failures))


if __name__ == "__main__":
    main()
