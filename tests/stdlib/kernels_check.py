#!/usr/bin/env python3
"""The kernel modules of stdlib/kernel, against their definitions.

    kernels_check.py KERNELS_1D KERNELS_2D KERNELS_3D

Each program writes the kernels along a ray (kernels.part.in: h = 0.5,
eps = 1.7, r from 0 to 2.4 h in steps of h / 2000). Here, independently of
the formulas in the modules:
- the SPH kernels (Wendland C2, cubic spline) integrate to 1 over space
  (Simpson's rule in r with the surface of a sphere of radius r) and vanish
  from r = 2h on;
- their gradient factors equal -W'(r) / r: -grad r against W' by central
  differences;
- the radial basis functions' Laplacians equal phi'' + (d - 1) phi' / r by
  central differences, and phi itself its closed form.
"""
import csv
import math
import subprocess
import sys
import tempfile
from pathlib import Path

H, EPS = 0.5, 1.7


def columns(program, folder):
    out = Path(folder) / (Path(program).name + ".csv")
    subprocess.run([program, "--steps", "0", "--output", str(out), "--quiet"], check=True)
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    rows.sort(key=lambda row: float(row["r"]))
    return {name: [float(row[name]) for row in rows] for name in rows[0]}


def sphere(d, r):
    return 2.0 if d == 1 else 2 * math.pi * r if d == 2 else 4 * math.pi * r * r


def simpson(f, step):
    odd = sum(f[1:-1:2])
    even = sum(f[2:-1:2])
    return step / 3 * (f[0] + 4 * odd + 2 * even + f[-1])


def main():
    failures = []

    def check(what, got, want, tol):
        ok = abs(got - want) <= tol * max(1.0, abs(want))
        print(f"  {what}: {got:.10g} (want {want:.10g} within {tol:g}){'' if ok else '  FAILED'}")
        if not ok:
            failures.append(what)

    closed = {
        "mq": lambda r: math.sqrt(1 + (EPS * r) ** 2),
        "imq": lambda r: 1 / math.sqrt(1 + (EPS * r) ** 2),
        "ga": lambda r: math.exp(-(EPS * r) ** 2),
    }
    with tempfile.TemporaryDirectory() as folder:
        for d, program in enumerate(sys.argv[1:4], start=1):
            print(f"{d}D:")
            c = columns(program, folder)
            r = c["r"]
            step = r[1] - r[0]
            inside = [k for k, x in enumerate(r) if x <= 2 * H + 1e-12]
            for w in ("wendland", "spline"):
                f = [sphere(d, r[k]) * c[w][k] for k in inside]
                check(f"integral of {w}", simpson(f, step), 1.0, 1e-9)
                outside = max(abs(c[w][k]) for k in range(len(r)) if r[k] >= 2 * H)
                check(f"{w} from r = 2h on", outside, 0.0, 0.0)
                # W' = -grad r, compared where both are O(1): the central
                # difference's error is O(step^2) but for the spline's knot at
                # h, where its W'' jumps, and the supports' end at 2h.
                worst, largest = 0.0, 0.0
                for k in range(1, len(r) - 1):
                    if abs(r[k] - H) < 2 * step or abs(r[k] - 2 * H) < 2 * step:
                        continue
                    fd = (c[w][k + 1] - c[w][k - 1]) / (2 * step)
                    largest = max(largest, abs(fd))
                    worst = max(worst, abs(fd + c[w + "_grad"][k] * r[k]))
                check(f"{w}_grad: -grad r against W' (worst, relative to max |W'|)",
                      worst / largest, 0.0, 1e-5)
            for phi, formula in closed.items():
                worst = max(abs(c[phi][k] - formula(r[k])) for k in range(len(r)))
                check(f"{phi} against its closed form", worst, 0.0, 1e-14)
                worst = 0.0
                for k in range(1, len(r) - 1):
                    f = c[phi]
                    second = (f[k + 1] - 2 * f[k] + f[k - 1]) / step ** 2
                    first = (f[k + 1] - f[k - 1]) / (2 * step)
                    fd = second + (d - 1) * first / r[k]
                    worst = max(worst, abs(fd - c[phi + "_laplacian"][k]))
                check(f"{phi}_laplacian against phi'' + (d-1) phi'/r (worst)", worst, 0.0, 1e-5)
    if failures:
        print("FAILED: " + ", ".join(failures))
        sys.exit(1)


if __name__ == "__main__":
    main()
