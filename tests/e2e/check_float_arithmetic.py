#!/usr/bin/env python3
"""Pair terms on float lanes (schedule: arithmetic = float) against the same
model's double build: one step of the seed model from the same start, so that
v (0 at the start) holds exactly the step's force increment c * F.

    check_float_arithmetic.py DOUBLE_PROGRAM FLOAT_PROGRAM [ARGS...]

Checks, on v's components by particle id:
- the relative L2 error ||v_float - v_double|| / ||v_double|| is at most
  BOUND (below);
- it is above FLOOR: float lanes ran (double lanes differ from the scalar
  walk by a few roundings of 2^-53, e2e/md_simd_vs_scalar; nothing in double
  gives an error of 1e-9), and the two runs are not bitwise equal;
- the float build gives the same bits, every column, with OMP_NUM_THREADS=1
  and 2.

BOUND: the unit roundoff of float is u = 2^-24 = 6.0e-8. A term of the seed,
-exp(-r) dx / r, is rounded at each step of its float evaluation: r (the
double condition's |dx| demoted, 1/2 u) and dx's components (1/2 u each),
exp (Highway's float Exp, within 1 ulp; r < rc << 1, so r's rounding hardly
moves it), the division and the product by dx (1/2 u each): at most 3 u =
1.8e-7 of each component, and every term is added to double sums without
further rounding. A particle's force is a sum of about 9 terms whose errors
are unrelated, and for uniform points so are their directions, so that
||F||^2 is about the sum of the terms' squares and the relative L2 error of
v is about the terms' RMS relative error: below their worst case, 3 u. The
bound, 2e-7 (3.4 u, the issue's target), leaves a tenth for cancellation
among a particle's terms. (Measured: 5.2e-8, 0.9 u.) The conditions are
decided in double, so no pair crosses a cutoff.
"""
import csv
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

BOUND = 2e-7
FLOOR = 1e-9


def run(program, args, out, threads):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    subprocess.run([program, *args, "--output", str(out), "--quiet"], check=True, env=env)
    with open(out, newline="") as f:
        return {row["id"]: row for row in csv.DictReader(f)}


def velocity(row):
    return [float(row[c]) for c in sorted(row) if c.startswith("v_")]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    double_program, float_program, args = sys.argv[1], sys.argv[2], sys.argv[3:]
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        exact = run(double_program, args, folder / "double.csv", 2)
        one = run(float_program, args, folder / "float_1.csv", 1)
        two = run(float_program, args, folder / "float_2.csv", 2)
    if one.keys() != exact.keys():
        sys.exit("the float and double runs hold different particles")
    error = norm = 0.0
    for key, row in exact.items():
        v, w = velocity(row), velocity(one[key])
        error += sum((a - b) ** 2 for a, b in zip(w, v))
        norm += sum(a * a for a in v)
    relative = math.sqrt(error / norm)
    print(f"{len(exact)} particles: relative L2 of v, float lanes against double: "
          f"{relative:.3e} (bound {BOUND:.1e}, floor {FLOOR:.1e})")
    failures = []
    if not relative <= BOUND:
        failures.append(f"relative L2 {relative:.3e} above {BOUND:.1e}")
    if not relative > FLOOR:
        failures.append(f"relative L2 {relative:.3e} not above {FLOOR:.1e}: float lanes did not run")
    if one == exact:
        failures.append("float lanes gave the double build's bits")
    if one != two:
        differ = sum(one[key] != two[key] for key in one)
        failures.append(f"1 and 2 threads differ at {differ} particles")
    else:
        print("1 and 2 threads: the same bits")
    if failures:
        sys.exit("; ".join(failures))


if __name__ == "__main__":
    main()
