#!/usr/bin/env python3
"""wall.elastic, an elastic plane for inertial integrators, against the
analytic bounce and against the integrators' steps written out here.

    wall_elastic_check.py ELASTIC_1D ELASTIC_3D

ELASTIC_1D is symplectic Euler in 1D, ELASTIC_3D velocity Verlet in 3D on
the plane dot(n, p) = 0.3, n along (1, 2, 2) (wall_elastic_*d.part); each
logs a ball's height z above its plane, its normal velocity vn and its
energy every step (dt = 1e-3).
- Free flight (g = 0): the ball meets the plane at speed w (and, in 3D,
  slides along it at u) and leaves it at w: z = |h - w t| and vn = -w, then
  +w, every step; the energy and the sliding do not change; the final
  position is the analytic one (to 1e-12).
- A ball dropped under g (velocity Verlet) from h = g t*^2 / 2, t* = 400.5
  dt, so that it meets the plane in the middle of a step: the drift takes
  it dt/2 through, the mirror puts it back, and the second half kick then
  brings the normal velocity to the analytic one exactly, which leaves the
  ball g dt^2 / 4 above the analytic bounce until it meets the plane again:
  z = h - g t^2 / 2 up to the bounce, h - g (t - 2 t*)^2 / 2 + g dt^2 / 4
  after it (to 1e-10); its energy is up by g^2 dt^2 / 4.
- A ball dropped from h = 1 for 3000 steps (3 bounces): each step z and vn
  are those of the integrator and the wall's arithmetic done here on the
  normal coordinate (to 1e-9); under velocity Verlet each bounce changes
  the energy by at most g dt (|vn| + g dt), the energy of a mirror a step
  after the contact (and not at all between bounces).
"""
import csv
import math
import subprocess
import sys
import tempfile
from pathlib import Path

DT = 1e-3
G = 9.81


def run(program, folder, steps, settings):
    name = Path(program).name
    log, out = Path(folder) / f"{name}_log.csv", Path(folder) / f"{name}.csv"
    args = [program, "--steps", str(steps), "--log", str(log), "--log-every", "1",
            "--output", str(out), "--quiet"]
    for setting in settings:
        args += ["--set", setting]
    subprocess.run(args, check=True)
    with open(log, newline="") as f:
        # Row 0 is before the first step, which computes the observables.
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)][1:]
    with open(out, newline="") as f:
        return rows, list(csv.DictReader(f))


def worst(rows, expected, column):
    return max(abs(r[column] - expected(r)) for r in rows)


def check_free_flight(program, dim, folder, failures):
    h, w, u = 0.3505, 1.0, (0.5 if dim == 3 else 0.0)   # meets the plane mid-step
    settings = ["gravity.g=0", f"h={h!r}", f"w={w!r}"] + ([f"u={u!r}"] if dim == 3 else [])
    rows, state = run(program, folder, 1000, settings)
    t = lambda r: r["step"] * DT
    errors = {
        "z": worst(rows, lambda r: abs(h - w * t(r)), "height"),
        "vn": worst(rows, lambda r: -w if t(r) < h / w else w, "vn"),
        "energy": worst(rows, lambda r: 0.5 * (w * w + u * u), "energy"),
    }
    # The final position: 0.3 + z along n, and u t along the tangent (2, -1, 0) / sqrt(5).
    z_end = abs(h - w * 1.0)
    if dim == 3:
        n = [c / 3 for c in (1, 2, 2)]
        tangent = [c / math.sqrt(5) for c in (2, -1, 0)]
        expected = [(0.3 + z_end) * a + u * 1.0 * b for a, b in zip(n, tangent)]
    else:
        expected = [-(0.2 + z_end)]
    p = [float(state[0][f"p_{k}"]) for k in range(dim)]
    errors["p"] = max(abs(a - b) for a, b in zip(p, expected))
    print(f"elastic {dim}D, free flight through a bounce: worst errors "
          + ", ".join(f"{k} {e:.1e}" for k, e in errors.items()))
    for what, error in errors.items():
        if error > 1e-12:
            failures.append(f"elastic {dim}D, free flight: {what} off by {error:.2e}")


def check_mid_step_drop(program, folder, failures):
    t_hit = 400.5 * DT
    h = 0.5 * G * t_hit * t_hit
    rows, _ = run(program, folder, 1150, [f"h={h!r}"])

    def z(r):
        t = r["step"] * DT
        return h - 0.5 * G * t * t if t < t_hit else h - 0.5 * G * (t - 2 * t_hit) ** 2 + G * DT * DT / 4

    def vn(r):
        t = r["step"] * DT
        return -G * t if t < t_hit else -G * (t - 2 * t_hit)

    lift = G * G * DT * DT / 4
    errors = {"z": worst(rows, z, "height"), "vn": worst(rows, vn, "vn"),
              "energy": worst(rows, lambda r: G * h + (lift if r["step"] * DT > t_hit else 0),
                              "energy")}
    print(f"elastic 3D, a ball dropped {h:.4f} to meet the plane mid-step: worst errors "
          f"against the analytic bounce " + ", ".join(f"{k} {e:.1e}" for k, e in errors.items()))
    if rows[-1]["vn"] >= 0:
        failures.append("elastic 3D, mid-step drop: the run ends before the ball falls again")
    for what, error in errors.items():
        if error > 1e-10:
            failures.append(f"elastic 3D, mid-step drop: {what} off by {error:.2e}")


def reference(steps, h, verlet):
    """z and vn after each step: the integrator and the wall on the normal coordinate."""
    z, v, out = h, 0.0, [(h, 0.0)]
    for _ in range(steps):
        v += (0.5 if verlet else 1.0) * DT * -G
        z += DT * v
        if z < 0:
            v -= 2 * min(v, 0)
            z -= 2 * z
        if verlet:
            v += 0.5 * DT * -G
        out.append((z, v))
    return out


def check_drop(program, dim, folder, failures):
    verlet = dim == 3
    rows, _ = run(program, folder, 3000, ["h=1"])
    expected = reference(3000, 1.0, verlet)
    errors = {"z": max(abs(r["height"] - expected[int(r["step"])][0]) for r in rows),
              "vn": max(abs(r["vn"] - expected[int(r["step"])][1]) for r in rows)}
    bounces = sum(1 for a, b in zip(rows, rows[1:]) if a["vn"] < 0 < b["vn"])
    line = (f"elastic {dim}D, a ball dropped from 1: {bounces} bounces, worst errors against "
            f"the steps done here z {errors['z']:.1e}, vn {errors['vn']:.1e}")
    if bounces < 3:
        failures.append(f"elastic {dim}D, drop: {bounces} bounces, not 3")
    for what, error in errors.items():
        if error > 1e-9:
            failures.append(f"elastic {dim}D, drop: {what} off by {error:.2e}")
    if verlet:
        bound = G * DT * (max(abs(r["vn"]) for r in rows) + G * DT)
        done, drift = 0, 0.0
        for a, b in zip(rows, rows[1:]):
            change = abs(b["energy"] - a["energy"])
            if a["vn"] < 0 < b["vn"]:
                done += 1
                drift = max(drift, change / bound)
            elif change > 1e-12:
                failures.append(f"elastic 3D, drop: energy changes by {change:.2e} in flight")
        line += f"; each bounce changes the energy by at most {drift:.2f} of g dt (|vn| + g dt)"
        if drift > 1:
            failures.append(f"elastic 3D, drop: a bounce changes the energy by {drift} bounds")
    print(line)


def main():
    one, three = sys.argv[1:]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        check_free_flight(one, 1, folder, failures)
        check_free_flight(three, 3, folder, failures)
        check_mid_step_drop(three, folder, failures)
        check_drop(one, 1, folder, failures)
        check_drop(three, 3, folder, failures)
    if failures:
        sys.exit("\n".join(failures[:20]))


if __name__ == "__main__":
    main()
