#!/usr/bin/env python3
"""The fcc lattice sums A12 and A6 that examples/accuracy/lj_fcc.part uses,
computed independently with NumPy.

A_n = sum over the lattice sites j != 0 of (a / r_j)^n, a the nearest-
neighbour distance. With a = 1 the fcc sites are (x, y, z) / sqrt(2) for
integers x + y + z even. The sum runs over a sphere of radius R inside the
cube |x|, |y|, |z| <= M, and adds the continuum tail beyond R,
4 pi rho / ((n - 3) R^(n - 3)) with rho = sqrt(2) sites per unit volume.
A12 converges at once; A6 to about 1e-9 at M = 120.

  /usr/bin/python3 examples/accuracy/fcc_lattice_sums.py [M...]
"""
import sys

import numpy as np


def lattice_sums(M):
    k = np.arange(-M, M + 1)
    radius2 = M * M / 2.0 * 0.98
    a12 = a6 = 0.0
    y, z = np.meshgrid(k, k, indexing="ij")
    for x in k:
        r2 = x * x + y * y + z * z
        keep = ((x + y + z) % 2 == 0) & (r2 > 0)
        r2 = r2[keep] / 2.0
        r2 = np.sort(r2[r2 < radius2])[::-1]  # small terms first
        a12 += np.sum(r2 ** -6.0)
        a6 += np.sum(r2 ** -3.0)
    radius = np.sqrt(radius2)
    rho = np.sqrt(2.0)
    return (a12 + 4 * np.pi * rho / (9 * radius ** 9), a6 + 4 * np.pi * rho / (3 * radius ** 3))


def main():
    sizes = [int(m) for m in sys.argv[1:]] or [40, 80, 120]
    print(f"{'M':>5} {'A12':>18} {'A6':>18}")
    for M in sizes:
        a12, a6 = lattice_sums(M)
        print(f"{M:5d} {a12:18.10f} {a6:18.10f}")
    print("given: A12 = 12.13188, A6 = 14.45392")


if __name__ == "__main__":
    main()
