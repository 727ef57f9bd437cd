#!/usr/bin/env python3
"""force.gravity and force.gravity_acceleration on free particles, against
their trajectories computed here, in 1, 2 and 3 dims.

    gravity_check.py PARTC GRAVITY_1D GRAVITY_2D GRAVITY_3D SCENE_3D

- 3D (gravity_3d.part): force.gravity with its default down, -z, under
  velocity Verlet, which is exact for a constant force: after 100 steps of
  0.01 each particle is on its parabola p0 + v0 t - g t^2 / 2 e_z and moves
  at v0 - g t e_z (to 1e-12 of the largest coordinate: rounding only).
  weight is the sum of m g.
- 2D (gravity_2d.part): down = (3, -4), normalised to n = (0.6, -0.8), on
  particles of different masses under symplectic Euler with masses: after
  n steps v = v0 + n dt g n, p = p0 + n dt v0 + n (n + 1) / 2 dt^2 g n
  (the integrator's discrete trajectory, whatever the mass).
- 1D (gravity_1d.part): force.gravity_acceleration, down = (-0.5), on SPH's
  acceleration channel: the same discrete trajectory, along -1.
- const g = 0 at the use line of SCENE_3D folds gravity's terms of f and
  of weight away (partc --explain=json lists them under folded); a g that
  is not const folds nothing.
"""
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

STEPS = 100
DT = 0.01


def run(program, folder, logs=True):
    """The log's rows (if the model logs observables) and the final state."""
    name = Path(program).name
    log, out = Path(folder) / f"{name}_log.csv", Path(folder) / f"{name}.csv"
    subprocess.run([program, "--steps", str(STEPS), "--output", str(out), "--quiet"]
                   + (["--log", str(log)] if logs else []), check=True)
    rows = []
    if logs:
        with open(log, newline="") as f:
            rows = list(csv.DictReader(f))
    with open(out, newline="") as f:
        return rows, list(csv.DictReader(f))


def vector(row, name, dim):
    return [float(row[f"{name}_{k}"]) for k in range(dim)]


def initial_3d(i):
    return [0.1 * i, -0.2 * i, 0.3 + 0.05 * i], [0.5 - 0.25 * i, 0.125 * i, 1 - 0.5 * i]


def initial_2d(i):
    return [0.1 * i, 0.5 - 0.2 * i], [0.25 * i - 0.5, 0.75 - 0.125 * i]


def initial_1d(i):
    return [0.2 * i], [1 - 0.75 * i]


def compare(what, state, dim, expected, failures):
    """expected(id) -> (p, v); every component to 1e-12 of the largest."""
    scale = max(abs(c) for row in state for name in ("p", "v") for c in vector(row, name, dim))
    worst = 0.0
    for row in state:
        p, v = expected(int(row["id"]))
        got_p, got_v = vector(row, "p", dim), vector(row, "v", dim)
        worst = max(worst, *(abs(a - b) for a, b in zip(got_p + got_v, p + v)))
    print(f"{what}: {len(state)} particles after {STEPS} steps, worst |error| {worst:.2e} "
          f"of {scale:.2e}")
    if worst > 1e-12 * scale:
        failures.append(f"{what}: trajectories off by {worst:.2e}")


def check_3d(program, folder, failures):
    g, t = 9.81, STEPS * DT
    rows, state = run(program, folder)

    def parabola(i):
        p0, v0 = initial_3d(i)
        return ([p0[0] + v0[0] * t, p0[1] + v0[1] * t, p0[2] + v0[2] * t - 0.5 * g * t * t],
                [v0[0], v0[1], v0[2] - g * t])

    compare("gravity 3D, velocity Verlet", state, 3, parabola, failures)
    weight = float(rows[-1]["weight"])
    if abs(weight - len(state) * 2 * g) > 1e-12 * weight:
        failures.append(f"gravity 3D: weight {weight}, not {len(state) * 2 * g}")


def discrete(initial, a):
    """Symplectic Euler's trajectory under a constant acceleration a."""
    n = STEPS

    def at(i):
        p0, v0 = initial(i)
        return ([x + n * DT * u + n * (n + 1) / 2 * DT * DT * c for x, u, c in zip(p0, v0, a)],
                [u + n * DT * c for u, c in zip(v0, a)])
    return at


def check_2d(program, folder, failures):
    g = 3
    rows, state = run(program, folder)
    compare("gravity 2D along (3, -4), symplectic Euler with masses", state, 2,
            discrete(initial_2d, [0.6 * g, -0.8 * g]), failures)
    mass = sum(float(row["m"]) for row in state)
    weight = float(rows[-1]["weight"])
    if abs(weight - mass * g) > 1e-12 * weight:
        failures.append(f"gravity 2D: weight {weight}, not {mass * g}")


def check_1d(program, folder, failures):
    _, state = run(program, folder, logs=False)
    compare("gravity_acceleration 1D along (-0.5), SPH's symplectic Euler", state, 1,
            discrete(initial_1d, [-2.0]), failures)


def folded(partc, scene):
    out = subprocess.run([partc, str(scene), "--explain=json"], check=True,
                         capture_output=True, text=True).stdout
    return [(t["effect"], t["target"]) for t in json.loads(out)["folded"]]


def check_folding(partc, scene, folder, failures):
    text = Path(scene).read_text()
    use = "use force.gravity(g = 9.81) on P"
    if use not in text:
        sys.exit(f"{scene} has no line {use}")
    zero = Path(folder) / "gravity_folded.part"
    zero.write_text(text.replace(use, "use force.gravity(const g = 0) on P"))
    terms, kept = folded(partc, zero), folded(partc, scene)
    print(f"const g = 0 folds {terms}; g = 9.81 folds {kept}")
    # Each term twice: in the force slot velocity Verlet primes after init, and in the step.
    if sorted(terms) != [("gravity", "P.f"), ("gravity", "P.f"),
                         ("gravity", "weight"), ("gravity", "weight")]:
        failures.append(f"const g = 0: folded {terms}, not gravity's f and weight")
    if kept:
        failures.append(f"g = 9.81: folded {kept}")


def main():
    partc, one, two, three, scene = sys.argv[1:]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        check_1d(one, folder, failures)
        check_2d(two, folder, failures)
        check_3d(three, folder, failures)
        check_folding(partc, scene, folder, failures)
    if failures:
        sys.exit("\n".join(failures))


if __name__ == "__main__":
    main()
