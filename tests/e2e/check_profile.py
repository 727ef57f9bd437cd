#!/usr/bin/env python3
"""A model built with partc --profile against the same model built without.

usage: check_profile.py PLAIN PROFILED WORKDIR EFFECT[>FRACTION]...

Both run 50 steps on one thread. Their --output files must be identical
byte for byte (the timers and the calibration change no value), and the
profile's table must have a row per EFFECT with a predicted --drop saving,
no joint row (every kernel of several effects is split by the
calibration), rows that sum to the step time it states, and that time
within 5% of the driver's own clock around step(). EFFECT>FRACTION: that
effect's predicted saving must also exceed FRACTION of the step (a wide
bound: timings on a shared machine are noisy, so it checks a large effect,
such as a search radius the --drop build no longer needs)."""
import os
import re
import subprocess
import sys

from profile_table import read_table

plain, profiled, work = sys.argv[1:4]
effects = [arg.split(">")[0] for arg in sys.argv[4:]]
at_least = {arg.split(">")[0]: float(arg.split(">")[1]) for arg in sys.argv[4:] if ">" in arg}
os.makedirs(work, exist_ok=True)
env = dict(os.environ, OMP_NUM_THREADS="1")


def run(binary, name):
    out = os.path.join(work, name + ".csv")
    r = subprocess.run([binary, "--steps", "50", "--output", out], env=env, capture_output=True,
                       text=True, check=True)
    return out, r.stdout


plain_csv, _ = run(plain, "plain")
profiled_csv, text = run(profiled, "profiled")
failures = []
if open(plain_csv, "rb").read() != open(profiled_csv, "rb").read():
    failures.append("--output differs between the plain and the profiled build")

table = read_table(text)
if table is None:
    sys.exit("no profile table in the output:\n" + text)
step_ms, rows = table
clock = float(re.search(r"the driver's clock around step\(\): ([0-9.e+-]+) ms", text).group(1))

total = sum(ms for ms, _ in rows.values())
if abs(total - step_ms) > 0.05 * step_ms:
    failures.append(f"rows sum to {total} ms a step, the table says {step_ms}")
if abs(step_ms - clock) > 0.05 * clock:
    failures.append(f"the profile's step time {step_ms} ms is not within 5% of the driver's {clock}")
for name, (_, saving) in rows.items():
    if saving == "joint: not split":
        failures.append(f"joint row {name}: its kernel was not split")
for e in effects:
    if e not in rows:
        failures.append(f"no row for effect {e}")
    elif not re.match(r"-?[0-9.]+$", rows[e][1]):
        failures.append(f"effect {e} has no predicted --drop saving: {rows[e][1]}")
    elif e in at_least and float(rows[e][1]) <= at_least[e] * step_ms:
        failures.append(f"--drop {e} is predicted to save {rows[e][1]} ms a step, not over "
                        f"{at_least[e]:.0%} of the step's {step_ms} ms")

print(text[text.index("profile: "):])
if failures:
    sys.exit("\n".join(failures))
print(f"ok: output identical; {len(rows)} rows sum to {total:.4f} of {step_ms:.4f} ms "
      f"(driver {clock:.4f} ms)")
