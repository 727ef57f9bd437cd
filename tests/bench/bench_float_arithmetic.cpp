// bench_float_arithmetic: what float lanes (schedule: arithmetic = float)
// buy the seed velocity update
//
//   v[i] += c * sum(j, |dx| < rc and |dx| > 0, -exp(-|dx|) * dx / |dx|),  rc = sqrt(3 / N)
//
// as partc emits it with double arithmetic (md_velocity) and with float
// arithmetic (md_velocity_float), on the same uniform points of the periodic
// unit square, one thread, positions fixed (the search is built by the first
// update, as in bench_md). Per N:
//   double, float   the time of one update: median of --repeats timings of
//                   floor(3e6 / N) + 1 updates, interleaved with the others;
//   walk            the pair walk alone (PairBatches over an OrderedCellList
//                   at rc, the structure the models' searches choose here, the
//                   batches handed to a callback that computes nothing): the
//                   part float lanes leave in double;
//   +scatter        the walk and, per batch, the generated code's scatter of
//                   its term columns to i and j (scalar, into double sums),
//                   the terms not computed;
//   rest            an update's time less the walk's and the scatter's: its
//                   term loop, and clearing and applying the sums, in each
//                   build (what float lanes speed up);
//   err             the relative L2 error of v's increment after one update,
//                   ||v - v_ref|| / ||v_ref||, against a long double
//                   reference (seed_reference.hpp).
//
// Usage: bench_float_arithmetic [--n 10000,100000,1000000] [--repeats 5]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "md_velocity.hpp"
#include "md_velocity_float.hpp"
#include "partc/domain.hpp"
#include "partc/parallel.hpp"
#include "partc/search/ordered_cell_list.hpp"
#include "partc/simd/pair_batches.hpp"
#include "seed_model.hpp"
#include "seed_points.hpp"
#include "seed_reference.hpp"
#include "size_list.hpp"
#include "timing.hpp"

namespace {

using Vec2 = partc::Vec<2>;
constexpr double force_strength = 1e-3;  // c

using bench::uniform_points;

int run(const std::vector<std::size_t>& sizes, int repeats) {
  std::printf(
      "seed velocity update as partc emits it, one thread, %zu lanes of double, %zu of float;\n"
      "times in s per update (medians of %d), err = relative L2 of v's increment against long "
      "double\n",
      partc::simd::lanes(), partc::simd::hn::Lanes(partc::simd::Float()), repeats);
  std::printf("%9s %10s %10s %8s %10s %10s %8s %8s %10s %10s %9s %9s\n", "N", "double", "float",
              "speedup", "walk", "+scatter", "walk/d", "+sc/d", "rest_d", "rest_f", "err_d",
              "err_f");
  for (const std::size_t n : sizes) {
    const double rc = std::sqrt(3.0 / static_cast<double>(n));
    const std::vector<Vec2> points = uniform_points(n);
    MdVelocity in_double;
    MdVelocityFloat in_float;
    bench::load_seed_points(in_double, points, rc, force_strength);
    bench::load_seed_points(in_float, points, rc, force_strength);
    // One update each from v = 0 (v then holds the increment), before any timing;
    // the first builds each model's search.
    in_double.step();
    in_float.step();
    const auto reference = bench::seed_reference(points, rc, force_strength);
    const double err_double =
        bench::seed_errors(bench::seed_velocities(in_double), reference).relative_l2;
    const double err_float =
        bench::seed_errors(bench::seed_velocities(in_float), reference).relative_l2;

    const partc::Domain<2> domain = bench::periodic_unit_square();
    partc::OrderedCellList<2> cells;
    cells.build(domain, rc, points);
    partc::simd::PairBatches<2> batches;
    batches.build(cells, n);
    std::size_t pairs = 0;  // read after timing: the walk is not optimised away
    const auto walk = [&] {
      batches.for_each_pair(cells, false,
                            [&](partc::simd::PairBatch<2>& b) { pairs += b.count(); });
    };
    std::vector<Vec2> sums(n);
    const auto walk_and_scatter = [&] {
      batches.for_each_pair(cells, false, [&](partc::simd::PairBatch<2>& b) {
        b.columns(2);
        const double* const term_0 = b.column(0);
        const double* const term_1 = b.column(1);
        for (std::size_t k = 0; k < b.count(); ++k) {
          const std::size_t i = b.i()[k], j = b.j()[k];
          sums[i] += Vec2{{term_0[k], term_1[k]}};
          if (j != i) sums[j] -= Vec2{{term_0[k], term_1[k]}};
        }
      });
    };

    // About 3e6 point updates a timing (0.1 to 0.2 s here): long enough to
    // average over the scheduler's slices when other jobs share the cores,
    // which single updates of a few ms do not (they came out bimodal).
    const int per_timing = static_cast<int>(3000000 / n) + 1;
    std::vector<double> t_double, t_float, t_walk, t_scatter;
    for (int r = 0; r < repeats; ++r) {
      t_double.push_back(bench::seconds([&] { in_double.step(); }, per_timing) / per_timing);
      t_float.push_back(bench::seconds([&] { in_float.step(); }, per_timing) / per_timing);
      t_walk.push_back(bench::seconds(walk, per_timing) / per_timing);
      t_scatter.push_back(bench::seconds(walk_and_scatter, per_timing) / per_timing);
    }
    const double td = bench::median(t_double), tf = bench::median(t_float),
                 tw = bench::median(t_walk), ts = bench::median(t_scatter);
    std::printf("%9zu %10.3e %10.3e %8.2f %10.3e %10.3e %8.2f %8.2f %10.3e %10.3e %9.2e %9.2e\n", n,
                td, tf, td / tf, tw, ts, tw / td, ts / td, td - ts, tf - ts, err_double, err_float);
    if (pairs == 0) std::printf("  (no pairs walked)\n");
  }
  std::printf(
      "speedup: double's time over float's; walk/d, +sc/d: the shares of the double update\n"
      "that the walk, and the walk with the scatter, take; rest_d, rest_f: double's and float's\n"
      "update less the walk and the scatter; err_d, err_f: each build's relative L2 error\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes = {10000, 100000, 1000000};
  int repeats = 5;
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string flag = argv[a];
    if (flag == "--n") {
      sizes = bench::parse_sizes(argv[a + 1]);
    } else if (flag == "--repeats") {
      repeats = std::atoi(argv[a + 1]);
    } else {
      std::fprintf(stderr,
                   "usage: bench_float_arithmetic [--n 10000,100000,1000000] [--repeats 5]\n");
      return 2;
    }
  }
  if (repeats < 3) repeats = 3;  // a median of fewer is no median
  return partc::with_threads(1, [&] { return run(sizes, repeats); });
}
