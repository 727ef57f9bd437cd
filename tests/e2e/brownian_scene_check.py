#!/usr/bin/env python3
"""The Brownian obstacles scene against the single-file model, statistically.

    brownian_scene_check.py SINGLE_FILE SCENE

The scene's noise is keyed by its integrator's instance, so its
trajectories are not the single file's; their statistics must be. Each run
(N = 5000 tracers, dt = 1e-3, 1000 steps to t = 1, fixed seeds) gives the
msd and, from the tracers' final displacements d, its standard error
(the tracers are independent: they meet only the obstacles). Checks:
- free diffusion (phi = 0): the scene's msd is 6 D t within 4 standard errors;
- among spheres (phi = 0.2): the scene's msd equals the single file's within
  4 standard errors of their difference, and msd / 6t is Maxwell's
  D_eff / D = 2 / (2 + phi) within 3% (e2e_brownian's tolerance: Maxwell's
  estimate is not exact, and the msd at t = 1 still holds a little of the
  short-time excess);
- no tracer of the scene is inside an obstacle after any step (inside,
  logged every step, is 0).
"""
import csv
import math
import subprocess
import sys
import tempfile
from pathlib import Path

N, DT, STEPS, D = 5000, 1e-3, 1000, 1.0


def run(program, folder, phi, seed, scene):
    name = Path(program).name
    log, out = Path(folder) / f"{name}_log.csv", Path(folder) / f"{name}.csv"
    prefix = "euler_maruyama." if scene else ""
    subprocess.run([program, "--set", f"N={N}", "--set", f"phi={phi}",
                    "--set", f"{prefix}dt={DT}", "--set", f"{prefix}D={D}",
                    "--steps", str(STEPS), "--seed", str(seed), "--log", str(log),
                    "--log-every", "1", "--output", str(out), "--quiet"], check=True)
    with open(log, newline="") as f:
        rows = list(csv.DictReader(f))
    with open(Path(folder) / f"{name}_T.csv", newline="") as f:
        r2 = [sum(float(row[f"d_{k}"]) ** 2 for k in range(3)) for row in csv.DictReader(f)]
    mean = sum(r2) / len(r2)
    error = math.sqrt(sum((x - mean) ** 2 for x in r2) / (len(r2) - 1) / len(r2))
    return rows, float(rows[-1]["t"]), mean, error


def main():
    single, scene = sys.argv[1], sys.argv[2]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        rows, t, msd, error = run(scene, folder, 0, 11, True)
        expected = 6 * D * t
        print(f"free: scene msd {msd:.4f} +- {error:.4f} at t = {t:g}, 6 D t = {expected:.4f}")
        if abs(msd - expected) > 4 * error:
            failures.append(f"free: msd {msd} is not 6 D t = {expected} within 4 x {error}")
        phi = 0.2
        rows, t, msd, error = run(scene, folder, phi, 12, True)
        _, t_single, msd_single, error_single = run(single, folder, phi, 13, False)
        band = 4 * math.hypot(error, error_single)
        maxwell = 2 / (2 + phi)
        print(f"phi = {phi}: scene msd {msd:.4f} +- {error:.4f}, single file {msd_single:.4f} "
              f"+- {error_single:.4f} (difference {msd - msd_single:+.4f}, 4 standard errors "
              f"{band:.4f}); D_eff / D = {msd / (6 * D * t):.4f}, Maxwell {maxwell:.4f}")
        if t != t_single:
            failures.append(f"the scene ran to t = {t}, the single file to {t_single}")
        if abs(msd - msd_single) > band:
            failures.append(f"phi = {phi}: msd {msd} against the single file's {msd_single}")
        if abs(msd / (6 * D * t) / maxwell - 1) > 0.03:
            failures.append(f"phi = {phi}: D_eff / D {msd / (6 * D * t)}, Maxwell {maxwell}")
        inside = max(int(float(row["inside"])) for row in rows)
        print(f"tracers inside an obstacle, most after any of {len(rows) - 1} steps: {inside}")
        if inside != 0:
            failures.append(f"{inside} tracers inside an obstacle")
    if failures:
        sys.exit("\n".join(failures))


if __name__ == "__main__":
    main()
