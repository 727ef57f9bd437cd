#!/usr/bin/env python3
"""What precision costs and buys: the schedule's precision choices (under
Schedules in the README) measured on the seed model's velocity update and on
the fast sum, each an error against a stated reference and a time.

  /usr/bin/python3 examples/accuracy/precision.py [--small]
      [--build-dir DIR | --partc PARTC] [--program NAME=EXE ...]
      [--work DIR] [--repeats K] [--out DIR] [--replot] [--expect-shape]

The seed: tests/accuracy/seed_precision (CMake's target seed_precision; its
head comment says what it measures) runs the seed update as partc emits it
under four schedules - double; precision = float (real and vec variables,
positions included, stored as float, computed in double); arithmetic =
float (the pair terms on float lanes, added into double sums); both - on the
same 10^4, 10^5 and 10^6 uniform points (doubles) of the periodic unit
square. The reference is independent of partc: the seed sum in long double
(tests/bench/seed_reference.hpp) on the points as given, so float storage's
error includes what rounding the positions to float moves the force (the
force jumps to 0 at the cutoff: a pair moved across rc is a whole term
wrong, counted in cutoff_flips); rms_stored is the error against the same
reference on the points as the build stores them, the update's own error.
The time is one update's, median of --repeats (5) timings, one thread.

The fast sum: examples/accuracy/fast_sum_tol.part (a Coulomb potential of N
= 2 10^4 charges in [0.5, 1.5) in the unit cube, dense = fmm) over its tol
(1e-3 ... 1e-9), built with double storage and with `--schedule 'precision =
float'`. The fast multipole method computes in double whatever the storage
(runtime/partc/fast_sum/: the positions and charges are widened as they are
read, and the result is rounded once when it is stored); it has no float
arithmetic, and `arithmetic = float` does not apply to a fast sum (the pair
terms it puts on float lanes are those of neighbourhood sums), so the fast
sum is swept over storage and tol only. The reference is the direct sum in
double on the positions and charges as drawn (the double build's
direct_phi, matched by id through --output; both builds draw the same
doubles from the same seed, the float one then rounds them); rms_stored is
the model's own error_l2, against its direct sum of the values as stored
(held in double). The time is the fast sum's plan and evaluation, as the
run's summary prints it, median of --repeats (3) runs, one thread.

--small (the CI's): the seed at 10^4 only, one timing; the fast sum at N =
4000 for tol 1e-3, 1e-6 and 1e-9, one run each. A few seconds.

Output, in --out (default examples/images/accuracy): precision_seed.csv
(schedule, rms_error, max_error, wall_time_s, threads, commit, then n,
rms_stored, cutoff_flips) and precision_fast_sum.csv (tol, rms_error,
max_error, wall_time_s, threads, commit, then precision, n, order,
rms_stored): sweep.py's columns, the knob first, wall_time_s the time said
above; rms_error is a relative L2 error, max_error the largest point's error
relative to the largest value. precision.png: error against time, the seed
on the left (a colour per N, each point labelled with its schedule), the
fast sum on the right (a line per storage, each point labelled with its
tol); filled markers against the reference on the values as given, open
ones on the values as stored.

The shape, checked always and made a test by --expect-shape (exit 4 and
"expectation failed: ..." when it does not hold); nothing about time:
  - seed: double within 1e-13 of long double; arithmetic = float between
    1e-9 (float lanes ran) and 2e-7 (issue 11's bound); precision = float on
    its stored points between 1e-9 and 1e-7 (one rounding of v to float),
    and on the given points above that; both within 2e-7 on its stored points;
  - fast sum: double's error within tol everywhere and falling as tol falls
    (flat only at rounding's floor, 1e-13); float storage's at the loosest
    tol within 10% of double's (the method's error dominates), and at the
    tightest between 1e-8 and 1e-7 against both references while double's is
    below 1e-8 (float's rounding floors it).
Programs: seed_precision by --program seed_precision=EXE, else
BUILD_DIR/tests/accuracy/seed_precision; the fast sum's by --program
fast_sum_tol=EXE and fast_sum_tol_float=EXE, else built by examples/sweep.py's
build_program from partc (--build-dir or --partc, else the newest
build*/compiler/partc). Exit status: 0 done, 2 bad command line, 3 a build or
run failed, 4 an expectation failed.
"""
import argparse
import csv
import math
import os
import re
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import sweep  # noqa: E402  (examples/sweep.py: building, running, reading logs)

REPO = os.path.dirname(os.path.dirname(HERE))

PLANS = {
    "full": dict(seed_n=[10000, 100000, 1000000], seed_repeats=5, fast_n=20000,
                 tols=["1e-3", "1e-4", "1e-5", "1e-6", "1e-7", "1e-8", "1e-9"], fast_repeats=3),
    "small": dict(seed_n=[10000], seed_repeats=1, fast_n=4000, tols=["1e-3", "1e-6", "1e-9"],
                  fast_repeats=1),
}
# The fast sum's two builds: their names for --program, and partc's flags.
STORAGES = {"double": ("fast_sum_tol", []),
            "precision = float": ("fast_sum_tol_float", ["--schedule", "precision = float"])}
# The seed's schedules as seed_precision names them, and as the picture does.
SCHEDULES = {"double": "double", "precision = float": "float storage",
             "arithmetic = float": "float arithmetic",
             "precision = float, arithmetic = float": "both"}
# Float storage and both sit on one another: one label above, one below.
LABEL_OFFSETS = {"double": (5, 3), "precision = float": (5, 5),
                 "arithmetic = float": (5, 5), "precision = float, arithmetic = float": (5, -11)}
SEED_COLUMNS = ["schedule", "rms_error", "max_error", "wall_time_s", "threads", "commit", "n",
                "rms_stored", "cutoff_flips"]
FAST_COLUMNS = ["tol", "rms_error", "max_error", "wall_time_s", "threads", "commit",
                "precision", "n", "order", "rms_stored"]
THREADS = 1
FAST_SUM_LINE = re.compile(r"^sum at \S+: fmm order (\d+) for tol [^,]+, .*; 1 evaluation, "
                           r"(\S+) s$", re.M)


# ---------------------------------------------------------------------------
# Running.


def seed_rows(program, plan, work):
    """seed_precision's rows, at the plan's sizes."""
    table = os.path.join(work, "seed_precision.csv")
    command = [program, "--n", ",".join(str(n) for n in plan["seed_n"]),
               "--repeats", str(plan["seed_repeats"]), "--csv", table]
    print(f"== {' '.join(command)}", flush=True)
    result = sweep.run_checked(command, "seed_precision")
    print(result.stdout, end="", flush=True)
    rows = []
    with open(table, newline="") as f:
        for line in csv.DictReader(f):
            rows.append(dict(schedule=line["schedule"], rms_error=float(line["rms_error"]),
                             max_error=float(line["max_error"]),
                             wall_time_s=float(line["update_s"]), n=int(line["n"]),
                             rms_stored=float(line["rms_stored"]),
                             cutoff_flips=int(line["cutoff_flips"])))
    return rows


def read_potentials(path):
    """{id: (fast_phi, direct_phi)} from a run's --output table."""
    with open(path, newline="") as f:
        return {line["id"]: (float(line["fast_phi"]), float(line["direct_phi"]))
                for line in csv.DictReader(f)}


def fast_sum_run(program, n, tol, work, tag):
    """One run: the fast sum's order and seconds (its summary line), the
    model's own errors (its log), and every particle's potentials."""
    log = os.path.join(work, f"fast_sum_tol-{tag}-{n}-{tol}.log.csv")
    out = os.path.join(work, f"fast_sum_tol-{tag}-{n}-{tol}.csv")
    command = [program, "--steps", "0", "--set", f"N={n}", "--set", f"tol={tol}", "--log", log,
               "--log-every", "0", "--output", out]
    result = sweep.run_checked(command, os.path.basename(program),
                               env=dict(os.environ, OMP_NUM_THREADS=str(THREADS)))
    line = FAST_SUM_LINE.search(result.stdout)
    if not line:
        raise sweep.SweepError(f"{' '.join(command)}: no 'sum at ...: fmm order K for tol ..., "
                               f"1 evaluation, T s' line in its summary:\n{result.stdout}")
    row = sweep.read_row(log, None)
    return dict(order=int(line.group(1)), seconds=float(line.group(2)),
                rms_stored=float(sweep.observable(row, "error_l2")[0]),
                potentials=read_potentials(out))


def relative_errors(values, reference):
    """The relative L2 error of values against reference (both {id: value})
    and the largest error relative to the largest |reference|, as the model's
    error_l2 and error_max."""
    error = sum((values[k] - r) ** 2 for k, r in reference.items())
    norm = sum(r * r for r in reference.values())
    largest = max(abs(values[k] - r) for k, r in reference.items())
    return math.sqrt(error / norm), largest / max(abs(r) for r in reference.values())


def fast_sum_rows(programs, plan, work):
    n, rows, reference = plan["fast_n"], [], None
    for precision in STORAGES:
        for tol in plan["tols"]:
            runs = [fast_sum_run(programs[precision], n, tol, work, STORAGES[precision][0])
                    for _ in range(plan["fast_repeats"])]
            run = runs[0]
            if reference is None:  # the double build's first run: the drawn values, in double
                reference = {k: direct for k, (_, direct) in run["potentials"].items()}
            fast = {k: value for k, (value, _) in run["potentials"].items()}
            if fast.keys() != reference.keys():
                raise sweep.SweepError(f"the {precision} build holds other particles than the "
                                       f"double one")
            rms, largest = relative_errors(fast, reference)
            rows.append(dict(tol=tol, rms_error=rms, max_error=largest,
                             wall_time_s=statistics.median(r["seconds"] for r in runs),
                             precision=precision, n=n, order=run["order"],
                             rms_stored=run["rms_stored"]))
            print(f"precision: fast sum, {precision}, tol {tol}: order {run['order']}, "
                  f"{rms:.3e} ({run['rms_stored']:.3e} as stored), "
                  f"{rows[-1]['wall_time_s']:.3g} s", flush=True)
    return rows


def programs_for(args):
    given = dict(p.split("=", 1) for p in args.program)
    known = {"seed_precision"} | {name for name, _ in STORAGES.values()}
    unknown = set(given) - known
    if unknown:
        raise sweep.SweepError(f"--program for an unknown name: {', '.join(sorted(unknown))} "
                               f"(known: {', '.join(sorted(known))})")
    partc = None
    if not all(name in given for name, _ in STORAGES.values()) or "seed_precision" not in given:
        partc = os.path.abspath(args.partc) if args.partc else sweep.find_partc(args.build_dir)
    programs = {}
    for precision, (name, flags) in STORAGES.items():
        programs[precision] = given.get(name) or sweep.build_program(
            os.path.join(HERE, "fast_sum_tol.part"), partc, flags, args.work,
            "-O2 -march=native -ffp-contract=off")
    seed = given.get("seed_precision") or os.path.join(
        os.path.dirname(os.path.dirname(partc)), "tests", "accuracy", "seed_precision")
    if not os.access(seed, os.X_OK):
        raise sweep.SweepError(f"no seed_precision at {seed}: build it (cmake --build BUILD_DIR "
                               f"--target seed_precision) or pass --program seed_precision=EXE")
    programs["seed"] = seed
    return programs


# ---------------------------------------------------------------------------
# Tables.


def write_table(path, columns, rows, commit):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(columns)
        for r in rows:
            r = dict(r, threads=THREADS, commit=commit)
            writer.writerow([f"{r[c]:.6e}" if isinstance(r[c], float) else r[c]
                             for c in columns])
    print(f"precision: table {path}")


def read_table(path, numbers):
    rows = []
    with open(path, newline="") as f:
        for line in csv.DictReader(f):
            rows.append({k: (float(v) if k in numbers else int(v) if v.isdigit() else v)
                         for k, v in line.items()})
    return rows


def print_tables(seed, fast):
    print(f"{'N':>8} {'schedule':>38} {'rms_error':>10} {'max_error':>10} {'rms_stored':>10} "
          f"{'flips':>5} {'update_s':>10}")
    for r in seed:
        print(f"{r['n']:>8} {r['schedule']:>38} {r['rms_error']:>10.3e} {r['max_error']:>10.3e} "
              f"{r['rms_stored']:>10.3e} {r['cutoff_flips']:>5} {r['wall_time_s']:>10.3e}")
    print(f"{'precision':>18} {'N':>6} {'tol':>6} {'order':>5} {'rms_error':>10} "
          f"{'max_error':>10} {'rms_stored':>10} {'fast_sum_s':>10}")
    for r in fast:
        print(f"{r['precision']:>18} {r['n']:>6} {r['tol']:>6} {r['order']:>5} "
              f"{r['rms_error']:>10.3e} {r['max_error']:>10.3e} {r['rms_stored']:>10.3e} "
              f"{r['wall_time_s']:>10.3g}")


# ---------------------------------------------------------------------------
# The shape.


def check_shape(seed, fast):
    """The failed expectations (see the docstring)."""
    failures = []
    for r in seed:
        what = f"seed N = {r['n']}, {r['schedule']}"
        if r["schedule"] == "double" and not r["rms_error"] < 1e-13:
            failures.append(f"{what}: {r['rms_error']:.2e} from long double, not within 1e-13")
        if r["schedule"] == "arithmetic = float" and not 1e-9 < r["rms_error"] <= 2e-7:
            failures.append(f"{what}: {r['rms_error']:.2e} outside (1e-9, 2e-7]")
        if r["schedule"] == "precision = float":
            if not 1e-9 < r["rms_stored"] <= 1e-7:
                failures.append(f"{what}: {r['rms_stored']:.2e} on its stored points, outside "
                                f"(1e-9, 1e-7]")
            if not r["rms_error"] > r["rms_stored"]:
                failures.append(f"{what}: {r['rms_error']:.2e} on the given points, not above "
                                f"{r['rms_stored']:.2e} on its stored ones")
        if r["schedule"] == "precision = float, arithmetic = float" and not r["rms_stored"] <= 2e-7:
            failures.append(f"{what}: {r['rms_stored']:.2e} on its stored points, above 2e-7")

    by_storage = {p: sorted((r for r in fast if r["precision"] == p), key=lambda r: -float(r["tol"]))
                  for p in STORAGES}
    double, single = by_storage["double"], by_storage["precision = float"]
    for r in double:
        if not r["rms_error"] <= float(r["tol"]):
            failures.append(f"fast sum, double, tol {r['tol']}: measured {r['rms_error']:.2e}")
    for a, b in zip(double, double[1:]):
        if not (b["rms_error"] < a["rms_error"] or b["rms_error"] < 1e-13 or b["order"] == a["order"]):
            failures.append(f"fast sum, double: the error does not fall from tol {a['tol']} "
                            f"({a['rms_error']:.2e}) to {b['tol']} ({b['rms_error']:.2e})")
    if double and single:
        loose, loose_float = double[0], single[0]
        if not abs(loose_float["rms_error"] - loose["rms_error"]) <= 0.1 * loose["rms_error"]:
            failures.append(f"fast sum, tol {loose['tol']}: float storage's {loose_float['rms_error']:.2e} "
                            f"not within 10% of double's {loose['rms_error']:.2e}")
        tight, tight_float = double[-1], single[-1]
        if not tight["rms_error"] < 1e-8:
            failures.append(f"fast sum, double, tol {tight['tol']}: {tight['rms_error']:.2e}, not "
                            f"below 1e-8 (no floor to see)")
        for key, reference in (("rms_error", "as drawn"), ("rms_stored", "as stored")):
            if not 1e-8 < tight_float[key] < 1e-7:
                failures.append(f"fast sum, float storage, tol {tight['tol']}: "
                                f"{tight_float[key]:.2e} against the values {reference}, outside "
                                f"(1e-8, 1e-7)")
    return failures


# ---------------------------------------------------------------------------
# The picture.


def draw(png, seed, fast, plan):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    fig, (left, right) = plt.subplots(1, 2, figsize=(14, 6))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for colour, n in zip(colours, sorted({r["n"] for r in seed})):
        mine = [r for r in seed if r["n"] == n]
        t = [r["wall_time_s"] for r in mine]
        left.plot(t, [r["rms_error"] for r in mine], "o", color=colour, ms=7,
                  label=f"N = {n:.0e}".replace("e+0", "e"))
        for r, x in zip(mine, t):
            left.annotate(SCHEDULES[r["schedule"]], (x, r["rms_error"]), textcoords="offset points",
                          xytext=LABEL_OFFSETS[r["schedule"]], fontsize=7, color=colour)
            if r["rms_stored"] != r["rms_error"]:
                left.plot([x, x], [r["rms_stored"], r["rms_error"]], ":", color=colour, lw=0.8)
                left.plot(x, r["rms_stored"], "o", mfc="white", mec=colour, ms=7)
    left.set_title("seed velocity update (examples/md.part's force, rc = sqrt(3 / N))", fontsize=10)
    left.set_xlabel(f"time per update [s] (median of {plan['seed_repeats']}, 1 thread)")
    left.set_ylabel("relative L2 error of v's increment against long double")
    kinds = [Line2D([], [], ls="", marker="o", color="dimgrey", label="on the points as given"),
             Line2D([], [], ls="", marker="o", mfc="white", mec="dimgrey",
                    label="on the points as stored (float storage: rounded)")]
    handles, _ = left.get_legend_handles_labels()
    left.legend(handles=handles + kinds, fontsize=8, loc="center right")

    styles = {"double": ("o-", "double storage"), "precision = float": ("s--", "precision = float")}
    for colour, (precision, (style, label)) in zip(colours, styles.items()):
        mine = sorted((r for r in fast if r["precision"] == precision), key=lambda r: -float(r["tol"]))
        t = [r["wall_time_s"] for r in mine]
        right.plot(t, [r["rms_error"] for r in mine], style, color=colour, label=label)
        for r, x in zip(mine, t):
            right.annotate(r["tol"], (x, r["rms_error"]), textcoords="offset points",
                           xytext=(5, -9 if precision == "double" else 4), fontsize=7, color=colour)
        if precision != "double":
            right.plot(t, [r["rms_stored"] for r in mine], "s", mfc="white", mec=colour,
                       label=f"{label}, against the direct sum of the values as stored")
    n = fast[0]["n"] if fast else 0
    right.set_title(f"fast sum (dense = fmm, 1/r, N = {n} charges in the unit cube), labelled "
                    "with tol;\ncomputed in double whatever the storage", fontsize=10)
    right.set_xlabel(f"fast sum plan + evaluation [s] (median of {plan['fast_repeats']}, 1 thread)")
    right.set_ylabel("relative L2 error against the direct sum in double of the values as drawn")
    right.legend(fontsize=8, loc="upper right")
    for axis in (left, right):
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.grid(True, which="both", alpha=0.3)
    fig.suptitle("Precision: float storage (precision = float), float arithmetic with double "
                 "accumulation (arithmetic = float), and double: error against time")
    fig.tight_layout()
    sweep.save_figure(fig, png, 110, "precision")


# ---------------------------------------------------------------------------


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        description="The schedule's precision choices on the seed model and the fast sum: "
                    "error against time.",
        epilog="See the docstring at the top of examples/accuracy/precision.py.")
    parser.add_argument("--small", action="store_true", help="the CI's sizes")
    parser.add_argument("--build-dir", help="a build directory holding compiler/partc")
    parser.add_argument("--partc", help="the partc to build the fast sum's models with")
    parser.add_argument("--program", action="append", default=[], metavar="NAME=EXE",
                        help="a program built elsewhere: seed_precision, fast_sum_tol, "
                             "fast_sum_tol_float")
    parser.add_argument("--work", help="where builds and logs go (default: BUILD_DIR/precision, "
                                       "or beside the first --program)")
    parser.add_argument("--repeats", type=int,
                        help="timings per point (default: 5 for the seed, 3 for the fast sum; "
                             "1 each with --small)")
    parser.add_argument("--out", default=os.path.join(REPO, "examples", "images", "accuracy"),
                        help="where precision_seed.csv, precision_fast_sum.csv and "
                             "precision.png go")
    parser.add_argument("--replot", action="store_true",
                        help="run nothing: print, check and draw the tables in --out")
    parser.add_argument("--expect-shape", action="store_true",
                        help="exit 4 when the shape (see the docstring) does not hold")
    args = parser.parse_args(argv)
    if any("=" not in p for p in args.program):
        parser.error("--program takes NAME=EXE")
    if args.repeats is not None and args.repeats < 1:
        parser.error("--repeats must be at least 1")
    return args


def main(argv):
    args = parse_arguments(argv)
    plan = dict(PLANS["small" if args.small else "full"])
    if args.repeats:
        plan.update(seed_repeats=args.repeats, fast_repeats=args.repeats)
    seed_csv = os.path.join(args.out, "precision_seed.csv")
    fast_csv = os.path.join(args.out, "precision_fast_sum.csv")
    if args.replot:
        missing = [p for p in (seed_csv, fast_csv) if not os.path.exists(p)]
        if missing:
            print(f"precision: --replot reads {', '.join(missing)}, missing", file=sys.stderr)
            return 2
        seed = read_table(seed_csv, {"rms_error", "max_error", "wall_time_s", "rms_stored"})
        fast = read_table(fast_csv, {"rms_error", "max_error", "wall_time_s", "rms_stored"})
        for r in fast:
            r["tol"] = str(r["tol"])
    else:
        try:
            if args.work is None:
                args.work = sweep.default_work(args.program, args.build_dir, args.partc,
                                               "precision")
            os.makedirs(args.work, exist_ok=True)
            programs = programs_for(args)
            seed = seed_rows(programs["seed"], plan, args.work)
            fast = fast_sum_rows(programs, plan, args.work)
        except sweep.SweepError as error:
            print(f"precision: {error}", file=sys.stderr)
            return 3
        commit = sweep.git_commit()
        write_table(seed_csv, SEED_COLUMNS, seed, commit)
        write_table(fast_csv, FAST_COLUMNS, fast, commit)
    print_tables(seed, fast)
    failures = check_shape(seed, fast)
    if not failures:
        print("precision: shape holds: each choice's error where its rounding puts it, the fast "
              "sum within tol in double and floored by float's rounding when stored as float")
    for failure in failures:
        print(f"precision: {'expectation failed' if args.expect_shape else 'shape'}: {failure}")
    draw(os.path.join(args.out, "precision.png"), seed, fast, plan)
    return 4 if failures and args.expect_shape else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
