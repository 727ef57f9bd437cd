#!/usr/bin/env python3
"""The walls of stdlib/wall against their definitions, in 1, 2 and 3 dims.

    walls_check.py REFLECT_1D BOUNCE_1D REFLECT_2D BOUNCE_2D REFLECT_3D BOUNCE_3D

Each plane is dot(n, p) = 0.3, n = facing / |facing| with facing (1),
(3, 4) and (1, 2, 2) (wall_reflect.part.in, wall_bounce.part.in).
- wall.reflect: 20 particles on a line across the plane, one step of
  Euler-Maruyama with D = 0: a particle behind the plane (z < 0) is at
  p0 - 2 z n, bit for bit as that arithmetic gives it here, and in front of
  it; the others have not moved. Then 500 steps of Brownian motion (D = 1,
  dt = 1e-3): no particle is behind the plane after any step.
- wall.lj93 and velocity Verlet: three particles meet the wall at speeds
  0.5, 1 and 2 and leave it. The largest energy error of the run over the
  energy (2.625) is below 1e-4 at dt = 1e-3 (measured: 2.6e-5) and falls 3.5-4.5x when dt
  halves (second order); each particle leaves at its speed (to 1e-3),
  moving away along n.
"""
import csv
import math
import subprocess
import sys
import tempfile
from pathlib import Path

FACING = {1: (1.0,), 2: (3.0, 4.0), 3: (1.0, 2.0, 2.0)}
AT = 0.3
SPEEDS = (0.5, 1.0, 2.0)


def run(program, folder, args):
    name = Path(program).name
    log, out = Path(folder) / f"{name}_log.csv", Path(folder) / f"{name}.csv"
    subprocess.run([program, *args, "--seed", "4", "--log", str(log), "--output", str(out),
                    "--quiet"], check=True)
    with open(log, newline="") as f:
        rows = list(csv.DictReader(f))
    with open(out, newline="") as f:
        return rows, list(csv.DictReader(f))


def unit(dim):
    length = math.sqrt(sum(c * c for c in FACING[dim]))
    return [c / length for c in FACING[dim]]


def dot(a, b):
    s = a[0] * b[0]
    for x, y in zip(a[1:], b[1:]):
        s += x * y
    return s


def check_reflect(program, dim, folder, failures):
    n = unit(dim)
    _, state = run(program, folder, ["--steps", "1"])
    mirrored = 0
    for row in state:
        p0 = [float(row[f"p0_{k}"]) for k in range(dim)]
        p = [float(row[f"p_{k}"]) for k in range(dim)]
        z = dot(n, p0) - AT
        expected = [x - 2 * min(z, 0) * c for x, c in zip(p0, n)]
        mirrored += z < 0
        if p != expected:
            failures.append(f"reflect {dim}D: id {row['id']} at {p}, not {expected}")
        if dot(n, p) - AT < 0:
            failures.append(f"reflect {dim}D: id {row['id']} is behind the plane")
    rows, _ = run(program, folder, ["--steps", "500", "--log-every", "1",
                                    "--set", "euler_maruyama.D=1"])
    behind = max(int(float(r["behind"])) for r in rows)
    print(f"reflect {dim}D: {mirrored} of {len(state)} mirrored exactly; "
          f"most behind the plane after any of 500 Brownian steps: {behind}")
    if mirrored == 0:
        failures.append(f"reflect {dim}D: no particle started behind the plane")
    if behind:
        failures.append(f"reflect {dim}D: {behind} particles behind the plane")


def bounce_error(program, dim, folder, dt, failures):
    steps = round(3 / dt)
    rows, state = run(program, folder, ["--steps", str(steps), "--log-every", "1",
                                        "--set", f"velocity_verlet.dt={dt}"])
    e0 = sum(0.5 * v * v for v in SPEEDS)
    worst = max(abs(float(r["energy"]) - e0) for r in rows if int(float(r["step"])) > 0) / e0
    n = unit(dim)
    for row in state:
        v = [float(row[f"v_{k}"]) for k in range(dim)]
        speed = SPEEDS[int(row["id"])]
        along = dot(n, v)
        if abs(along - speed) > 1e-3 * speed or abs(math.sqrt(dot(v, v)) - speed) > 1e-3 * speed:
            failures.append(f"bounce {dim}D, dt {dt}: id {row['id']} leaves at {v}, not {speed} n")
    return worst


def check_bounce(program, dim, folder, failures):
    coarse = bounce_error(program, dim, folder, 1e-3, failures)
    fine = bounce_error(program, dim, folder, 5e-4, failures)
    print(f"bounce {dim}D: largest energy error / energy {coarse:.2e} at dt = 1e-3, "
          f"{fine:.2e} at 5e-4 ({coarse / fine:.2f}x)")
    if coarse > 1e-4:
        failures.append(f"bounce {dim}D: energy error {coarse}")
    if not 3.5 < coarse / fine < 4.5:
        failures.append(f"bounce {dim}D: energy error falls {coarse / fine}x, not 4x")


def main():
    programs = sys.argv[1:]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        for dim in (1, 2, 3):
            check_reflect(programs[2 * dim - 2], dim, folder, failures)
            check_bounce(programs[2 * dim - 1], dim, folder, failures)
    if failures:
        sys.exit("\n".join(failures[:20]))


if __name__ == "__main__":
    main()
