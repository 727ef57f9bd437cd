#!/usr/bin/env python3
"""NumPy/SciPy side of bench_solve: the same multiquadric RBF system, solved by
numpy.linalg.solve (LAPACK dgesv) and scipy.linalg.solve (dgetrf, the rcond
estimate dgecon, dgetrs: the work of partc's solve_dense), timed the same way.

The system (as in bench_solve.cpp): N = m^2 points on an m x m grid of the
unit square, spacing h = 1 / (m - 1), point k at ((k % m) h, (k // m) h);
A[i, j] = sqrt(1 + (eps r_ij)^2) with eps h = 0.5; the right-hand side is
Franke's function at the points. Each solve is timed alone, the median of
REPETITIONS runs kept.

Run it single-threaded, OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 in its
environment (.ci/bench does): the BLAS reads them when NumPy is imported.

Output, read by bench_solve: '#' lines (the BLAS library NumPy loaded, whose
speed decides the figures), then per N "N numpy_seconds scipy_seconds |w|",
|w| the 2-norm of SciPy's solution, for bench_solve to check that both
solved the same system.
"""
import statistics
import sys
import time

import numpy as np
import scipy.linalg

SIDES = (20, 30, 40, 50)  # N = 400, 900, 1600, 2500
REPETITIONS = 3
EPS_TIMES_H = 0.5


def franke(x, y):
    return (0.75 * np.exp(-((9 * x - 2) ** 2 + (9 * y - 2) ** 2) / 4)
            + 0.75 * np.exp(-((9 * x + 1) ** 2) / 49 - (9 * y + 1) / 10)
            + 0.5 * np.exp(-((9 * x - 7) ** 2 + (9 * y - 3) ** 2) / 4)
            - 0.2 * np.exp(-((9 * x - 4) ** 2) - (9 * y - 7) ** 2))


def system(m):
    h = 1.0 / (m - 1)
    k = np.arange(m * m)
    x, y = (k % m) * h, (k // m) * h
    eps = EPS_TIMES_H / h
    r2 = (x[:, None] - x[None, :]) ** 2 + (y[:, None] - y[None, :]) ** 2
    return np.sqrt(1.0 + eps * eps * r2), franke(x, y)


def median_seconds(solve):
    times = []
    for _ in range(REPETITIONS):
        start = time.perf_counter()
        solution = solve()
        times.append(time.perf_counter() - start)
    return statistics.median(times), solution


def blas_libraries():
    """The BLAS and LAPACK libraries mapped into this process (not SciPy's
    wrappers of them): Debian's alternatives pick reference BLAS or OpenBLAS."""
    with open("/proc/self/maps") as maps:
        paths = {line.split()[-1] for line in maps if "/" in line}
    return sorted(p for p in paths
                  if ("blas" in p or "lapack" in p) and "-packages/" not in p)


def main():
    print(f"# numpy {np.__version__}, scipy {scipy.__version__}")
    for path in blas_libraries():
        print(f"# loaded {path}")
    for m in SIDES:
        A, f = system(m)
        numpy_seconds, _ = median_seconds(lambda: np.linalg.solve(A, f))
        scipy_seconds, w = median_seconds(lambda: scipy.linalg.solve(A, f))
        print(f"{m * m} {numpy_seconds:.6f} {scipy_seconds:.6f} {np.linalg.norm(w):.17g}")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
