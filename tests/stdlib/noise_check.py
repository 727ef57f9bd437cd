#!/usr/bin/env python3
"""The standard library's noise, against its distribution.

    noise_check.py BROWNIAN_NOISE LANGEVIN_GAS

- Euler-Maruyama (brownian_noise.part: D = 0.5, dt = 0.01, 100 steps): each
  coordinate has mean 0 and variance 2 D t = 1 within 5 standard errors.
- Langevin thermostat (langevin_gas.part: kT = 1.5, gamma = 1, 2000 steps of
  0.005, twenty relaxation times): mean v_k^2 = kT within 5 standard errors
  plus the integrator's O(gamma dt) bias, taken as 1%.
"""
import csv
import math
import subprocess
import sys
import tempfile
from pathlib import Path


def final(program, steps, folder, columns):
    out = Path(folder) / (Path(program).name + ".csv")
    subprocess.run([program, "--steps", str(steps), "--seed", "17", "--output", str(out),
                    "--quiet"], check=True)
    with open(out, newline="") as f:
        return [[float(row[c]) for c in columns] for row in csv.DictReader(f)]


def main():
    brownian, langevin = sys.argv[1], sys.argv[2]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        xs = [c for row in final(brownian, 100, folder, ["p_0", "p_1", "p_2"]) for c in row]
        n = len(xs)
        mean = sum(xs) / n
        var = sum((x - mean) ** 2 for x in xs) / (n - 1)
        expected = 2 * 0.5 * 100 * 0.01
        print(f"Euler-Maruyama: mean {mean:.4f} (0 +- {5 * math.sqrt(expected / n):.4f}), "
              f"variance {var:.4f} ({expected} +- {5 * expected * math.sqrt(2 / n):.4f})")
        if abs(mean) > 5 * math.sqrt(expected / n):
            failures.append(f"Euler-Maruyama: mean {mean}")
        if abs(var - expected) > 5 * expected * math.sqrt(2 / n):
            failures.append(f"Euler-Maruyama: variance {var}, not {expected}")

        vs = [c for row in final(langevin, 2000, folder, ["v_0", "v_1", "v_2"]) for c in row]
        kT = 1.5
        t = sum(v * v for v in vs) / len(vs)
        band = 5 * kT * math.sqrt(2 / len(vs)) + 0.01 * kT
        print(f"Langevin: mean v^2 {t:.4f} ({kT} +- {band:.4f})")
        if abs(t - kT) > band:
            failures.append(f"Langevin: temperature {t}, not {kT}")
    if failures:
        sys.exit("\n".join(failures))


if __name__ == "__main__":
    main()
