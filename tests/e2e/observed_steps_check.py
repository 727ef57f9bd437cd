#!/usr/bin/env python3
"""What only the logged state needs is computed only on logged steps, and
that changes no value (tests/e2e/observed_steps.part).

    observed_steps_check.py PROGRAM

Runs the model twice with the same seed: logging every step, and logging
every 7th step (--log-file-every 7), which observes only those steps and the
last. The second log must be the first's rows of those steps, byte for byte,
and both final states the same bytes: the thermostat reads e_kin every step,
so e_kin must still be computed every step (a stale one would change the
velocities). The second run must walk neighbours fewer times, as its u[i]
(the pair energy) runs only on observed steps.
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path

EVERY, STEPS = 7, 70


def run(program, folder, name, extra):
    log, out = Path(folder) / f"{name}.csv", Path(folder) / f"{name}_out.csv"
    summary = subprocess.run([program, "--steps", str(STEPS), "--seed", "3", "--log", str(log),
                              "--output", str(out), "--log-every", "0", *extra],
                             check=True, capture_output=True, text=True).stdout
    walks = re.search(r"walked (\d+) times", summary)
    if not walks:
        sys.exit("no walk count in the summary:\n" + summary)
    return log.read_bytes(), out.read_bytes(), int(walks.group(1))


def main():
    program = sys.argv[1]
    with tempfile.TemporaryDirectory() as folder:
        every_log, every_out, every_walks = run(program, folder, "every", [])
        thin_log, thin_out, thin_walks = run(program, folder, "thin",
                                             ["--log-file-every", str(EVERY)])
    lines = every_log.decode().splitlines(keepends=True)
    expected = lines[0] + "".join(l for l in lines[1:] if int(l.split(",")[0]) % EVERY == 0)
    failures = []
    if thin_log != expected.encode():
        failures.append("the log of every 7th step differs from those rows of the full log:\n" +
                        thin_log.decode() + "\nexpected:\n" + expected)
    if thin_out != every_out:
        failures.append("the final states differ")
    if not thin_walks < every_walks:
        failures.append(f"observing every {EVERY}th step walked neighbours {thin_walks} times, "
                        f"every step {every_walks}: u[i] ran on every step")
    if failures:
        sys.exit("\n".join(failures))
    print(f"{STEPS // EVERY + 1} rows the same, final states the same; "
          f"walks {thin_walks} against {every_walks}")


if __name__ == "__main__":
    main()
