#!/usr/bin/env python3
"""The SPH dam-break scene with and without its artificial viscosity.

    sph_scene_viscosity.py SCENE_PROGRAM

Runs examples/scenes/sph_dam_break.part to t = 0.8 s (3084 steps) with
alpha = 0.1 and with alpha = 0 (the viscosity's term is then 0 in every
pair: the run of the scene without it, whose C++ cli/drop_sph_viscosity
checks). The viscosity only takes energy away (tests/stdlib/sph), so the
fluid's kinetic energy sum m v^2 / 2 must be lower with it; the front, set
by gravity and pressure, must move by less than 1%.
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


def main():
    with tempfile.TemporaryDirectory() as folder:
        e_with, front_with = final(sys.argv[1], 0.1, folder)
        e_without, front_without = final(sys.argv[1], 0, folder)
    print(f"t = 0.8 s: kinetic energy {e_with:.6g} J/m with viscosity, {e_without:.6g} without "
          f"({e_with / e_without - 1:+.1%}); front {front_with:.5g} m and {front_without:.5g} m")
    failures = []
    if not e_with < e_without:
        failures.append("the viscosity does not take kinetic energy away")
    if abs(front_with / front_without - 1) > 0.01:
        failures.append("the fronts differ by more than 1%")
    if failures:
        sys.exit("FAILED: " + "; ".join(failures))


if __name__ == "__main__":
    main()
