#!/usr/bin/env python3
"""Checks the standard library's force effects alone and in pairs.

    compose_check.py BUILD_DIR EFFECT...

BUILD_DIR holds compose_A (one effect) and compose_A_B (two) for the
effects named, built from compose.part.in. Each runs 0 steps: the
integrator's primed force slot leaves the forces of the initial state in f.
  - pair forces obey Newton's third law: the total force is 0 (to 1e-12
    of the sum of magnitudes);
  - the forces of A and B together are the forces of A plus those of B
    (to 1e-12 of the largest), in every component of every particle: the
    merged channel adds what each effect adds alone, and one effect's
    noise does not change when another is used.
"""
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

PAIR_FORCES = {"soft_exp", "lj", "wca", "coulomb", "spring_dashpot"}


def forces(program, folder):
    out = Path(folder) / (program.name + ".csv")
    subprocess.run([str(program), "--steps", "0", "--seed", "11", "--output", str(out), "--quiet"],
                   check=True)
    with open(out, newline="") as f:
        return {int(row["id"]): [float(row[f"f_{k}"]) for k in range(3)] for row in csv.DictReader(f)}


def main():
    build, names = Path(sys.argv[1]), sys.argv[2:]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        alone = {n: forces(build / f"compose_{n}", folder) for n in names}
        for n, f in alone.items():
            scale = max(abs(c) for v in f.values() for c in v)
            if scale == 0:
                failures.append(f"{n}: no force at all (the check would be of zeros)")
            if n in PAIR_FORCES:
                total = [sum(v[k] for v in f.values()) for k in range(3)]
                magnitude = sum(abs(c) for v in f.values() for c in v)
                print(f"{n}: total force {total} of {magnitude:.3e}")
                if max(abs(t) for t in total) > 1e-12 * magnitude:
                    failures.append(f"{n}: total force {total}, not 0 (Newton's third law)")
        for a_index, a in enumerate(names):
            for b in names[a_index + 1:]:
                together = forces(build / f"compose_{a}_{b}", folder)
                scale = max(abs(c) for i in together for c in together[i])
                worst = max(abs(together[i][k] - alone[a][i][k] - alone[b][i][k])
                            for i in together for k in range(3))
                print(f"{a} + {b}: worst |f_ab - f_a - f_b| = {worst:.2e} of {scale:.2e}")
                if worst > 1e-12 * scale:
                    failures.append(f"{a} + {b}: forces differ from the sum by {worst:.2e}")
    if failures:
        sys.exit("\n".join(failures))
    print("every pair composes: forces together equal the sum of each alone")


if __name__ == "__main__":
    main()
