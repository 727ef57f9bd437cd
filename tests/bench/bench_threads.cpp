// bench_threads: what a second thread buys partc's generated kernels. Each
// workload runs with 1 and with 2 threads (partc::with_threads, in one
// process, on identical data), taking turns so that a slow spell of the
// machine hits both alike; the table gives both times and the speedup.
//
// - The md velocity update of bench_md (md_velocity.part.in) at N = 10^5 and
//   10^6, rc = sqrt(3/N): uniform static points, search built before timing;
//   Te is one update, from batches of at least `min_batch_seconds` (median of
//   `repetitions`).
// - The LJ melt of bench_lj (examples/lj_melt.part, 32000 atoms, 100 steps
//   from the same start; median of `repetitions` runs). Its steps are also
//   split into those that rebuilt the Verlet lists (counted, as in bench_lj, by
//   the model's search_report) and the rest: the list build's queries run in
//   parallel, but NeighbourSearch::build and ParticleSet::permute are serial;
//   the force sum runs in two parallel phases of slabs.
// The runtime promises results bitwise independent of the thread count: the
// final LJ state of both thread counts is compared, and the answer printed.
// The first and last rows time a loop of arithmetic alone (no memory traffic,
// no imbalance), as a reference for what a second thread can give on this
// machine at that moment: on a shared machine whose other core is busy, well
// under 2, and the kernels' speedups between them mean little.
//
// Usage: bench_threads (no arguments; see .ci/bench). Needs OpenMP, and two
// cores for a meaningful speedup.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

// Generated headers have no include guard: each is included exactly once
// (lj_melt.hpp through lj_melt_setup.hpp).
#include "partc/parallel.hpp"
#include "timing.hpp"
#include "lj_melt_setup.hpp"
#include "md_velocity.hpp"

namespace {

constexpr int repetitions = 3;
constexpr double min_batch_seconds = 0.2;
constexpr int thread_counts[] = {1, 2};

void print_row(const char* kernel, std::size_t n, double one, double two) {
  std::printf("%-40s %8zu %12.3e %12.3e %8.2f\n", kernel, n, one, two, one / two);
}

// The reference: sum of sqrt(k) over a fixed range, in blocks handed out by
// partc::parallel_for, a partial sum each.
void arithmetic_reference(const char* label) {
  constexpr long count = 100000000;
  constexpr long blocks = 64;
  volatile double sink = 0.0;  // keeps the compiler from dropping the loop
  std::vector<double> partial(blocks);
  const auto loop = [&] {
    partc::parallel_for(blocks, partc::LoopWork::blocks, [&](std::size_t b) {
      double s = 0.0;
      const long first = static_cast<long>(b) * (count / blocks);
      for (long k = first; k < first + count / blocks; ++k) s += std::sqrt(static_cast<double>(k));
      partial[b] = s;
    });
    double s = 0.0;
    for (const double p : partial) s += p;
    sink = sink + s;
  };
  std::vector<double> te[2];
  for (int r = 0; r < repetitions; ++r)
    for (int t = 0; t < 2; ++t) {
      te[t].push_back(partc::with_threads(thread_counts[t], [&] { return bench::seconds(loop); }));
    }
  print_row(label, static_cast<std::size_t>(count), bench::median(te[0]), bench::median(te[1]));
}

// As bench_md: uniform points in the unit square, loaded with ids 0..N-1.
void md_update(std::size_t n) {
  std::mt19937_64 random(2017);
  const auto uniform = [&random] { return static_cast<double>(random() >> 11) * 0x1p-53; };
  MdVelocity model;
  model.params().N = static_cast<std::int64_t>(n);
  model.params().c = 1e-3;
  model.params().rc = std::sqrt(3.0 / static_cast<double>(n));
  partc::CsvTable table;
  table.header = {"id", "p_0", "p_1"};
  for (std::size_t i = 0; i < n; ++i)
    table.rows.push_back({static_cast<double>(i), uniform(), uniform()});
  model.load({{"P", table}});
  // The first step builds the cell list.
  const double first = partc::with_threads(1, [&] { return bench::seconds([&] { model.step(); }); });
  const int batch = std::max(1, static_cast<int>(min_batch_seconds / first));
  std::vector<double> te[2];
  for (int r = 0; r < repetitions; ++r)
    for (int t = 0; t < 2; ++t) {
      te[t].push_back(partc::with_threads(thread_counts[t], [&] {
        bench::seconds([&] { model.step(); }, batch);
        return bench::seconds([&] { model.step(); }, batch) / batch;
      }));
    }
  print_row("md velocity update, Te / s", n, bench::median(te[0]), bench::median(te[1]));
}

struct MeltRun {
  double loop = 0.0, rebuild_steps = 0.0, other_steps = 0.0;  // seconds
  int rebuilds = 0;
  std::vector<lj_melt_bench::Vec3> final_position;  // by id
};

MeltRun melt_run(const lj_melt_bench::MeltState& start) {
  LjMelt model;
  lj_melt_bench::load_melt(model, start);
  MeltRun run;
  std::size_t builds = lj_melt_bench::list_builds(model);
  for (int step = 1; step <= lj_melt_bench::steps; ++step) {
    const double t = bench::seconds([&] { model.step(); });
    run.loop += t;
    if (lj_melt_bench::list_builds(model) != builds) {
      builds = lj_melt_bench::list_builds(model);
      run.rebuild_steps += t;
      ++run.rebuilds;
    } else {
      run.other_steps += t;
    }
  }
  run.final_position = lj_melt_bench::melt_state(model).position;
  return run;
}

void lj_melt() {
  const lj_melt_bench::MeltState start = lj_melt_bench::melt_start();
  std::vector<MeltRun> runs[2];
  for (int r = 0; r < repetitions; ++r)
    for (int t = 0; t < 2; ++t) {
      runs[t].push_back(partc::with_threads(thread_counts[t], [&] { return melt_run(start); }));
    }
  // The run of median loop time, per thread count.
  const auto typical = [](std::vector<MeltRun> v) {
    std::sort(v.begin(), v.end(),
              [](const MeltRun& a, const MeltRun& b) { return a.loop < b.loop; });
    return v[v.size() / 2];
  };
  const MeltRun one = typical(runs[0]), two = typical(runs[1]);
  const std::size_t n = start.size();
  const int steps = lj_melt_bench::steps;
  print_row("LJ melt, time per step / s", n, one.loop / steps, two.loop / steps);
  if (one.rebuilds == two.rebuilds && one.rebuilds > 0 && one.rebuilds < steps) {
    print_row("  steps that rebuilt the lists / s", n, one.rebuild_steps / one.rebuilds,
              two.rebuild_steps / two.rebuilds);
    print_row("  steps that did not / s", n, one.other_steps / (steps - one.rebuilds),
              two.other_steps / (steps - two.rebuilds));
  }
  std::printf(
      "  (%d of %d steps rebuilt the lists, step 1 included; final positions bitwise %s for 1 and "
      "2 threads)\n",
      one.rebuilds, steps, one.final_position == two.final_position ? "identical" : "DIFFERENT");
}

}  // namespace

int main() {
#if defined(_OPENMP)
  std::printf("1 vs 2 threads (%d processors available). Compiler: %s\n\n",
              omp_get_num_procs(), __VERSION__);
#else
  std::printf("Built without OpenMP: both columns are one thread. Compiler: %s\n\n", __VERSION__);
#endif
  std::printf("%-40s %8s %12s %12s %8s\n", "kernel", "N", "1 thread", "2 threads", "speedup");
  arithmetic_reference("reference: arithmetic only / s");
  md_update(100000);
  md_update(1000000);
  lj_melt();
  arithmetic_reference("reference again, after / s");
}
