#!/usr/bin/env python3
"""The pair walks of a run, from the driver's search report.

    check_walks.py PROGRAM STEPS PER_STEP AT_START

Runs PROGRAM for STEPS steps and asserts that the report lists at least one
search and that each was walked exactly PER_STEP * STEPS + AT_START times
(AT_START: the walks before the first step, as an integrator's primed
forces).
"""
import re
import subprocess
import sys


def main():
    program, steps, per_step, at_start = sys.argv[1], *map(int, sys.argv[2:5])
    out = subprocess.run([program, "--steps", str(steps)], check=True, capture_output=True,
                         text=True).stdout
    rows = re.findall(r"^  (.+?): (.*); built (\d+) times?, walked (\d+) times?$", out,
                      re.MULTILINE)
    if not rows:
        sys.exit("no search in the report:\n" + out)
    expected = per_step * steps + at_start
    for serves, structure, builds, walks in rows:
        print(f"{serves} ({structure}): built {builds}, walked {walks}; expected {expected}")
    if any(int(r[3]) != expected for r in rows):
        sys.exit("FAILED: a search walked other than expected")


if __name__ == "__main__":
    main()
