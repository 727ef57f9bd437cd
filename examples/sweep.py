#!/usr/bin/env python3
"""What accuracy costs in time: run a partc model over the values of one knob,
measure an error and the wall time of each run, write a CSV and a log-log
picture of error against time, and fit the order of the error in the knob.

  /usr/bin/python3 examples/sweep.py MODEL.part --knob NAME --values V1,V2,...
      [--steps K | --steps EXPR] [--set NAME=VALUE | --set NAME=EXPR]... [--seed S]
      ERROR: --error OBS [--error-max OBS] [--error-se OBS] [--expected OBS]
           | --value OBS --exact OBS
           | --value OBS --reference finest
      [--at-step K] [--knob-scale h|inverse] [--fit-window LO:HI]
      [--repeats 3] [--threads 1] [--csv FILE] [--png FILE] [--title TEXT]
      [--build-dir DIR | --partc PARTC] [--program EXE] [--work DIR] [--replot]
      [--expect-order P --order-tolerance T] [--expect-monotone]
      [--expect-within-se K]

The knob. `--knob NAME` is a `param` of the model: one program is built and
each run gets `--set NAME=VALUE` (the value exactly as written in --values).
A knob is an object with two questions (class ParamKnob below): which partc
flags a value needs (none for a param: one build serves every value) and
which driver arguments. `--knob-kind schedule --knob 'NAME: KEY'` sweeps a
schedule entry through partc's `--schedule 'NAME: KEY = VALUE'` option
(ScheduleKnob): one build per value, no driver arguments (`--knob 'force:
skin' --values 0.1,0.3`, the statement named force in the model). A knob must be a
number (the fit and the picture are log-log); a knob of words (search =
cell_list) is another kind still to write.

How long a run is. `--steps K` runs K steps whatever the knob; `--steps EXPR`
is a Python expression in x, the knob value (`x` for a knob that counts steps
per period, `round(100 / x)` for a time step to t = 100), rounded to an int.
So is a `--set NAME=VALUE` whose value is not a number: a param that must
follow the knob (`--knob n --set width=x+2`, a tank as wide as a column of n
particles; `--set damping=0.04/x`, a damping per step that keeps its rate per
unit time as dt = 1/n shrinks).

The error, read from the row the driver logs (`--log FILE.csv`) at the end of
the run (or at step K with --at-step K). Observables are model-level values,
so a model reduces over its particles itself (an RMS and a max over
particles are two observables); a vec observable is its components.
  (a) --error OBS: the model computes the error itself (against an analytic
      value). RMS error = the root mean square of OBS's components, max error
      = their largest magnitude, or the magnitude of --error-max OBS2.
      --error-se OBS3: its standard error (error bars, a column error_se);
      --expected OBS4: the error a formula predicts (a column expected, drawn
      beside the measured one).
  (b) --value OBS --exact OBS2: the error is OBS - OBS2, per component.
  (c) --value OBS --reference finest: the error is OBS - OBS at the finest
      knob value (the smallest, or the largest with --knob-scale inverse);
      that run is the reference and has error 0 (kept in the CSV, not fitted).

The fitted order: the least-squares slope of log(RMS error) against
log(knob) over the fit window (--fit-window LO:HI, knob values, both ends
included; by default every point with a positive error). --knob-scale h (the
default) says the knob is a step size, order = slope; inverse says it counts
steps or grows with accuracy (n_steps, a cutoff), order = -slope.

Output: the CSV (columns knob value, rms_error, max_error, wall_time_s,
threads, commit, then error_se and expected when asked for) and, with
--png, two panels: error against the median wall time per run (each point
labelled with its knob value), and error against the knob with the fitted
line. The wall time is the whole run of the generated program, start-up
included, median of --repeats runs (3 by default), with OMP_NUM_THREADS =
--threads (1 by default).

The program is built like tests/CMakeLists.txt builds models: partc (--partc,
or from --build-dir, else the newest build*/compiler/partc) writes MODEL.cpp with
--main, then g++ -O2 -march=native -ffp-contract=off (--cxx-flags) -std=c++17 -fopenmp with runtime/ (and Eigen) on the
include path, linked with the runtime library of partc's build (BUILD_DIR/libpartc_runtime.a,
CMake's target partc_runtime), into --work (BUILD_DIR/sweep by default); a build whose C++
did not change is reused. --program EXE runs a program built elsewhere
(CMake's partc_add_model) instead.

--expect-order P --order-tolerance T, --expect-monotone (the RMS error falls
as the knob refines) and --expect-within-se K (|error - expected| <= K
standard errors at every point) make the sweep a test: a failed expectation
is printed as "expectation failed: ..." and the exit status is 4.
Exit status: 0 done, 2 bad command line, 3 a build or run failed, 4 an
expectation failed.

--replot runs nothing: it reads the table at --csv and prints, checks and
draws it again (a bias is then compared by its magnitude).
"""
import argparse
import csv
import glob
import hashlib
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class SweepError(Exception):
    """A build or a run failed: exit status 3."""


# ---------------------------------------------------------------------------
# Knobs: what a value needs at build time and at run time.


class ParamKnob:
    """A `param` of the model: one build, `--set NAME=VALUE` per run."""

    def __init__(self, name):
        self.name = name

    def partc_flags(self, value):
        return ()

    def driver_args(self, value):
        return ["--set", f"{self.name}={value}"]


class ScheduleKnob:
    """A schedule entry, `NAME: KEY`, chosen by partc's `--schedule 'NAME: KEY =
    VALUE'` option (over the model's own schedule block): one build per value,
    no driver arguments."""

    def __init__(self, entry):
        self.entry = entry  # "NAME: KEY"

    def partc_flags(self, value):
        return ("--schedule", f"{self.entry} = {value}")

    def driver_args(self, value):
        return []


# ---------------------------------------------------------------------------
# Building and running.


def find_partc(build_dir):
    if build_dir:
        path = os.path.join(build_dir, "compiler", "partc")
        if not os.access(path, os.X_OK):
            raise SweepError(f"no partc at {path}")
        return path
    found = [p for p in glob.glob(os.path.join(REPO, "build*", "compiler", "partc"))
             if os.access(p, os.X_OK)]
    if not found:
        raise SweepError("no partc found at build*/compiler/partc: build it "
                         "(cmake --build build --target partc) or pass --build-dir")
    return max(found, key=os.path.getmtime)


def default_work(programs, build_dir, partc, name):
    """Where a figure script's builds and logs go when --work is not given:
    NAME beside the first --program (NAME=EXE), else in the build directory
    (--build-dir, or the one holding --partc or the newest partc)."""
    if programs:
        home = os.path.dirname(os.path.abspath(programs[0].split("=", 1)[1]))
    else:
        home = build_dir or os.path.dirname(os.path.dirname(
            os.path.abspath(partc or find_partc(None))))
    return os.path.join(home, name)


def save_figure(fig, png, dpi, who):
    """Writes FIG to PNG (making its folder), closes it and says so."""
    import matplotlib.pyplot as plt
    os.makedirs(os.path.dirname(os.path.abspath(png)), exist_ok=True)
    fig.savefig(png, dpi=dpi)
    plt.close(fig)
    print(f"{who}: picture {png}")


def runtime_library(partc):
    """The runtime library built beside PARTC (BUILD_DIR/compiler/partc)."""
    path = os.path.join(os.path.dirname(os.path.dirname(partc)), "libpartc_runtime.a")
    if not os.path.exists(path):
        raise SweepError(f"no runtime library at {path}: build it "
                         "(cmake --build BUILD_DIR --target partc_runtime)")
    return path


def run_checked(command, what, env=None):
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    if result.returncode != 0:
        raise SweepError(f"{what} failed (exit {result.returncode}): {' '.join(command)}\n"
                         f"{result.stdout}{result.stderr}")
    return result


def build_program(model, partc, flags, work, cxx_flags):
    """partc, then g++: the driver program of MODEL with partc's FLAGS. The
    C++ is regenerated each time (partc takes a fraction of a second) and
    compiled only when it differs from the last build's."""
    stem = os.path.splitext(os.path.basename(model))[0]
    tag = hashlib.sha1(" ".join([*flags, cxx_flags]).encode()).hexdigest()[:8]
    directory = os.path.join(work, f"{stem}-{tag}")
    os.makedirs(directory, exist_ok=True)
    cpp = os.path.join(directory, f"{stem}.cpp")
    fresh = cpp + ".new"
    run_checked([partc, model, "-o", fresh, "--main", *flags], f"partc {model}")
    program = os.path.join(directory, stem)
    with open(fresh) as f:
        new_text = f.read()
    old_text = None
    if os.path.exists(cpp):
        with open(cpp) as f:
            old_text = f.read()
    if new_text == old_text and os.access(program, os.X_OK):
        os.remove(fresh)
        return program
    os.replace(fresh, cpp)
    command = [os.environ.get("CXX", "g++"), *cxx_flags.split(), "-std=c++17", "-fopenmp",
               "-I", os.path.join(REPO, "runtime")]
    if os.path.isdir("/usr/include/eigen3"):
        command += ["-I", "/usr/include/eigen3"]
    command += [cpp, runtime_library(partc), "-o", program]
    print(f"sweep: compiling {cpp}", flush=True)
    run_checked(command, "the C++ compiler")
    return program


def evaluate(expression, value):
    """A Python expression in x, the knob VALUE (math's names, round, int, abs,
    min and max at hand)."""
    names = {name: getattr(math, name) for name in dir(math) if not name.startswith("_")}
    names.update(x=float(value), round=round, int=int, abs=abs, min=min, max=max)
    try:
        return eval(expression, {"__builtins__": {}}, names)  # noqa: S307 (the user's command)
    except Exception as error:
        raise SweepError(f"'{expression}' at x = {value}: {error}") from error


def steps_for(expression, value):
    """The number of steps of the run at knob VALUE: an int, or a Python
    expression in x."""
    steps = evaluate(expression, value)
    if abs(steps - round(steps)) > 1e-9 * max(1, abs(steps)):
        raise SweepError(f"--steps {expression} is {steps} at x = {value}, not a whole number "
                         f"of steps: round it (round(...))")
    return int(round(steps))


def set_args(assignments, value):
    """The driver's --set arguments at knob VALUE: a number passes as written,
    anything else is an expression in x (a param that follows the knob: `width=x+2`;
    a whole result is written as an int, for an int param)."""
    args = []
    for assignment in assignments:
        name, _, text = assignment.partition("=")
        try:
            float(text)
        except ValueError:
            result = evaluate(text, value)
            text = str(int(round(result))) if result == round(result) else repr(float(result))
        args += ["--set", f"{name}={text}"]
    return args


def read_row(log, at_step):
    with open(log, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SweepError(f"{log}: no rows logged")
    if at_step is None:
        return rows[-1]
    for row in rows:
        if int(float(row["step"])) == at_step:
            return row
    raise SweepError(f"{log}: no row of step {at_step}")


def observable(row, name):
    """The components of observable NAME in a logged row (a vec is NAME_0, ...)."""
    if name in row:
        return np.array([float(row[name])])
    components = []
    while f"{name}_{len(components)}" in row:
        components.append(float(row[f"{name}_{len(components)}"]))
    if not components:
        columns = ", ".join(k for k in row if k not in ("step", "t"))
        raise SweepError(f"observable '{name}' is not in the log (logged: {columns}); "
                         f"name it in the model's output line")
    return np.array(components)


def run_once(program, args, log, threads):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    start = time.perf_counter()
    run_checked([program, *args, "--log", log, "--log-every", "0", "--quiet"],
                os.path.basename(program), env=env)
    return time.perf_counter() - start


def git_commit():
    try:
        out = subprocess.run(["git", "-C", REPO, "rev-parse", "--short=12", "HEAD"],
                             capture_output=True, text=True)
        return out.stdout.strip() or "unknown"
    except OSError:
        return "unknown"


# ---------------------------------------------------------------------------
# Fitting and drawing.


def fit_order(knobs, errors, window, scale):
    """Least squares of log error on log knob over the window; the order and
    the points used."""
    use = [k for k, e in zip(knobs, errors) if e > 0 and (window is None or
                                                          window[0] <= k <= window[1])]
    chosen = [(k, e) for k, e in zip(knobs, errors) if k in use and e > 0]
    if len(chosen) < 2:
        return None, chosen
    x = np.log([k for k, _ in chosen])
    y = np.log([e for _, e in chosen])
    slope, intercept = np.polyfit(x, y, 1)
    order = slope if scale == "h" else -slope
    return (order, slope, intercept), chosen


def label_log_axis(axis, ticker, values):
    """Plain labels on a log axis; minor ticks at 2 and 5 labelled too when
    the values span less than two decades (a sweep's times often span less
    than one, where matplotlib's default labels overlap)."""
    plain = ticker.FuncFormatter(lambda v, _: f"{v:g}")
    axis.set_major_formatter(plain)
    axis.set_minor_locator(ticker.LogLocator(subs=(2.0, 5.0)))
    values = [v for v in values if v > 0]
    narrow = values and math.log10(max(values) / min(values)) < 2
    axis.set_minor_formatter(plain if narrow else ticker.NullFormatter())


def draw(png, rows, args, fit, chosen):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import ticker

    knob_label = args.knob_label or args.knob
    error_label = args.error_label or "RMS error"
    knobs = np.array([r["knob"] for r in rows])
    errors = np.array([r["rms_error"] for r in rows])
    times = np.array([r["wall_time_s"] for r in rows])
    se = np.array([r.get("error_se", 0.0) for r in rows])
    shown = errors > 0
    fig, (left, right) = plt.subplots(1, 2, figsize=(12.5, 5.2), sharey=True)
    threads = f"{args.threads} thread{'s' if args.threads > 1 else ''}"
    for axis, xs, xlabel in ((left, times, f"wall time per run [s] (median of {args.repeats} "
                              f"runs, {threads}, start-up included)"),
                             (right, knobs, knob_label)):
        yerr = se[shown] if args.error_se else None
        axis.errorbar(xs[shown], errors[shown], yerr=yerr, fmt="o-", capsize=3,
                      label="measured" + (" (+- 1 standard error)" if args.error_se else ""))
        shown_values = list(errors[shown])
        if args.expected:
            expected = np.array([r["expected"] for r in rows])
            axis.plot(xs, expected, "s--", mfc="none", label=args.expected_label or "expected")
            shown_values += list(expected)
        axis.set_xscale("log")
        axis.set_yscale("log")
        label_log_axis(axis.xaxis, ticker, list(xs[shown]))
        label_log_axis(axis.yaxis, ticker, shown_values)
        axis.set_xlabel(xlabel)
        axis.grid(True, which="both", alpha=0.3)
    left.set_ylabel(error_label)
    left.margins(x=0.12)  # room for the last point's label
    for x, y, k in zip(times[shown], errors[shown], knobs[shown]):
        left.annotate(f"{args.knob} = {k:g}", (x, y), textcoords="offset points", xytext=(6, 4),
                      fontsize=8)
    if fit is not None:
        order, slope, intercept = fit
        ks = np.array([k for k, _ in chosen])
        line = np.exp(intercept) * ks ** slope
        right.plot(ks, line, "k:", label=f"least-squares fit: order {order:.2f} "
                                         f"({args.knob} = {ks.min():g} ... {ks.max():g})")
    if getattr(args, "reference_text", None):
        right.text(0.02, 0.02, f"reference: the run at {args.knob} = {args.reference_text}",
                   transform=right.transAxes, fontsize=8)
    left.set_title("error against time")
    right.set_title(f"error against {args.knob}")
    right.legend(fontsize=8)
    left.legend(fontsize=8)
    fig.suptitle(args.title or f"{os.path.basename(args.model)}: {error_label} over {args.knob}")
    fig.tight_layout()
    save_figure(fig, png, 110, "sweep")


def read_table(path, knob):
    """The rows of a CSV this script wrote (for --replot)."""
    rows = []
    with open(path, newline="") as f:
        for line in csv.DictReader(f):
            row = dict(knob=float(line[knob]), text=line[knob],
                       rms_error=float(line["rms_error"]), max_error=float(line["max_error"]),
                       wall_time_s=float(line["wall_time_s"]), threads=int(line["threads"]),
                       commit=line["commit"])
            for extra in ("error_se", "expected"):
                if extra in line:
                    row[extra] = float(line[extra])
            row["signed"] = row["rms_error"]
            rows.append(row)
    return rows


# ---------------------------------------------------------------------------


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        description="Run a partc model over one knob; error against wall time.",
        epilog="See the docstring at the top of examples/sweep.py.")
    parser.add_argument("model", help="the .part file")
    parser.add_argument("--knob", required=True,
                        help="the param to sweep (with --knob-kind schedule: 'NAME: KEY')")
    parser.add_argument("--knob-kind", choices=["param", "schedule"], default="param")
    parser.add_argument("--values", required=True, help="comma-separated knob values")
    parser.add_argument("--steps", default="0", help="steps per run: an int, or an expression in x")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a param for every run: a number, or an expression in x")
    parser.add_argument("--seed", help="the driver's --seed")
    parser.add_argument("--error", help="(a) an observable that is an error")
    parser.add_argument("--error-max", help="(a) the observable giving the max error column")
    parser.add_argument("--error-se", help="the observable giving the error's standard error")
    parser.add_argument("--expected", help="the observable giving a predicted error")
    parser.add_argument("--value", help="(b, c) the observable compared")
    parser.add_argument("--exact", help="(b) the observable holding its exact value")
    parser.add_argument("--reference", choices=["finest"], help="(c) against the finest run")
    parser.add_argument("--at-step", type=int, help="read the row of this step, not the last")
    parser.add_argument("--knob-scale", choices=["h", "inverse"], default="h")
    parser.add_argument("--fit-window", help="LO:HI, knob values of the fit (inclusive)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--csv", help="the table to write")
    parser.add_argument("--png", help="the picture to draw (needs matplotlib)")
    parser.add_argument("--title")
    parser.add_argument("--knob-label")
    parser.add_argument("--error-label")
    parser.add_argument("--expected-label")
    parser.add_argument("--build-dir", help="a build directory holding compiler/partc")
    parser.add_argument("--partc", help="the partc to use (instead of BUILD_DIR/compiler/partc)")
    parser.add_argument("--cxx-flags", default="-O2 -march=native -ffp-contract=off",
                        help="the C++ compiler's optimisation flags (default -O2 -march=native "
                        "-ffp-contract=off: vectors as wide as the machine has, each operation "
                        "rounded as written, as CMake's PARTC_NATIVE)")
    parser.add_argument("--program", help="a driver program built elsewhere (param knobs only)")
    parser.add_argument("--work", help="where builds and logs go (default: BUILD_DIR/sweep, "
                                       "or beside --program)")
    parser.add_argument("--replot", action="store_true",
                        help="run nothing: print, check and draw the table already at --csv")
    parser.add_argument("--expect-order", type=float)
    parser.add_argument("--order-tolerance", type=float, default=0.1)
    parser.add_argument("--expect-monotone", action="store_true")
    parser.add_argument("--expect-within-se", type=float, metavar="K")
    args = parser.parse_args(argv)
    modes = [args.error is not None, args.exact is not None, args.reference is not None]
    if sum(modes) != 1:
        parser.error("say how the error is measured: --error OBS, --value OBS --exact OBS, "
                     "or --value OBS --reference finest")
    if (args.exact or args.reference) and not args.value:
        parser.error("--exact and --reference compare --value OBS")
    if args.value and args.error:
        parser.error("--value goes with --exact or --reference, not with --error")
    if args.expect_within_se is not None and not (args.error_se and args.expected):
        parser.error("--expect-within-se needs --error-se and --expected")
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    if args.program and args.knob_kind != "param":
        parser.error("--program serves a param knob only (other knobs rebuild per value)")
    if args.fit_window:
        lo, _, hi = args.fit_window.partition(":")
        args.fit_window = (float(lo), float(hi))
    args.value_texts = [v.strip() for v in args.values.split(",") if v.strip()]
    if len(args.value_texts) < 2:
        parser.error("--values needs at least two values")
    return args


def sweep(args):
    knob = ParamKnob(args.knob) if args.knob_kind == "param" else ScheduleKnob(args.knob)
    partc = None
    if not args.program:
        partc = os.path.abspath(args.partc) if args.partc else find_partc(args.build_dir)
    if args.work is None:
        home = os.path.dirname(os.path.abspath(args.program)) if args.program else \
            os.path.dirname(os.path.dirname(os.path.abspath(partc)))
        args.work = os.path.join(home, "sweep")
    os.makedirs(args.work, exist_ok=True)
    programs = {}
    seed = ["--seed", args.seed] if args.seed is not None else []
    threads = args.threads
    commit = git_commit()
    stem = os.path.splitext(os.path.basename(args.model))[0]
    results = []
    for text in args.value_texts:
        flags = knob.partc_flags(text)
        if args.program:
            program = args.program
        else:
            if flags not in programs:
                programs[flags] = build_program(os.path.abspath(args.model), partc, list(flags),
                                                args.work, args.cxx_flags)
            program = programs[flags]
        steps = steps_for(args.steps, text)
        log_every = args.at_step if args.at_step else max(steps, 1)
        run_args = [*set_args(args.set, text), *seed, *knob.driver_args(text),
                    "--steps", str(steps), "--log-file-every", str(log_every)]
        # Named after the program and its arguments too: two sweeps of one
        # model (other --set values, say) may run at once in one --work.
        run_tag = hashlib.sha1(" ".join([program, *run_args]).encode()).hexdigest()[:8]
        log = os.path.join(args.work, f"{stem}-{args.knob.replace(':', '_').replace(' ', '')}"
                                      f"-{text}-{run_tag}.log.csv")
        times = [run_once(program, run_args, log, threads) for _ in range(args.repeats)]
        row = read_row(log, args.at_step)
        results.append(dict(knob=float(text), text=text, row=row, steps=steps,
                            wall_time_s=statistics.median(times)))
        print(f"sweep: {args.knob} = {text}: {steps} steps, {statistics.median(times):.4g} s "
              f"(median of {args.repeats})", flush=True)

    finest = None
    if args.reference:
        pick = min if args.knob_scale == "h" else max
        finest = pick(results, key=lambda r: r["knob"])
    rows = []
    for r in results:
        if args.error:
            differences = observable(r["row"], args.error)
        elif args.exact:
            differences = observable(r["row"], args.value) - observable(r["row"], args.exact)
        else:
            differences = observable(r["row"], args.value) - observable(finest["row"], args.value)
        rms = float(np.sqrt(np.mean(differences ** 2)))
        largest = float(np.max(np.abs(differences)))
        if args.error_max:
            largest = float(np.max(np.abs(observable(r["row"], args.error_max))))
        out = dict(knob=r["knob"], text=r["text"], rms_error=rms, max_error=largest,
                   wall_time_s=r["wall_time_s"], threads=threads, commit=commit,
                   signed=float(differences[0]) if differences.size == 1 else rms)
        if args.error_se:
            out["error_se"] = float(np.sqrt(np.mean(observable(r["row"], args.error_se) ** 2)))
        if args.expected:
            out["expected"] = float(np.sqrt(np.mean(observable(r["row"], args.expected) ** 2)))
        rows.append(out)
    return rows, finest


def report(args, rows, finest):
    """Prints the table, the fitted order and local orders; writes the CSV and
    picture; returns the failed expectations."""
    failures = []
    header = [args.knob, "rms_error", "max_error", "wall_time_s", "threads", "commit"]
    if args.error_se:
        header.append("error_se")
    if args.expected:
        header.append("expected")
    if args.csv:
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(header)
            for r in rows:
                line = [r["text"], f"{r['rms_error']:.6e}", f"{r['max_error']:.6e}",
                        f"{r['wall_time_s']:.6f}", r["threads"], r["commit"]]
                if args.error_se:
                    line.append(f"{r['error_se']:.6e}")
                if args.expected:
                    line.append(f"{r['expected']:.6e}")
                writer.writerow(line)
        print(f"sweep: table {args.csv}")

    print(" ".join(f"{h:>14}" for h in header[:4] + header[6:]))
    for r in rows:
        cells = [r["text"], f"{r['rms_error']:.4e}", f"{r['max_error']:.4e}",
                 f"{r['wall_time_s']:.4g}"]
        if args.error_se:
            cells.append(f"{r['error_se']:.3e}")
        if args.expected:
            cells.append(f"{r['expected']:.4e}")
        print(" ".join(f"{c:>14}" for c in cells))
    if finest is not None:
        print(f"sweep: reference: the run at {args.knob} = {finest['text']} (finest)")
        args.reference_text = finest["text"]

    ordered = sorted(rows, key=lambda r: r["knob"], reverse=args.knob_scale == "h")
    # Coarse to fine: local orders between neighbours.
    local = []
    for a, b in zip(ordered, ordered[1:]):
        if a["rms_error"] > 0 and b["rms_error"] > 0:
            slope = math.log(b["rms_error"] / a["rms_error"]) / math.log(b["knob"] / a["knob"])
            local.append(f"{a['text']}->{b['text']}: {slope if args.knob_scale == 'h' else -slope:.3f}")
    if local:
        print("sweep: local orders, coarse to fine: " + ", ".join(local))

    knobs = [r["knob"] for r in rows]
    errors = [r["rms_error"] for r in rows]
    fit, chosen = fit_order(knobs, errors, args.fit_window, args.knob_scale)
    if fit is None:
        print("sweep: fewer than two points with a positive error in the fit window: no order")
        if args.expect_order is not None:
            failures.append("no fitted order")
    else:
        order, slope, _ = fit
        window = ", ".join(f"{k:g}" for k, _ in chosen)
        print(f"sweep: fitted order {order:.3f} (least-squares slope {slope:.3f} of log RMS error "
              f"against log {args.knob}; window {args.knob} = {window}: {len(chosen)} points)")
        if args.expect_order is not None and abs(order - args.expect_order) > args.order_tolerance:
            failures.append(f"fitted order {order:.3f} is outside {args.expect_order} +- "
                            f"{args.order_tolerance}")
    if args.expect_monotone:
        measured = [r for r in ordered if not (finest is not None and r is finest)]
        for a, b in zip(measured, measured[1:]):
            if not b["rms_error"] < a["rms_error"]:
                failures.append(f"error does not fall from {args.knob} = {a['text']} "
                                f"({a['rms_error']:.4e}) to {b['text']} ({b['rms_error']:.4e})")
    if args.expect_within_se is not None:
        k = args.expect_within_se
        for r in rows:
            signed = r["signed"]  # a bias is compared with its sign
            if abs(signed - r["expected"]) > k * r["error_se"]:
                failures.append(f"at {args.knob} = {r['text']} the error {signed:.4e} differs "
                                f"from the expected {r['expected']:.4e} by more than {k:g} "
                                f"standard errors ({r['error_se']:.2e})")
            else:
                print(f"sweep: {args.knob} = {r['text']}: error {signed:.4e} vs expected "
                      f"{r['expected']:.4e}: {abs(signed - r['expected']) / r['error_se']:.2f} "
                      f"standard errors apart")
    if args.png:
        draw(args.png, rows, args, fit, chosen)
    return failures


def main(argv):
    args = parse_arguments(argv)
    if args.replot:
        if not args.csv or not os.path.exists(args.csv):
            print("sweep: --replot reads the table at --csv, which is missing", file=sys.stderr)
            return 2
        rows = read_table(args.csv, args.knob)
        finest = None
        if args.reference:
            pick = min if args.knob_scale == "h" else max
            finest = pick(rows, key=lambda r: r["knob"])
        args.threads = rows[0]["threads"]
        args.csv = None  # the table stays as it is
        failures = report(args, rows, finest)
        for failure in failures:
            print(f"sweep: expectation failed: {failure}")
        return 4 if failures else 0
    try:
        rows, finest = sweep(args)
    except SweepError as error:
        print(f"sweep: {error}", file=sys.stderr)
        return 3
    failures = report(args, rows, finest)
    for failure in failures:
        print(f"sweep: expectation failed: {failure}")
    return 4 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
