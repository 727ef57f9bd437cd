#!/usr/bin/env python3
"""Checks the standard library's force and constraint effects alone and in pairs.

    compose_check.py BUILD_DIR EFFECT...

BUILD_DIR holds compose_A (one effect) and compose_A_B (two) for the
effects named, built from compose.part.in. Each runs 0 steps: the
integrator's primed force slot leaves the forces of the initial state in f.
  - pair forces obey Newton's third law: the total force is 0 (to 1e-12
    of the sum of magnitudes);
  - the forces of A and B together are the forces of A plus those of B
    (to 1e-12 of the largest), in every component of every particle: the
    merged channel adds what each effect adds alone, and one effect's
    noise does not change when another is used.
A constraint (wall.elastic) contributes no force: alone, its f is 0, and
with another effect the forces are that effect's. What it does is checked
after one step instead: its plane z = 0.55 cuts the lowest layer, and the
positions are those of the run without it (the other effect alone, or free
flight p + dt v from the initial state), mirrored through the plane where
they are behind it; some are, and none is left behind.
"""
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

PAIR_FORCES = {"soft_exp", "lj", "wca", "coulomb", "spring_dashpot"}
# Each constraint's plane z = at, facing +z, as its use line in
# tests/stdlib/CMakeLists.txt places it; and compose.part.in's dt.
CONSTRAINTS = {"elastic": 0.55}
DT = 0.001


def state(program, folder, steps):
    """Each particle's row (id -> column -> value) after `steps` steps."""
    out = Path(folder) / f"{program.name}_{steps}.csv"
    subprocess.run([str(program), "--steps", str(steps), "--seed", "11", "--output", str(out),
                    "--quiet"], check=True)
    with open(out, newline="") as f:
        return {int(row["id"]): {k: float(v) for k, v in row.items()} for row in csv.DictReader(f)}


def forces(program, folder):
    return {i: [row[f"f_{k}"] for k in range(3)] for i, row in state(program, folder, 0).items()}


def positions(rows):
    return {i: [row[f"p_{k}"] for k in range(3)] for i, row in rows.items()}


def check_constraint(name, at, run, free, failures):
    """After one step, `run` (with the constraint) has the positions `free`
    (without it) mirrored through the plane z = at where they are behind it."""
    worst, mirrored, behind = 0.0, 0, 0
    for i, p in free.items():
        want = p[:2] + [p[2] - 2 * min(p[2] - at, 0)]
        mirrored += p[2] < at
        behind += run[i][2] < at
        worst = max(worst, max(abs(run[i][k] - want[k]) for k in range(3)))
    print(f"  {name}: {mirrored} mirrored, {behind} behind the plane after, "
          f"worst |p - mirrored p_free| = {worst:.2e}")
    if mirrored == 0:
        failures.append(f"{name}: no particle reached the plane (the check would be empty)")
    if behind or worst > 1e-12:
        failures.append(f"{name}: {behind} behind the plane, positions off by {worst:.2e}")


def main():
    build, names = Path(sys.argv[1]), sys.argv[2:]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        alone = {n: forces(build / f"compose_{n}", folder) for n in names}
        for n, f in alone.items():
            scale = max(abs(c) for v in f.values() for c in v)
            if n in CONSTRAINTS and scale != 0:
                failures.append(f"{n}: a constraint with a force of {scale:.2e}")
            if n not in CONSTRAINTS and scale == 0:
                failures.append(f"{n}: no force at all (the check would be of zeros)")
            if n in PAIR_FORCES:
                total = [sum(v[k] for v in f.values()) for k in range(3)]
                magnitude = sum(abs(c) for v in f.values() for c in v)
                print(f"{n}: total force {total} of {magnitude:.3e}")
                if max(abs(t) for t in total) > 1e-12 * magnitude:
                    failures.append(f"{n}: total force {total}, not 0 (Newton's third law)")
        for a_index, a in enumerate(names):
            for b in names[a_index + 1:]:
                together = forces(build / f"compose_{a}_{b}", folder)
                scale = max(abs(c) for i in together for c in together[i])
                worst = max(abs(together[i][k] - alone[a][i][k] - alone[b][i][k])
                            for i in together for k in range(3))
                print(f"{a} + {b}: worst |f_ab - f_a - f_b| = {worst:.2e} of {scale:.2e}")
                if worst > 1e-12 * scale:
                    failures.append(f"{a} + {b}: forces differ from the sum by {worst:.2e}")
        for c, at in CONSTRAINTS.items():
            if c not in names:
                continue
            print(f"{c} after one step:")
            start = state(build / f"compose_{c}", folder, 0)
            free = {i: [row[f"p_{k}"] + DT * row[f"v_{k}"] for k in range(3)]
                    for i, row in start.items()}
            check_constraint(c, at, positions(state(build / f"compose_{c}", folder, 1)), free,
                             failures)
            for other in names:
                if other == c:
                    continue
                pair = "_".join(sorted((c, other), key=names.index))
                check_constraint(f"{other} + {c}", at,
                                 positions(state(build / f"compose_{pair}", folder, 1)),
                                 positions(state(build / f"compose_{other}", folder, 1)), failures)
    if failures:
        sys.exit("\n".join(failures))
    print("every pair composes: forces together equal the sum of each alone")


if __name__ == "__main__":
    main()
