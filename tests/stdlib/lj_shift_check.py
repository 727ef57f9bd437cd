#!/usr/bin/env python3
"""pair.lj's energy, plain and shifted, against a brute-force pair sum.

    lj_shift_check.py BUILD_DIR

BUILD_DIR holds energy_lj and energy_lj_shift (energy.part.in with
pair.lj(rc = 2.5) and pair.lj(rc = 2.5, const shift = true)). Each writes its
start (--steps 0): e_lj must equal, to 1e-12 relative, the sum over pairs
within rc (minimum image in the periodic box of side 6.6) of
4 (r^-12 - r^-6), less 4 (rc^-12 - rc^-6) a pair for the shifted one; and
the two runs' forces must be the same bit for bit (the shift is energy only).
"""
import csv
import itertools
import subprocess
import sys
import tempfile
from pathlib import Path

BOX, RC = 6.6, 2.5


def run(program, folder):
    log, out = Path(folder) / "log.csv", Path(folder) / "out.csv"
    subprocess.run([str(program), "--steps", "0", "--seed", "3", "--log", str(log),
                    "--output", str(out), "--quiet"], check=True)
    energy = float(next(csv.DictReader(open(log, newline="")))["e_lj"])
    return energy, list(csv.DictReader(open(out, newline="")))


def lj(r2):
    return 4 * (r2**-6 - r2**-3)


def main():
    build = Path(sys.argv[1])
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        plain, state = run(build / "energy_lj", folder)
        shifted, shifted_state = run(build / "energy_lj_shift", folder)
    p = [[float(r[f"p_{k}"]) for k in range(3)] for r in state]
    total, pairs = 0.0, 0
    for a, b in itertools.combinations(p, 2):
        d = [x - y for x, y in zip(a, b)]
        r2 = sum((x - BOX * round(x / BOX)) ** 2 for x in d)
        if r2 < RC * RC:
            total += lj(r2)
            pairs += 1
    expected = {"plain": total, "shifted": total - pairs * lj(RC * RC)}
    for name, value in (("plain", plain), ("shifted", shifted)):
        error = abs(value - expected[name]) / abs(expected[name])
        print(f"{name}: e_lj {value:.15g}, brute force {expected[name]:.15g} "
              f"({pairs} pairs), relative difference {error:.2e}")
        if error > 1e-12:
            failures.append(f"{name} e_lj differs from the brute-force sum by {error:.2e}")
    forces = [[r[f"f_{k}"] for k in range(3)] for r in state]
    if forces != [[r[f"f_{k}"] for k in range(3)] for r in shifted_state]:
        failures.append("the shift changed the forces")
    if failures:
        sys.exit("FAILED: " + "; ".join(failures))


if __name__ == "__main__":
    main()
