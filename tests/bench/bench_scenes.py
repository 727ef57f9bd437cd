#!/usr/bin/env python3
"""Scenes against the hand-written models they reproduce, in one run.

    bench_scenes.py EXAMPLES_BUILD_DIR [PARTC]

examples/scenes/md.part (symplectic Euler + the soft exponential force,
from stdlib/) against examples/md.part (one statement for v, one for p),
N = 1e3 ... 1e6; and examples/scenes/lj_melt.part (velocity Verlet + LJ)
against examples/lj_melt.part, 32000 atoms. Both programs of a pair run
alternately, 3 rounds, one thread; the figure is the run time the driver
reports (the steps, not init), the median of the rounds. The issue's target:
a scene within 1.05x of the hand-written model.

With PARTC, also partc's own time on the LJ melt scene with the standard
library as it is and with 2000 more (unused) modules beside it: it should
grow with the effects used, not with the size of the library.
"""
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROUNDS = 3


def seconds(program, args):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out = subprocess.run([str(program), *args], env=env, check=True, capture_output=True,
                         text=True).stdout
    match = re.search(r"(\d+) steps, seed \d+, ([0-9.e+-]+) s", out)
    if not match:
        sys.exit(f"{program}: no timing in its summary:\n{out}")
    return float(match.group(2))


def compare(label, hand, scene, args):
    times = {hand: [], scene: []}
    for _ in range(ROUNDS):
        for program in (hand, scene):
            times[program].append(seconds(program, args))
    a, b = statistics.median(times[hand]), statistics.median(times[scene])
    print(f"{label:<28} {a:>10.4f} {b:>10.4f} {b / a:>8.3f}")


def main():
    build = Path(sys.argv[1])
    print(f"{'model':<28} {'hand (s)':>10} {'scene (s)':>10} {'ratio':>8}")
    for n, steps in ((1000, 2000), (10000, 200), (100000, 20), (1000000, 4)):
        compare(f"md N={n}, {steps} steps", build / "md", build / "md_scene",
                ["--set", f"N={n}", "--steps", str(steps), "--seed", "1"])
    compare("lj_melt 32000, 100 steps", build / "lj_melt", build / "lj_melt_scene",
            ["--steps", "100", "--seed", "1"])
    if len(sys.argv) > 2:
        library_size(sys.argv[2])


def library_size(partc):
    root = Path(__file__).resolve().parents[2]
    scene = root / "examples" / "scenes" / "lj_melt.part"
    with tempfile.TemporaryDirectory() as folder:
        big = Path(folder) / "stdlib"
        shutil.copytree(root / "stdlib", big)
        for k in range(2000):
            (big / "extra").mkdir(exist_ok=True)
            (big / "extra" / f"effect_{k}.part").write_text(
                f"module extra.effect_{k}\neffect effect_{k}(a: real = 1) on P {{\n"
                f"  contributes f: vec\n  at force: f[i] += a * sum(j, |dx| < 1 and |dx| > 0, dx)\n}}\n")
        times = {"as it is": [], "with 2000 modules more": []}
        for _ in range(5):
            for label, extra in (("as it is", []), ("with 2000 modules more", ["--stdlib", str(big)])):
                start = time.perf_counter()
                subprocess.run([partc, str(scene), "-o", str(Path(folder) / "out.cpp"), *extra],
                               check=True)
                times[label].append(time.perf_counter() - start)
        for label, values in times.items():
            print(f"partc on scenes/lj_melt.part, stdlib {label}: {statistics.median(values):.3f} s")


if __name__ == "__main__":
    main()
