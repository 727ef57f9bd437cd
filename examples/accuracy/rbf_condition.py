#!/usr/bin/env python3
"""What the shape parameter costs: RBF interpolation (examples/rbf_franke.part,
multiquadrics) and Kansa collocation (examples/kansa_poisson.part, Gaussians)
over the shape parameter eps for several node counts n x n, with the error on
the grid and the dense solve's condition estimate.

  /usr/bin/python3 examples/accuracy/rbf_condition.py
      [--small] [--models rbf_franke,kansa_poisson]
      [--build-dir DIR | --partc PARTC | --program MODEL=EXE ...]
      [--work DIR] [--repeats 3] [--csv FILE] [--png FILE] [--replot]
      [--expect-shape] [--warn-above 1e12]

Each run is the model's driver with --set n=N --set eps=EPS and 0 steps (the
solve is in init). From it: rms_error and max_error, the last row of its --log
CSV; from the summary it prints, the solve line ("solve w: dense LU, n = 400,
rcond 7.5e-13, ...") and the warning after it, if any. condition is 1/rcond,
LU's 1-norm estimate (two digits, as printed); method is LU, or COD when rcond
fell below 2.2e-16 and the runtime solved by a complete orthogonal
decomposition instead (runtime/partc/solve/dense_solve.hpp). Below that
threshold rcond is itself rounding noise (1/rcond of 1e20 and beyond), so a
COD run's condition says "singular to working precision", not how singular.
rank (COD only), residual and solve_s (the solve's own seconds, two digits)
are the solve line's too. time_s is the whole run's wall time, start-up and
the grid included, median of --repeats, on one thread.

The sweeps (PLANS below; --small for the CI's): Franke with multiquadrics, n =
10, 15, 20, 30, eps = 1 ... 64; Kansa with its default Gaussian basis, n = 10,
15, 20, 30, eps = 1 ... 16 (beyond about 20 the Gaussian's condition rises
again as its Laplacian rows dominate, and the error nears 100%). Both
evaluate on a 41 x 41 grid (21 x 21 with --small).

Output: a CSV (model, n, eps, rms_error, max_error, condition, warned, method,
rank, residual, solve_s, time_s, commit), a table on the terminal with the best eps per
n (the smallest RMS error) and its condition, and with --png one row per
model: RMS error against eps and the condition estimate against eps, one line
per n, runs that warned and COD runs marked, the 1e12 warning line drawn.

The shape, checked always and made a test by --expect-shape (exit 4 and
"expectation failed: ..." when it does not hold):
  - for each n, the condition estimate rises as eps falls over the LU runs,
    and the COD runs, if any, are the smallest eps;
  - a run warned exactly when its condition exceeds --warn-above (the
    runtime's threshold, 1e12);
  - at the smallest sampled eps where no n warned (well-conditioned for
    every n), the RMS error falls as n grows.
Programs: built by examples/sweep.py's build_program from partc (--build-dir
or --partc, else the newest build*/compiler/partc), or given (--program
rbf_franke=EXE, CMake's partc_add_model targets). Exit status: 0 done, 2 bad
command line, 3 a build or run failed, 4 an expectation failed.
"""
import argparse
import csv
import os
import re
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import sweep  # noqa: E402  (examples/sweep.py: building, running, reading logs)

EXAMPLES = os.path.dirname(HERE)
SINGULAR_RCOND = 2.220446049250313e-16  # below it the runtime solves by COD


def log_spaced(lo_power, hi_power, per_octave=4):
    """eps = 2^(k / per_octave) for k in [lo_power, hi_power] * per_octave, as
    the texts passed to --set (four significant digits)."""
    return [f"{2 ** (k / per_octave):.4g}"
            for k in range(lo_power * per_octave, hi_power * per_octave + 1)]


# What each model's sweep runs: node counts, eps values, params fixed for all.
PLANS = {
    "full": {
        "rbf_franke": dict(ns=[10, 15, 20, 30], eps=log_spaced(0, 6), fixed={"m": 41}),
        "kansa_poisson": dict(ns=[10, 15, 20, 30], eps=log_spaced(0, 4), fixed={"m": 41}),
    },
    # The CI's: each model's runs under a second, and still every kind of run
    # (LU, LU with a warning, COD) for the checks to see.
    "small": {
        "rbf_franke": dict(ns=[6, 9, 12], eps=["1", "2", "4", "8", "16"], fixed={"m": 21}),
        "kansa_poisson": dict(ns=[6, 9, 12], eps=["2", "3", "4", "5", "8"], fixed={"m": 21}),
    },
}
# The basis each model sweeps, and the largest |exact value| on its grid (the
# scale of its error).
BASIS = {"rbf_franke": "multiquadric sqrt(1 + (eps r)^2)",
         "kansa_poisson": "Gaussian exp(-(eps r)^2)"}
EXACT_MAX = {"rbf_franke": "1.22", "kansa_poisson": "1"}

SOLVE_LINE = re.compile(r"^solve (\w+): (.+?), n = (\d+)(?:, rank (\d+))?, rcond ([^,]+), "
                        r"residual ([^,]+), ([^ ]+) s$", re.M)
WARNING_LINE = re.compile(r"^warning: solve \w+: (ill-conditioned|the matrix is singular)", re.M)


def parse_summary(text, what):
    """The solve's facts from the driver's summary."""
    solve = SOLVE_LINE.search(text)
    if not solve:
        raise sweep.SweepError(f"{what}: no 'solve NAME: ..., rcond ...' line in its summary:\n"
                               f"{text}")
    method_text = solve.group(2)
    if method_text == "dense LU":
        method = "LU"
    elif "complete orthogonal decomposition" in method_text:
        method = "COD"
    else:
        raise sweep.SweepError(f"{what}: a solve by '{method_text}', not a dense one")
    rcond = float(solve.group(5))
    return dict(condition=1 / rcond if rcond > 0 else float("inf"),
                warned=bool(WARNING_LINE.search(text)), method=method,
                rank=solve.group(4) or "", residual=float(solve.group(6)),
                solve_s=float(solve.group(7)))


def run_point(program, model, n, eps, fixed, work, repeats):
    """One run of MODEL at n, eps: its errors, solve facts and median time."""
    log = os.path.join(work, f"{model}-n{n}-eps{eps}.log.csv")
    command = [program, "--steps", "0", "--log", log, "--log-every", "0",
               "--set", f"n={n}", "--set", f"eps={eps}"]
    for name, value in fixed.items():
        command += ["--set", f"{name}={value}"]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = sweep.run_checked(command, model, env=env)
        times.append(time.perf_counter() - start)
    row = sweep.read_row(log, None)
    point = dict(model=model, n=n, eps=eps,
                 rms_error=float(sweep.observable(row, "rms_error")[0]),
                 max_error=float(sweep.observable(row, "max_error")[0]),
                 time_s=statistics.median(times))
    point.update(parse_summary(result.stdout, f"{model} n={n} eps={eps}"))
    return point


def programs_for(args, models):
    """{model: its driver program}: given by --program, else built here."""
    given = dict(p.split("=", 1) for p in args.program)
    unknown = set(given) - set(BASIS)
    if unknown:
        raise sweep.SweepError(f"--program for an unknown model: {', '.join(sorted(unknown))}")
    programs = {}
    partc = None
    for model in models:
        if model in given:
            programs[model] = given[model]
            continue
        if partc is None:
            partc = os.path.abspath(args.partc) if args.partc else sweep.find_partc(args.build_dir)
        programs[model] = sweep.build_program(os.path.join(EXAMPLES, f"{model}.part"), partc, [],
                                              args.work, "-O2")
    return programs


def run_sweeps(args, models):
    plans = PLANS["small" if args.small else "full"]
    os.makedirs(args.work, exist_ok=True)
    programs = programs_for(args, models)
    commit = sweep.git_commit()
    points = []
    for model in models:
        plan = plans[model]
        for n in plan["ns"]:
            for eps in plan["eps"]:
                point = run_point(programs[model], model, n, eps, plan["fixed"], args.work,
                                  args.repeats)
                point["commit"] = commit
                points.append(point)
            print(f"rbf_condition: {model} n = {n}: {len(plan['eps'])} runs", flush=True)
    return points


COLUMNS = ["model", "n", "eps", "rms_error", "max_error", "condition", "warned", "method",
           "rank", "residual", "solve_s", "time_s", "commit"]


def write_table(path, points):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(COLUMNS)
        for p in points:
            writer.writerow([p["model"], p["n"], p["eps"], f"{p['rms_error']:.6e}",
                             f"{p['max_error']:.6e}", f"{p['condition']:.2e}",
                             int(p["warned"]), p["method"], p["rank"], f"{p['residual']:.1e}",
                             f"{p['solve_s']:.2g}", f"{p['time_s']:.4f}", p["commit"]])
    print(f"rbf_condition: table {path}")


def read_table(path):
    points = []
    with open(path, newline="") as f:
        for line in csv.DictReader(f):
            points.append(dict(line, n=int(line["n"]), rms_error=float(line["rms_error"]),
                               max_error=float(line["max_error"]),
                               condition=float(line["condition"]),
                               warned=line["warned"] == "1", residual=float(line["residual"]),
                               solve_s=float(line["solve_s"]), time_s=float(line["time_s"])))
    return points


def by_model_and_n(points):
    """{model: {n: [points by falling eps]}}, models and n in the table's order."""
    grouped = {}
    for p in points:
        grouped.setdefault(p["model"], {}).setdefault(p["n"], []).append(p)
    for lines in grouped.values():
        for n in lines:
            lines[n].sort(key=lambda p: -float(p["eps"]))
    return grouped


def best_eps(line):
    return min(line, key=lambda p: p["rms_error"])


def print_table(points):
    print(f"{'model':>14} {'n':>3} {'eps':>6} {'rms_error':>10} {'max_error':>10} "
          f"{'condition':>9} {'method':>6} {'warned':>6} {'solve_s':>7} {'time_s':>7}")
    for p in points:
        print(f"{p['model']:>14} {p['n']:>3} {p['eps']:>6} {p['rms_error']:>10.3e} "
              f"{p['max_error']:>10.3e} {p['condition']:>9.1e} {p['method']:>6} "
              f"{'yes' if p['warned'] else '':>6} {p['solve_s']:>7.2g} {p['time_s']:>7.3f}")
    for model, lines in by_model_and_n(points).items():
        for n, line in lines.items():
            best = best_eps(line)
            print(f"rbf_condition: {model} n = {n}: best eps {best['eps']} (RMS error "
                  f"{best['rms_error']:.2e}, condition {best['condition']:.1e}, {best['method']}"
                  f"{', warned' if best['warned'] else ''})")


def check_shape(points, warn_above):
    """The failed expectations (see the docstring); prints what held."""
    failures = []
    for p in points:
        if p["warned"] != (p["condition"] > warn_above):
            failures.append(f"{p['model']} n = {p['n']}, eps = {p['eps']}: condition "
                            f"{p['condition']:.1e} {'>' if p['condition'] > warn_above else '<='} "
                            f"{short(warn_above)} but {'a' if p['warned'] else 'no'} warning")
    for model, lines in by_model_and_n(points).items():
        for n, line in lines.items():
            lu = [p for p in line if p["method"] == "LU"]
            for a, b in zip(lu, lu[1:]):
                if not b["condition"] > a["condition"]:
                    failures.append(f"{model} n = {n}: condition does not rise from eps = "
                                    f"{a['eps']} ({a['condition']:.1e}) to {b['eps']} "
                                    f"({b['condition']:.1e})")
            methods = "".join("L" if p["method"] == "LU" else "C" for p in line)
            if "CL" in methods:
                failures.append(f"{model} n = {n}: an LU run at a smaller eps than a COD run "
                                f"(by falling eps: {methods})")
        every_eps = sorted({float(p["eps"]) for line in lines.values() for p in line})
        quiet = [e for e in every_eps
                 if all(not p["warned"] for line in lines.values()
                        for p in line if float(p["eps"]) == e)]
        if not quiet:
            failures.append(f"{model}: every sampled eps warned for some n; no well-conditioned "
                            f"eps to compare n at")
            continue
        eps = quiet[0]
        errors = [(n, p["rms_error"]) for n, line in sorted(lines.items())
                  for p in line if float(p["eps"]) == eps]
        text = ", ".join(f"n = {n}: {e:.2e}" for n, e in errors)
        print(f"rbf_condition: {model}: at eps = {eps:g} (smallest eps where no n warned) "
              f"RMS error {text}")
        for (n_a, e_a), (n_b, e_b) in zip(errors, errors[1:]):
            if not e_b < e_a:
                failures.append(f"{model}: at eps = {eps:g} the error does not fall from n = "
                                f"{n_a} ({e_a:.2e}) to n = {n_b} ({e_b:.2e})")
    return failures


def short(value):
    """1e12 as "1e12", not "1e+12"."""
    return f"{value:.0e}".replace("e+", "e")


def draw(png, points, plans, warn_above):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    grouped = by_model_and_n(points)
    fig, axes = plt.subplots(len(grouped), 2, figsize=(13, 5.2 * len(grouped)), squeeze=False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for (model, lines), (error_axis, condition_axis) in zip(grouped.items(), axes):
        for colour, (n, line) in zip(colours, lines.items()):
            eps = [float(p["eps"]) for p in line]
            for axis, key in ((error_axis, "rms_error"), (condition_axis, "condition")):
                values = [p[key] for p in line]
                axis.plot(eps, values, "-", color=colour, lw=1.2,
                          label=f"n = {n} ({n * n} nodes)")
                for e, v, p in zip(eps, values, line):
                    if p["method"] == "COD":
                        axis.plot(e, v, "x", color=colour, ms=6, mew=1.5)
                    elif p["warned"]:
                        axis.plot(e, v, "o", mfc="white", mec=colour, ms=6, mew=1.5)
                    else:
                        axis.plot(e, v, "o", color=colour, ms=4)
            best = best_eps(line)
            error_axis.plot(float(best["eps"]), best["rms_error"], "*", color=colour, ms=14,
                            mec="black", mew=0.6, zorder=5)
        condition_axis.axhline(warn_above, color="crimson", ls="--", lw=1)
        condition_axis.text(0.98, warn_above * 1.6, f"warning above {short(warn_above)}",
                            color="crimson", ha="right", va="bottom", fontsize=9,
                            transform=condition_axis.get_yaxis_transform())
        condition_axis.text(0.98, 1.6 / SINGULAR_RCOND,
                            "above 1/2.2e-16 LU is dropped and COD solves\n"
                            "(1/rcond here is itself rounding noise)",
                            color="dimgrey", ha="right", va="bottom", fontsize=8,
                            transform=condition_axis.get_yaxis_transform())
        for axis in (error_axis, condition_axis):
            axis.set_xscale("log", base=2)
            axis.set_yscale("log")
            axis.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
            axis.set_xlabel("shape parameter eps [1 / length; unit square]")
            axis.grid(True, which="major", alpha=0.3)
        # After the log scale, so that the limits are the data's.
        low, high = condition_axis.get_ylim()
        condition_axis.axhspan(1 / SINGULAR_RCOND, high, color="grey", alpha=0.1, lw=0)
        condition_axis.set_ylim(low, high)
        m = plans[model]["fixed"]["m"]
        error_axis.set_ylabel(f"RMS error on the {m} x {m} grid (max |exact| = "
                              f"{EXACT_MAX[model]})")
        condition_axis.set_ylabel("condition estimate 1/rcond (LU, 1-norm)")
        error_axis.set_title(f"{model} ({BASIS[model]}): error against eps",
                             fontsize=10)
        condition_axis.set_title(f"{model}: condition against eps", fontsize=10)
        grey = "dimgrey"
        kinds = [Line2D([], [], ls="", marker="o", color=grey, ms=4, label="LU"),
                 Line2D([], [], ls="", marker="o", mfc="white", mec=grey, mew=1.5, ms=6,
                        label=f"LU, warned (condition > {short(warn_above)})"),
                 Line2D([], [], ls="", marker="x", color=grey, mew=1.5, ms=6,
                        label="COD (rcond < 2.2e-16), warned")]
        handles, _ = error_axis.get_legend_handles_labels()
        star = Line2D([], [], ls="", marker="*", color=grey, mec="black", mew=0.6, ms=12,
                      label="best eps for that n")
        error_axis.legend(handles=handles + kinds + [star], fontsize=8, loc="best")
        condition_axis.legend(fontsize=8, loc="upper right")
    fig.suptitle("The shape parameter: error against the dense solve's conditioning "
                 "(one run per point, 0 steps: the solve is in init)")
    fig.tight_layout()
    sweep.save_figure(fig, png, 100, "rbf_condition")


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        description="RBF interpolation and Kansa collocation: error and condition against "
                    "the shape parameter.",
        epilog="See the docstring at the top of examples/accuracy/rbf_condition.py.")
    parser.add_argument("--small", action="store_true", help="the CI's sweeps")
    parser.add_argument("--models", default="rbf_franke,kansa_poisson")
    parser.add_argument("--build-dir", help="a build directory holding compiler/partc")
    parser.add_argument("--partc", help="the partc to build the models with")
    parser.add_argument("--program", action="append", default=[], metavar="MODEL=EXE",
                        help="a driver program built elsewhere")
    parser.add_argument("--work", help="where builds and logs go (default: BUILD_DIR/rbf_condition, "
                                       "or beside the first --program)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--csv")
    parser.add_argument("--png")
    parser.add_argument("--replot", action="store_true",
                        help="run nothing: print, check and draw the table at --csv")
    parser.add_argument("--expect-shape", action="store_true",
                        help="exit 4 when the shape (see the docstring) does not hold")
    parser.add_argument("--warn-above", type=float, default=1e12,
                        help="the condition above which a run must warn (the runtime's: 1e12)")
    args = parser.parse_args(argv)
    args.models = [m for m in args.models.split(",") if m]
    unknown = [m for m in args.models if m not in BASIS]
    if unknown:
        parser.error(f"unknown model {', '.join(unknown)} (rbf_franke, kansa_poisson)")
    if any("=" not in p for p in args.program):
        parser.error("--program takes MODEL=EXE")
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    if args.replot and not (args.csv and os.path.exists(args.csv)):
        parser.error("--replot reads the table at --csv, which is missing")
    return args


def main(argv):
    args = parse_arguments(argv)
    if args.replot:
        points = [p for p in read_table(args.csv) if p["model"] in args.models]
    else:
        try:
            if args.work is None:
                args.work = sweep.default_work(args.program, args.build_dir, args.partc,
                                               "rbf_condition")
            points = run_sweeps(args, args.models)
        except sweep.SweepError as error:
            print(f"rbf_condition: {error}", file=sys.stderr)
            return 3
        if args.csv:
            write_table(args.csv, points)
    print_table(points)
    failures = check_shape(points, args.warn_above)
    if not failures:
        print("rbf_condition: shape holds: condition rises as eps falls (LU runs; COD at the "
              f"small end), warnings exactly above {short(args.warn_above)}, error falls with n "
              "at a well-conditioned eps")
    for failure in failures:
        print(f"rbf_condition: {'expectation failed' if args.expect_shape else 'shape'}: "
              f"{failure}")
    if args.png:
        draw(args.png, points, PLANS["small" if args.small else "full"], args.warn_above)
    return 4 if failures and args.expect_shape else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
