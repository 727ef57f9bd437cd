// bench_lj: LAMMPS's "melt" workload (in.melt at benchmark size) run by the
// partc model examples/lj_melt.part, timed next to LAMMPS itself.
//
// 32000 Lennard-Jones atoms (epsilon = sigma = mass = 1, cutoff 2.5, not
// shifted) start on an fcc lattice at reduced density 0.8442 with velocities
// for T = 3.0 and zero total momentum; velocity Verlet, dt = 0.005, 100 steps;
// forces from Verlet lists with a skin of 0.3. The starting state is built
// here (lj_melt_setup.hpp) and loaded through the generated class's load().
//
// Measured, on one thread (OMP_NUM_THREADS=1 from .ci/bench):
// - the loop time of the 100 steps (the run of median loop time among
//   `repetitions` runs from the same start) and so the time per step. partc's
//   first step builds the Verlet lists; LAMMPS builds its first lists in its
//   setup, outside its "Loop time", so the ratio is also given without step 1.
// - neighbour list rebuilds, as the model reports them (search_report). Steps with and without
//   a rebuild, timed one by one, split a step into the force sum (with the
//   integration, a few percent) and the list build, as LAMMPS's Pair and
//   Neigh timings do.
// - physics, in an untimed run: temperature and energies every 10 steps,
//   computed here with a hand-written cell list (lj_melt_setup.hpp), not by
//   partc; and the model's forces at step 100 against the hand-written ones,
//   which must agree (else the timings would be of different work).
//
// LAMMPS (optional): each argument is a LAMMPS log of this workload
// (.ci/bench writes the inputs and runs lmp). Logs are grouped by their
// neigh_modify and pair_style lines, i.e. by rebuild policy and pair kernel:
// in.melt's "every 20 delay 0 check no" rebuilds every 20 steps
// unconditionally (5 times in 100 steps, without checking that no pair was
// missed), "every 1 delay 0 check yes" rebuilds when some atom moved more than
// half the skin: partc's policy; lj/cut/opt is the OPT package's kernel (what
// -sf opt picks), LAMMPS's fastest serial one. Per group: the median loop
// time, and the first log's thermo output and build count.
//
// Usage: bench_lj [LAMMPS_LOG]...
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "lammps_log.hpp"
// lj_melt_setup.hpp includes the generated lj_melt.hpp, which has no include
// guard: including it here as well would define LjMelt twice.
#include "timing.hpp"
#include "lj_melt_setup.hpp"

namespace {

using namespace lj_melt_bench;

// Runs of the 100 steps; the median loop time is kept (see bench_md.cpp).
constexpr int repetitions = 3;
// Energies and temperature every this many steps, in the untimed run.
constexpr int thermo_every = 10;
// The model's f and the hand-written force sum the same pair terms in another
// order and with other roundings (s = 1/r^2 powers against r^-6 ones): ~1e-15
// relative per term. A missing or extra pair changes a force by a whole term.
constexpr double force_tolerance = 1e-10;

// Thermo rows, LAMMPS's and partc's (computed here) alike.
using bench::Thermo;

// One run of the 100 steps as partc does it.
struct PartcRun {
  double loop_seconds = 0.0;
  std::vector<double> step_seconds;  // step k + 1 at index k
  std::vector<int> rebuild_steps;    // steps that rebuilt the Verlet lists
  std::vector<Thermo> thermo;        // untimed run only
};

Thermo thermo_of(int step, const MeltState& s) {
  const double n = static_cast<double>(s.size());
  return {step, s.temperature(), s.potential / n, s.potential / n, 0.0, s.total_energy() / n};
}

// Timed: only step() is inside the clock. Untimed (physics): thermo every
// thermo_every steps and the force check at the end.
PartcRun run_partc(const MeltState& start, bool physics) {
  LjMelt model;
  load_melt(model, start);
  PartcRun run;
  if (physics) run.thermo.push_back(thermo_of(0, start));
  std::size_t builds = list_builds(model);
  for (int step = 1; step <= steps; ++step) {
    const auto t0 = std::chrono::steady_clock::now();
    model.step();
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - t0;
    run.step_seconds.push_back(elapsed.count());
    run.loop_seconds += elapsed.count();
    if (list_builds(model) != builds) {
      run.rebuild_steps.push_back(step);
      builds = list_builds(model);
    }
    if (physics && step % thermo_every == 0)
      run.thermo.push_back(thermo_of(step, melt_state(model)));
  }
  if (physics) {
    std::vector<Vec3> model_force;
    const MeltState end = melt_state(model, &model_force);
    double worst = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < end.size(); ++i) {
      const Vec3 &a = model_force[i], &b = end.force[i];
      worst = std::max(worst, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
      scale = std::max(scale, std::hypot(b[0], b[1], b[2]));
    }
    if (!(worst <= force_tolerance * scale)) {
      std::fprintf(stderr,
                   "bench_lj: at step %d the model's forces differ from the hand-written ones by "
                   "%.3g relative (tolerance %g)\n",
                   steps, worst / scale, force_tolerance);
      std::exit(1);
    }
  }
  return run;
}

// The logs of one rebuild policy.
struct LammpsPolicy {
  bench::LammpsLog first;
  std::vector<double> loop_seconds;
};

std::string list(const std::vector<int>& steps) {
  std::string s;
  for (const int k : steps) s += (s.empty() ? "" : " ") + std::to_string(k);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<LammpsPolicy> lammps;  // in the order of the arguments
  for (int a = 1; a < argc; ++a) {
    const std::optional<bench::LammpsLog> log = bench::read_lammps_log(argv[a]);
    if (!log) {
      std::fprintf(stderr, "bench_lj: %s: not a LAMMPS log with a thermo table and a loop time\n",
                   argv[a]);
      return 2;
    }
    auto same = std::find_if(lammps.begin(), lammps.end(), [&](const LammpsPolicy& p) {
      return p.first.neigh_modify == log->neigh_modify && p.first.pair_style == log->pair_style;
    });
    if (same == lammps.end()) same = lammps.insert(lammps.end(), {*log, {}});
    same->loop_seconds.push_back(log->loop_seconds);
  }

  const MeltState start = melt_start();
  std::printf(
      "LJ melt (LAMMPS in.melt at 20^3 fcc cells): %zu atoms, density %g, box %.6f, rc %g,\n"
      "dt 0.005, %d steps, one thread; partc: examples/lj_melt.part, Verlet lists with skin 0.3.\n"
      "Loop time: median of %d runs (partc) / of the logs given (LAMMPS). Compiler: %s\n",
      start.size(), density, box_length(), cutoff, steps, repetitions, __VERSION__);

  const PartcRun physics = run_partc(start, true);
  std::vector<PartcRun> runs;
  for (int r = 0; r < repetitions; ++r) runs.push_back(run_partc(start, false));
  std::sort(runs.begin(), runs.end(),
            [](const PartcRun& a, const PartcRun& b) { return a.loop_seconds < b.loop_seconds; });
  const PartcRun& timed = runs[runs.size() / 2];
  const double partc_loop = timed.loop_seconds;

  // Steps 2..100 of the median run, with and without a rebuild. Step 1 builds
  // the first lists, which LAMMPS does in its setup, before its loop.
  double rebuild_time = 0.0, other_time = 0.0;
  int rebuilds = 0, others = 0;
  for (int step = 2; step <= steps; ++step) {
    const double t = timed.step_seconds[static_cast<std::size_t>(step - 1)];
    if (std::count(timed.rebuild_steps.begin(), timed.rebuild_steps.end(), step)) {
      rebuild_time += t;
      ++rebuilds;
    } else {
      other_time += t;
      ++others;
    }
  }
  const double other_step = others ? other_time / others : std::nan("");
  const double rebuild_step = rebuilds ? rebuild_time / rebuilds : std::nan("");

  // Side by side: partc, then each LAMMPS log group (rebuild policy).
  const double nan = std::nan("");
  std::printf("\n%-40s %12s", "", "partc");
  for (std::size_t k = 0; k < lammps.size(); ++k) std::printf(" %11s%zu", "LAMMPS ", k + 1);
  std::printf("\n");
  const auto row = [&](const char* label, double partc_value, auto&& lammps_value,
                       const char* format) {
    std::printf("%-40s", label);
    const auto print = [format](double v) {
      char cell[64] = "-";
      if (!std::isnan(v)) std::snprintf(cell, sizeof cell, format, v);
      std::printf(" %12s", cell);
    };
    print(partc_value);
    for (const LammpsPolicy& p : lammps) print(lammps_value(p));
    std::printf("\n");
  };
  const auto lammps_loop = [](const LammpsPolicy& p) { return bench::median(p.loop_seconds); };
  row("loop time of 100 steps / s", partc_loop, lammps_loop, "%.3f");
  row(
      "time per step / ms", 1e3 * partc_loop / steps,
      [&](const LammpsPolicy& p) { return 1e3 * lammps_loop(p) / steps; }, "%.2f");
  row(
      "partc loop time / LAMMPS loop time", nan,
      [&](const LammpsPolicy& p) { return partc_loop / lammps_loop(p); }, "%.2f");
  row(
      "  the same, partc without step 1", nan,
      [&](const LammpsPolicy& p) {
        return (partc_loop - timed.step_seconds[0]) * steps / (steps - 1) / lammps_loop(p);
      },
      "%.2f");
  row(
      "list builds in the loop", rebuilds,
      [](const LammpsPolicy& p) { return static_cast<double>(p.first.builds); }, "%.0f");
  row(
      "step without a list build / ms (a)", 1e3 * other_step,
      [](const LammpsPolicy& p) { return 1e3 * p.first.pair_seconds / steps; }, "%.2f");
  row(
      "one list build / ms (b)", 1e3 * (rebuild_step - other_step),
      [](const LammpsPolicy& p) {
        return p.first.builds > 0 ? 1e3 * p.first.neigh_seconds / p.first.builds : std::nan("");
      },
      "%.2f");
  for (const int step : {0, 50, 100}) {
    const Thermo* ours = bench::at_step(physics.thermo, step);
    const auto theirs = [step](const LammpsPolicy& p) {
      return bench::at_step(p.first.thermo, step);
    };
    char label[64];
    std::snprintf(label, sizeof label, "T at step %d", step);
    row(
        label, ours->temperature,
        [&](const LammpsPolicy& p) { return theirs(p) ? theirs(p)->temperature : nan; }, "%.4f");
    std::snprintf(label, sizeof label, "E_tot / atom at step %d", step);
    row(
        label, ours->total,
        [&](const LammpsPolicy& p) { return theirs(p) ? theirs(p)->total : nan; }, "%.6f");
  }
  const auto drift = [](const std::vector<Thermo>& thermo) {
    const Thermo *first = bench::at_step(thermo, 0), *last = bench::at_step(thermo, steps);
    return first && last ? (last->total - first->total) / std::abs(first->total) : std::nan("");
  };
  row(
      "E_tot drift, steps 0-100 (relative)", drift(physics.thermo),
      [&](const LammpsPolicy& p) { return drift(p.first.thermo); }, "%+.2e");
  std::printf(
      "(a) partc: mean of steps 2-100 without a rebuild; LAMMPS: its Pair time / 100 steps\n"
      "(b) partc: mean of the steps with a rebuild - (a); LAMMPS: its Neigh time / builds\n");
  for (std::size_t k = 0; k < lammps.size(); ++k)
    std::printf("LAMMPS %zu: pair_style %s, neigh_modify %s (%zu runs)\n", k + 1,
                lammps[k].first.pair_style.c_str(), lammps[k].first.neigh_modify.c_str(),
                lammps[k].loop_seconds.size());
  if (lammps.empty()) std::printf("(no LAMMPS logs given: no LAMMPS columns)\n");

  std::printf("\npartc rebuilt its lists in steps %s; step 1 took %.2f ms\n",
              list(timed.rebuild_steps).c_str(), 1e3 * timed.step_seconds[0]);

  std::printf(
      "\npartc's thermo, computed by bench_lj (not by partc): T over 3N-3 degrees of freedom,\n"
      "energies per atom, LJ truncated at rc and not shifted (as LAMMPS's lj/cut)\n");
  std::printf("%6s %10s %12s %12s %12s\n", "step", "T", "E_pair", "E_tot", "E_tot-E_0");
  for (const Thermo& t : physics.thermo)
    std::printf("%6d %10.5f %12.6f %12.6f %+12.3e\n", t.step, t.temperature, t.e_pair, t.total,
                t.total - physics.thermo.front().total);
  return 0;
}
