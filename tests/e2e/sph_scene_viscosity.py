#!/usr/bin/env python3
"""The SPH dam-break scene with and without its artificial viscosity.

    sph_scene_viscosity.py SCENE_PROGRAM

Runs examples/scenes/sph_dam_break.part to t = 0.8 s (3084 steps) with
alpha = 0.1 and with alpha = 0 (the viscosity's term is then 0 in every
pair: the run of the scene without it, whose C++ cli/drop_sph_viscosity
checks). The viscosity only takes energy away (tests/stdlib/sph), so the
fluid's kinetic energy sum m v^2 / 2 must be lower with it; the front, set
by gravity and pressure, must move by less than 1%.

Then the column at rest (a tank as wide as the column, velocities damped
for 1 s, then free to t = 2 s; alpha = 0.3): with viscosity its pressure
stays hydrostatic, RMS |p - rho0 g (H - y)| within 3% of rho0 g H and
max |v| below 0.05 m/s; without it the sound waves of the settling are not
damped, and both must be larger.
"""
import csv
import subprocess
import sys
import tempfile
from pathlib import Path


def final(program, alpha, folder):
    out = Path(folder) / f"alpha{alpha}.csv"
    subprocess.run([program, "--steps", "3084", "--set", f"viscosity.alpha={alpha}",
                    "--output", str(out), "--quiet"], check=True)
    with open(out.with_name(f"{out.stem}_F.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    e_kin = sum(0.5 * float(r["m"]) * (float(r["v_0"]) ** 2 + float(r["v_1"]) ** 2) for r in rows)
    front = max(float(r["p_0"]) for r in rows)
    return e_kin, front


def column(program, alpha, folder):
    """p_rms / (rho0 g H) and v_max at t = 2 s of the column at rest."""
    log = Path(folder) / f"column{alpha}.csv"
    subprocess.run([program, "--set", "width=22", "--set", "sph_symplectic_euler.settle=1",
                    "--set", f"viscosity.alpha={alpha}", "--steps", "7710", "--log", str(log),
                    "--quiet"], check=True)
    with open(log, newline="") as f:
        last = list(csv.DictReader(f))[-1]
    rho0_g_h = 1000 * 9.81 * (2 * 20 + 1.5) / 20
    return float(last["p_rms"]) / rho0_g_h, float(last["v_max"])


def main():
    with tempfile.TemporaryDirectory() as folder:
        e_with, front_with = final(sys.argv[1], 0.1, folder)
        e_without, front_without = final(sys.argv[1], 0, folder)
        rms_with, v_with = column(sys.argv[1], 0.3, folder)
        rms_without, v_without = column(sys.argv[1], 0, folder)
    print(f"t = 0.8 s: kinetic energy {e_with:.6g} J/m with viscosity, {e_without:.6g} without "
          f"({e_with / e_without - 1:+.1%}); front {front_with:.5g} m and {front_without:.5g} m")
    print(f"column at rest, t = 2 s: p_rms = {rms_with:.2%} of rho0 g H, max |v| = {v_with:.3g} m/s "
          f"with viscosity; {rms_without:.2%} and {v_without:.3g} m/s without")
    failures = []
    if not (rms_with < 0.03 and v_with < 0.05):
        failures.append("the column with viscosity is not at rest")
    if not (rms_without > rms_with and v_without > v_with):
        failures.append("the column without viscosity is as quiet as with it")
    if not e_with < e_without:
        failures.append("the viscosity does not take kinetic energy away")
    if abs(front_with / front_without - 1) > 0.01:
        failures.append("the fronts differ by more than 1%")
    if failures:
        sys.exit("FAILED: " + "; ".join(failures))


if __name__ == "__main__":
    main()
