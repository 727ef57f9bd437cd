#!/usr/bin/env python3
"""NumPy/SciPy side of bench_example_solves: the dense systems of the RBF
examples' solve statements (examples/rbf_franke.part, examples/kansa_poisson.part)
assembled and solved by NumPy and SciPy, printed beside partc's figures.

Input: the directory bench_example_solves wrote: partc.txt, one line per
system, "example unknown n eps partc_seconds partc_assembly_seconds
partc_solve_seconds |x| rcond",
and each system as the generated code wrote it (--matrix-market):
<example>_n<n>_<unknown>.mtx and ..._rhs.mtx.

Per system, each the median of REPETITIONS runs, one thread:
- assembly: the matrix and right side built with NumPy from the example's
  formulas, vectorised (the nodes at (k mod n, k // n) / (n - 1), r the
  N x N distance matrix); checked against the written matrix (largest
  difference relative to its largest entry, printed);
- numpy.linalg.solve (LAPACK dgesv) of the written matrix and right side;
- scipy.linalg.lu_factor + lu_solve (dgetrf, dgetrs) of the same.
NumPy s and SciPy s are assembly + solve, the work of partc's whole
statement (which also estimates rcond and computes the residual, O(N^2)
work beside LU's O(N^3)). |x| diff compares partc's solution with SciPy's.

Run it single-threaded, OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 in its
environment (.ci/bench does): the BLAS reads them when NumPy is imported.

Usage: example_solves.py DIR
"""
import os
import statistics
import sys
import time

import numpy as np
import scipy
import scipy.io
import scipy.linalg

REPETITIONS = 5


def nodes(n):
    k = np.arange(n * n)
    return (k % n) / (n - 1), (k // n) / (n - 1)


def distances(x, y):
    return np.sqrt((x[None, :] - x[:, None]) ** 2 + (y[None, :] - y[:, None]) ** 2)


def franke(x, y):
    return (0.75 * np.exp(-((9 * x - 2) ** 2 + (9 * y - 2) ** 2) / 4)
            + 0.75 * np.exp(-((9 * x + 1) ** 2) / 49 - (9 * y + 1) / 10)
            + 0.5 * np.exp(-((9 * x - 7) ** 2 + (9 * y - 3) ** 2) / 4)
            - 0.2 * np.exp(-((9 * x - 4) ** 2) - (9 * y - 7) ** 2))


def rbf_franke(n, eps):
    """sum(j, phi(|dx|) * w[j]) = f[i], phi(r) = sqrt(1 + (eps r)^2)."""
    x, y = nodes(n)
    return np.sqrt(1 + (eps * distances(x, y)) ** 2), franke(x, y)


def kansa_poisson(n, eps):
    """Gaussian basis (basis = 0): boundary rows phi(|dx|), interior rows
    -laplace phi(|dx|); right side 0 and 2 pi^2 sin(pi x) sin(pi y)."""
    x, y = nodes(n)
    k = np.arange(n * n)
    column, row = k % n, k // n
    boundary = (column == 0) | (column == n - 1) | (row == 0) | (row == n - 1)
    r = distances(x, y)
    gauss = np.exp(-(eps * r) ** 2)
    laplace = (4 * eps ** 4 * r * r - 4 * eps * eps) * gauss
    A = np.where(boundary[:, None], gauss, -laplace)
    f = np.where(boundary, 0.0, 2 * np.pi * np.pi * np.sin(np.pi * x) * np.sin(np.pi * y))
    return A, f


ASSEMBLE = {"rbf_franke": rbf_franke, "kansa_poisson": kansa_poisson}


def median_seconds(f):
    times, result = [], None
    for _ in range(REPETITIONS):
        start = time.perf_counter()
        result = f()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def blas_libraries():
    """The BLAS and LAPACK libraries mapped into this process (Debian's
    alternatives pick reference BLAS or OpenBLAS)."""
    with open("/proc/self/maps") as maps:
        paths = {line.split()[-1] for line in maps if "/" in line}
    return sorted(p for p in paths
                  if ("blas" in p or "lapack" in p) and "-packages/" not in p)


def main():
    directory = sys.argv[1]
    rows = []
    with open(os.path.join(directory, "partc.txt")) as figures:
        for line in figures:
            example, unknown, n, eps, *seconds, x_norm, rcond = line.split()
            rows.append((example, unknown, int(n), float(eps), *map(float, seconds),
                         float(x_norm), float(rcond)))

    measured = []
    for (example, unknown, n, eps, partc_s, partc_assembly_s, partc_solve_s, x_norm,
         rcond) in rows:
        stem = os.path.join(directory, f"{example}_n{n}_{unknown}")
        A = np.ascontiguousarray(scipy.io.mmread(stem + ".mtx"))
        b = np.asarray(scipy.io.mmread(stem + "_rhs.mtx")).ravel()
        assembly_s, (A_numpy, b_numpy) = median_seconds(lambda: ASSEMBLE[example](n, eps))
        matrix_diff = max(np.abs(A_numpy - A).max() / np.abs(A).max(),
                          np.abs(b_numpy - b).max() / max(np.abs(b).max(), 1e-300))
        numpy_s, _ = median_seconds(lambda: np.linalg.solve(A, b))
        scipy_s, x = median_seconds(lambda: scipy.linalg.lu_solve(scipy.linalg.lu_factor(A), b))
        x_diff = abs(np.linalg.norm(x) - x_norm) / x_norm
        measured.append((example, n, partc_s, partc_assembly_s, partc_solve_s, assembly_s, numpy_s, scipy_s,
                         matrix_diff, x_diff, rcond))

    print(f"NumPy {np.__version__}, SciPy {scipy.__version__}, BLAS: "
          + (", ".join(blas_libraries()) or "(none found)"))
    print("NumPy s = NumPy assembly + numpy.linalg.solve; SciPy s = NumPy assembly + "
          "scipy.linalg.lu_factor + lu_solve;\nmedians of %d, one thread." % REPETITIONS)
    print()
    print(f"{'example':<14} {'n':>4} {'N':>6} {'partc s':>9} {'NumPy s':>9} {'SciPy s':>9}"
          f" {'partc/NumPy':>11} {'partc/SciPy':>11}")
    for example, n, partc_s, _, _, assembly_s, numpy_s, scipy_s, *_ in measured:
        print(f"{example:<14} {n:>4} {n * n:>6} {partc_s:>9.3g} {assembly_s + numpy_s:>9.3g}"
              f" {assembly_s + scipy_s:>9.3g} {partc_s / (assembly_s + numpy_s):>11.2f}"
              f" {partc_s / (assembly_s + scipy_s):>11.2f}")
    print()
    print("Split into assembly and solve, and checks: the largest difference between NumPy's\n"
          "matrix (and right side) and partc's, relative to its largest entry; |x| of partc\n"
          "and SciPy, relative difference (may reach about 1e-16 / rcond).")
    print(f"{'example':<14} {'N':>6} | {'assembly: partc':>15} {'NumPy':>8} |"
          f" {'solve: partc':>12} {'numpy':>8} {'scipy LU':>8} | {'matrix diff':>11}"
          f" {'|x| diff':>9} {'rcond':>8}")
    for (example, n, partc_s, partc_assembly_s, partc_solve_s, assembly_s, numpy_s, scipy_s,
         matrix_diff, x_diff, rcond) in measured:
        print(f"{example:<14} {n * n:>6} | {partc_assembly_s:>15.3g} {assembly_s:>8.3g} |"
              f" {partc_solve_s:>12.3g} {numpy_s:>8.3g} {scipy_s:>8.3g} | {matrix_diff:>11.1e}"
              f" {x_diff:>9.1e} {rcond:>8.1e}")


if __name__ == "__main__":
    main()
