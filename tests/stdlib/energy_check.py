#!/usr/bin/env python3
"""Checks that each pair effect's force is minus the gradient of its energy.

    energy_check.py BUILD_DIR NAME=ENERGY...

BUILD_DIR holds energy_NAME, a scene of one effect that logs its energy
observable ENERGY. From its initial state (written with --steps 0), each
coordinate of a few particles is moved by +-h and the energy read back
(--input runs the integrator's primed force slot on the state loaded):
the central difference -(E(x+h) - E(x-h)) / 2h must equal that component
of f to 1e-6 of the largest force (h = 1e-5: truncation error ~h^2 |E'''|,
rounding ~1e-16 |E| / h).
"""
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

H = 1e-5
PARTICLES = (0, 7, 101)


def run(program, folder, args):
    log = Path(folder) / "log.csv"
    out = Path(folder) / "out.csv"
    subprocess.run([str(program), "--steps", "0", "--seed", "3", "--log", str(log),
                    "--output", str(out), "--quiet", *args], check=True)
    with open(log, newline="") as f:
        energy_rows = list(csv.DictReader(f))
    with open(out, newline="") as f:
        state = list(csv.DictReader(f))
    return energy_rows[0], state


def write_state(rows, path):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)


def main():
    build, specs = Path(sys.argv[1]), sys.argv[2:]
    failures = []
    with tempfile.TemporaryDirectory() as folder:
        for spec in specs:
            name, energy = spec.split("=")
            program = build / f"energy_{name}"
            _, state = run(program, folder, [])
            scale = max(abs(float(r[f"f_{k}"])) for r in state for k in range(3))
            by_id = {int(r["id"]): r for r in state}
            worst = 0.0
            for pid in PARTICLES:
                for k in range(3):
                    energies = []
                    for sign in (1, -1):
                        moved = [dict(r) for r in state]
                        row = next(r for r in moved if int(r["id"]) == pid)
                        row[f"p_{k}"] = repr(float(row[f"p_{k}"]) + sign * H)
                        path = Path(folder) / "moved.csv"
                        write_state(moved, path)
                        log, _ = run(program, folder, ["--input", str(path)])
                        energies.append(float(log[energy]))
                    gradient = (energies[0] - energies[1]) / (2 * H)
                    worst = max(worst, abs(gradient + float(by_id[pid][f"f_{k}"])))
            print(f"{name}: worst |f + dE/dx| = {worst:.2e} of max |f| = {scale:.2e}")
            if scale == 0:
                failures.append(f"{name}: no force at all")
            if worst > 1e-6 * scale:
                failures.append(f"{name}: f differs from -grad {energy} by {worst:.2e}")
    if failures:
        sys.exit("\n".join(failures))
    print("every force is minus the gradient of its energy")


if __name__ == "__main__":
    main()
