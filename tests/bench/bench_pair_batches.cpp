// bench_pair_batches: what packing each point's pairs (simd/pair_batches.hpp)
// buys the seed velocity update, before the compiler emits it: the sum
//
//   S_i = sum over 0 < |dx| < rc of -exp(-|dx|) dx / |dx|,   rc = sqrt(3 / N)
//
// over uniform points of the periodic unit square, each pair once (Newton's
// third law), computed by
//   scalar   OrderedCellList::for_each_pair with the term one pair at a time,
//            as partc's generated code does today;
//   batch    PairBatches: the pairs of consecutive points packed by
//            compress-stores, the term on full Highway vectors (hn::Exp,
//            Div), then scattered to i and j from columns; written as the
//            compiler will emit it;
// beside the floor's hand-vectorised kernels in the same run (compact_simd:
// AVX2 packing, every pair twice; sell4: a precomputed SELL-4 list, pure pair
// arithmetic). Structures are built before timing, as the floor does; the
// batch's coordinate copy (PairBatches::build) is timed on its own line.
// Each sum is checked against a brute-force one (N <= 2e4) or the scalar one.
//
// Usage: bench_pair_batches [--n 1000,10000,100000,1000000] [--repeats 5]
// One thread; medians of --repeats timings of floor(1000 / N) + 1 updates.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "partc/domain.hpp"
#include "partc/parallel.hpp"
#include "partc/search/ordered_cell_list.hpp"
#include "partc/simd/pair_batches.hpp"
#include "seed_points.hpp"
#include "size_list.hpp"
#include "timing.hpp"
#ifdef PARTC_BENCH_FLOOR
#include "floor_kernels.hpp"
#endif

namespace {

using partc::Vec;
using Vec2 = Vec<2>;
namespace simd = partc::simd;
namespace hn = partc::simd::hn;

using bench::uniform_points;

// The scalar pair walk, term as the generated code writes it.
void sum_scalar(const partc::OrderedCellList<2>& cells, double rc, std::vector<Vec2>& sum) {
  sum.assign(sum.size(), Vec2::zero());
  cells.for_each_pair([&](std::size_t i, const auto& pairs_of_i) {
    Vec2 sum_i = Vec2::zero();
    pairs_of_i([&](std::size_t j, const Vec2& dx) {
      const double dx_norm = partc::norm(dx);
      if (dx_norm < rc && dx_norm > 0) {
        const Vec2 term = -std::exp(-dx_norm) * dx / dx_norm;
        sum_i += term;
        if (j != i) sum[j] -= term;
      }
    });
    sum[i] += sum_i;
  });
}

// The packed walk: the term per component on vectors of pairs, masked by the
// sum's condition (the padding's terms are computed and never read), kept in
// two columns; then each
// pair's term scattered to both ends (i +=, j -=), after the vector loop so
// as not to serialise it. No pair (i, i): the condition |dx| > 0 excludes it.
// The term's scalar factors taken together, -exp(-r) / r, times dx: one
// division a pair, not one per component (measured: 1.5x the time with two).
void sum_batches(const partc::OrderedCellList<2>& cells, simd::PairBatches<2>& batches, double rc,
                 std::vector<Vec2>& sum) {
  sum.assign(sum.size(), Vec2::zero());
  batches.for_each_pair(cells, false, [&](simd::PairBatch<2>& b) {
    const simd::Real d;
    const std::size_t lanes = hn::Lanes(d);
    b.columns(2);
    double* term0 = b.column(0);
    double* term1 = b.column(1);
    const auto rc_v = hn::Set(d, rc);
    const auto zero = hn::Zero(d);
    for (std::size_t k = 0; k < b.padded(); k += lanes) {
      const auto dx0 = hn::LoadU(d, b.dx(0) + k), dx1 = hn::LoadU(d, b.dx(1) + k);
      const auto dx_norm = hn::Sqrt(hn::LoadU(d, b.r2() + k));
      const auto when = hn::And(hn::Lt(dx_norm, rc_v), hn::Gt(dx_norm, zero));
      const auto scale =
          hn::IfThenElseZero(when, hn::Div(hn::Neg(hn::Exp(d, hn::Neg(dx_norm))), dx_norm));
      hn::StoreU(hn::Mul(scale, dx0), d, term0 + k);
      hn::StoreU(hn::Mul(scale, dx1), d, term1 + k);
    }
    const std::uint64_t* is = b.i();
    const std::uint64_t* js = b.j();
    for (std::size_t k = 0; k < b.count(); ++k) {
      sum[is[k]][0] += term0[k];
      sum[is[k]][1] += term1[k];
      sum[js[k]][0] -= term0[k];
      sum[js[k]][1] -= term1[k];
    }
  });
}

// All pairs, for the check: the minimum image in the unit square.
std::vector<Vec2> sum_brute(const std::vector<Vec2>& p, double rc) {
  std::vector<Vec2> sum(p.size(), Vec2::zero());
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      Vec2 dx = p[j] - p[i];
      for (int k = 0; k < 2; ++k) dx[k] -= std::nearbyint(dx[k]);
      const double r = partc::norm(dx);
      if (r < rc && r > 0) sum[i] += -std::exp(-r) * dx / r;
    }
  return sum;
}

// Relative L2 distance of two sums (in one order).
double distance(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    num += partc::squared_norm(a[i] - b[i]);
    den += partc::squared_norm(b[i]);
  }
  return std::sqrt(num / den);
}

}  // namespace

int run(const std::vector<std::size_t>& sizes, int repeats);

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes{1000, 10000, 100000, 1000000};
  int repeats = 5;
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string flag = argv[a];
    if (flag == "--n")
      sizes = bench::parse_sizes(argv[a + 1]);
    else if (flag == "--repeats")
      repeats = std::atoi(argv[a + 1]);
    else {
      std::fprintf(stderr, "bench_pair_batches: unknown flag %s\n", argv[a]);
      return 2;
    }
  }
  return partc::with_threads(1, [&] { return run(sizes, repeats); });
}

int run(const std::vector<std::size_t>& sizes, int repeats) {
  std::printf("seed velocity update, one thread, %zu lanes of double; N/Te in points per second\n",
              simd::lanes());
  std::printf("%9s %12s %12s %12s %12s %12s %10s %10s %11s\n", "N", "scalar", "batch",
              "compact_simd", "sell4", "batch_build", "batch/cmp", "batch/sell4", "batch_err");
  for (const std::size_t n : sizes) {
    const double rc = std::sqrt(3.0 / static_cast<double>(n));
    const std::vector<Vec2> points = uniform_points(n);
    const partc::Domain<2> domain = bench::periodic_unit_square();
    partc::OrderedCellList<2> cells;
    cells.build(domain, rc, points);
    simd::PairBatches<2> batches;
    const double build_s = bench::seconds([&] { batches.build(cells, n); });

    std::vector<Vec2> scalar(n), batch(n);
    sum_scalar(cells, rc, scalar);
    sum_batches(cells, batches, rc, batch);
    // The check: against all pairs where affordable, else against the scalar walk.
    std::vector<Vec2> reference = scalar;
    if (n <= 20000) {
      const std::vector<Vec2> brute = sum_brute(points, rc);
      reference.assign(n, Vec2::zero());
      for (std::size_t k = 0; k < n; ++k) reference[k] = brute[cells.order()[k]];
      if (distance(scalar, reference) > 1e-13) {
        std::fprintf(stderr, "scalar walk disagrees with brute force at N = %zu\n", n);
        return 1;
      }
    }
    const double error = distance(batch, reference);
    if (error > 1e-13) {
      std::fprintf(stderr, "batch walk disagrees: relative L2 %.3g at N = %zu\n", error, n);
      return 1;
    }

    const int per_timing = static_cast<int>(1000 / n) + 1;
    std::vector<double> t_scalar, t_batch, t_compact, t_sell4;
#ifdef PARTC_BENCH_FLOOR
    std::vector<double> x(n), y(n);
    for (std::size_t k = 0; k < n; ++k) x[k] = points[k][0], y[k] = points[k][1];
    const bool floor_ok = floor_ref::VelocityUpdate::applicable(rc);
    const bool sell4_ok = floor_ok && floor_ref::VelocityUpdate::sell4_fits(int(n), rc);
    std::optional<floor_ref::VelocityUpdate> floor;
    if (floor_ok) floor.emplace(x.data(), y.data(), int(n), rc, 1.0, sell4_ok);
#endif
    for (int r = 0; r < repeats; ++r) {
      t_scalar.push_back(bench::seconds([&] { sum_scalar(cells, rc, scalar); }, per_timing) /
                         per_timing);
      t_batch.push_back(
          bench::seconds([&] { sum_batches(cells, batches, rc, batch); }, per_timing) / per_timing);
#ifdef PARTC_BENCH_FLOOR
      if (floor) {
        t_compact.push_back(bench::seconds([&] { floor->update_compact(); }, per_timing) /
                            per_timing);
        if (sell4_ok)
          t_sell4.push_back(bench::seconds([&] { floor->update_sell4(); }, per_timing) /
                            per_timing);
      }
#endif
    }
    const auto rate = [&](const std::vector<double>& t) {
      return t.empty() ? 0.0 : static_cast<double>(n) / bench::median(t);
    };
    const auto ratio = [&](const std::vector<double>& t) {
      return t.empty() ? 0.0 : bench::median(t_batch) / bench::median(t);
    };
    std::printf("%9zu %12.3e %12.3e %12.3e %12.3e %12.3e %10.2f %10.2f %11.2e\n", n, rate(t_scalar),
                rate(t_batch), rate(t_compact), rate(t_sell4), static_cast<double>(n) / build_s,
                ratio(t_compact), ratio(t_sell4), error);
  }
  std::printf(
      "batch/cmp, batch/sell4: batch's time over the floor kernel's (< 1: faster); a 0 is a "
      "kernel not run (the floor needs 3 cells a side, SELL-4 fits in memory)\n");
  return 0;
}
