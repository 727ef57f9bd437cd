"""The table a model built with partc --profile prints after its run
(partc/profile.hpp's Profile::report), read back: for check_profile.py and
tests/bench/bench_profile.py."""
import re


def read_table(text):
    """(ms a step in step(), {row: (ms a step, the --drop column's text or "")}),
    or None when the text holds no table."""
    lines = text.splitlines()
    start = next((k for k, l in enumerate(lines) if l.startswith("profile: ")), None)
    if start is None:
        return None
    step_ms = float(re.search(r"([0-9.]+) ms a step in step\(\)", lines[start]).group(1))
    rows = {}
    for line in lines[start + 2:]:
        m = re.match(r"  (.+?)\s+([0-9.]+)\s+([0-9.]+)%(?:\s+(\S.*))?$", line)
        if not m:
            break
        rows[m.group(1)] = (float(m.group(2)), m.group(4) or "")
    return step_ms, rows
