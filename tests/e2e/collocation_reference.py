#!/usr/bin/env python3
"""The RBF examples' solves against dense NumPy solves of the same systems.

    collocation_reference.py rbf PROGRAM     (examples/rbf_franke.part)
    collocation_reference.py kansa PROGRAM   (examples/kansa_poisson.part)
    collocation_reference.py rbf-fmm PROGRAM    (the same, solved matrix-free:
    collocation_reference.py kansa-fmm PROGRAM   dense = fmm, tol = 1e-8)

For each n, runs the generated program, reads its CSV output, and builds and
solves the same collocation system independently with NumPy:
- where cond(A) < 1e10, partc's values on the evaluation grid match those of
  NumPy's solution to 1e-6 relative;
- rbf: the interpolant reproduces f at the nodes to 1e-10 relative (1e-7
  matrix-free, whose residual is asked to 1e-8 in the L2 norm);
- the error against the exact function falls as n grows.
- matrix-free runs check accuracy (--check-accuracy): the residual against
  the direct sums meets the solver's tol, or the program fails;
The matrix-free runs keep eps times the node spacing fixed (0.5 for rbf,
0.6 for kansa), where GMRES converges (runtime/partc/solve/matrix_free_solve.hpp).
Prints a table; exit status 0 when all hold.
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

import numpy as np


def franke(x, y):
    return (0.75 * np.exp(-((9 * x - 2) ** 2 + (9 * y - 2) ** 2) / 4)
            + 0.75 * np.exp(-((9 * x + 1) ** 2) / 49 - (9 * y + 1) / 10)
            + 0.5 * np.exp(-((9 * x - 7) ** 2 + (9 * y - 3) ** 2) / 4)
            - 0.2 * np.exp(-(9 * x - 4) ** 2 - (9 * y - 7) ** 2))


def poisson_exact(x, y):
    return np.sin(np.pi * x) * np.sin(np.pi * y)


def grid_points(n):
    """The examples' nodes: x = (k mod n, k // n) / (n - 1), in id order."""
    k = np.arange(n * n)
    return np.stack([k % n, k // n], axis=1) / (n - 1)


def distances(a, b):
    return np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)


def run(program, work, settings, check_accuracy):
    out = os.path.join(work, "run.csv")
    args = [program, "--steps", "0", "--quiet", "--output", out]
    if check_accuracy:  # the matrix-free solves' contract: residual against direct sums
        args.append("--check-accuracy")
    for name, value in settings.items():
        args += ["--set", f"{name}={value}"]
    subprocess.run(args, check=True)

    def read(set_name):
        with open(out.replace(".csv", f"_{set_name}.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}

    return read("Node"), read("Grid")


def rbf(n, nodes, grid, eps):
    x = grid_points(n)
    A = np.sqrt(1 + (eps * distances(x, x)) ** 2)
    f = franke(x[:, 0], x[:, 1])
    g = np.stack([grid["p_0"], grid["p_1"]], axis=1)
    s = np.sqrt(1 + (eps * distances(g, x)) ** 2) @ np.linalg.solve(A, f)
    error = np.sqrt(np.mean((grid["s"] - franke(g[:, 0], g[:, 1])) ** 2))
    node_error = np.max(np.abs(nodes["s"] - f)) / np.max(np.abs(f))
    return np.linalg.cond(A), grid["s"], s, error, node_error


def kansa(n, nodes, grid, eps):
    x = grid_points(n)
    k = np.arange(n * n)
    boundary = (k % n == 0) | (k % n == n - 1) | (k // n == 0) | (k // n == n - 1)
    r = distances(x, x)
    phi = np.exp(-(eps * r) ** 2)
    laplace = (4 * eps ** 4 * r ** 2 - 4 * eps ** 2) * phi
    A = np.where(boundary[:, None], phi, -laplace)
    b = np.where(boundary, 0.0, 2 * np.pi ** 2 * poisson_exact(x[:, 0], x[:, 1]))
    g = np.stack([grid["p_0"], grid["p_1"]], axis=1)
    u = np.exp(-(eps * distances(g, x)) ** 2) @ np.linalg.solve(A, b)
    error = np.max(np.abs(grid["u"] - poisson_exact(g[:, 0], g[:, 1])))
    return np.linalg.cond(A), grid["u"], u, error, 0.0


def main():
    which, program = sys.argv[1], sys.argv[2]
    # reference, sizes, settings, the shape parameter for n, error name, node tolerance
    cases = {"rbf": (rbf, (5, 8, 11, 14, 20), {"m": 41}, lambda n: 3, "rms error", 1e-10),
             "kansa": (kansa, (10, 15, 20, 30), {"basis": 0, "m": 41}, lambda n: 6, "max error",
                       1e-10),
             "rbf-fmm": (rbf, (10, 20, 30, 40), {"m": 41}, lambda n: 0.5 * (n - 1), "rms error",
                         1e-7),
             "kansa-fmm": (kansa, (10, 20, 30), {"basis": 0, "m": 41}, lambda n: 0.6 * (n - 1),
                           "max error", 1e-7)}
    reference, sizes, settings, shape, error_name, node_tolerance = cases[which]
    failures, errors = [], []
    print(f"{which}: {'n':>4} {'cond(A)':>10} {error_name:>11} {'node error':>11} {'vs numpy':>10}")
    with tempfile.TemporaryDirectory() as work:
        for n in sizes:
            eps = shape(n)
            nodes, grid = run(program, work, dict(settings, n=n, eps=eps),
                              which.endswith("-fmm"))
            if not np.allclose(np.stack([nodes["p_0"], nodes["p_1"]], axis=1), grid_points(n),
                               atol=1e-15):
                failures.append(f"n = {n}: the program's nodes are not the ones rebuilt here")
            cond, ours, theirs, error, node_error = reference(n, nodes, grid, eps)
            versus = np.max(np.abs(ours - theirs)) / np.max(np.abs(theirs))
            print(f"{which}: {n:>4} {cond:>10.2e} {error:>11.3e} {node_error:>11.2e} "
                  f"{versus:>10.2e}{'' if cond < 1e10 else '  (not compared: cond >= 1e10)'}")
            errors.append(error)
            if cond < 1e10 and versus > 1e-6:
                failures.append(f"n = {n}: partc's values differ from NumPy's by {versus:.2e}")
            if node_error > node_tolerance:
                failures.append(f"n = {n}: node values reproduced only to {node_error:.2e}")
    if any(b >= a for a, b in zip(errors, errors[1:])):
        failures.append(f"the {error_name} does not fall with n: {errors}")
    for failure in failures:
        print("FAILED:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
