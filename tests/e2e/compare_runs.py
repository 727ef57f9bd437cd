#!/usr/bin/env python3
"""Runs two generated models with the same arguments and checks that every
column of the first's final state is in the second's, with the same text:
the same numbers bit for bit (the driver writes 17 significant digits).

    compare_runs.py [--tolerance T] [--rename A=B]... [--ignore COLUMN]...
                    [--particles SET] PROGRAM_A PROGRAM_B [ARGS...]

--rename A=B gives PROGRAM_B "--set B=VALUE" where PROGRAM_A gets
"--set A=VALUE" (a model's parameter g is its scene's gravity.g).
--ignore COLUMN leaves out a column of PROGRAM_A that PROGRAM_B does not
store (a value its scene computes where it is used); for a vector, all
its components (--ignore f leaves out f_0, f_1, f_2).
--particles SET compares the set SET of a model of several sets (whose
driver writes one file per set, OUTPUT_SET.csv).
With --tolerance, values may differ by T times the largest magnitude of
their column instead (for two models that sum the same terms in another
order). Used for scenes against the single-file models they reproduce: the
scene may store more (its force channel), never different values.
"""
import csv
import re
import subprocess
import sys
import tempfile
from pathlib import Path


def final_state(program, args, folder, particles):
    out = Path(folder) / (Path(program).name + ".csv")
    subprocess.run([program, *args, "--output", str(out), "--quiet"], check=True)
    if particles:
        out = out.with_name(f"{out.stem}_{particles}.csv")
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{program} wrote no particles")
    return rows


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    argv = sys.argv[1:]
    tolerance = 0.0
    renames = {}
    ignored = set()
    particles = None
    while argv and argv[0] in ("--tolerance", "--rename", "--ignore", "--particles"):
        if argv[0] == "--tolerance":
            tolerance = float(argv[1])
        elif argv[0] == "--ignore":
            ignored.add(argv[1])
        elif argv[0] == "--particles":
            particles = argv[1]
        else:
            name_a, _, name_b = argv[1].partition("=")
            renames[name_a] = name_b
        argv = argv[2:]
    a, b, args = argv[0], argv[1], argv[2:]
    args_b = []
    for arg in args:
        name, equals, value = arg.partition("=")
        args_b.append(renames[name] + equals + value if equals and name in renames else arg)
    with tempfile.TemporaryDirectory() as folder:
        rows_a = final_state(a, args, folder, particles)
        rows_b = final_state(b, args_b, folder, particles)
    if len(rows_a) != len(rows_b):
        sys.exit(f"{len(rows_a)} particles against {len(rows_b)}")
    columns = [c for c in rows_a[0].keys() if re.sub(r"_[0-9]+$", "", c) not in ignored
               and c not in ignored]
    missing = [c for c in columns if c not in rows_b[0]]
    if missing:
        sys.exit(f"{b} does not write {missing}")
    by_id = {row["id"]: row for row in rows_b}
    scale = {c: max(abs(float(row[c])) for row in rows_a) for c in columns}
    differ = 0
    for row in rows_a:
        other = by_id[row["id"]]
        for c in columns:
            same = row[c] == other[c] if tolerance == 0 else \
                abs(float(row[c]) - float(other[c])) <= tolerance * scale[c]
            if not same:
                if differ < 5:
                    print(f"id {row['id']}, {c}: {row[c]} against {other[c]}")
                differ += 1
    if differ:
        sys.exit(f"{differ} values differ")
    print(f"{len(rows_a)} particles, columns {', '.join(columns)}: " +
          ("identical" if tolerance == 0 else f"equal to {tolerance} of each column's largest"))


if __name__ == "__main__":
    main()
