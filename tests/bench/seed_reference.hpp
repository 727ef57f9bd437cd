// The seed velocity update's increment, c * sum(j, |dx| < rc and |dx| > 0,
// -exp(-|dx|) * dx / |dx|), summed in long double on the periodic unit
// square, and the errors of a computed increment against it: the reference
// of the benches and figures that measure what a precision choice costs on
// the seed (bench_float_arithmetic, tests/accuracy/seed_precision).
//
// Written apart from the runtime on purpose: a grid of cells at least rc
// wide (rc <= 1/3, so N >= 27), each point against its 3 x 3 cells with the
// minimum image, each pair summed from both ends (no Newton's third law),
// so nothing is shared with the code under test but the points.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "partc/parallel.hpp"
#include "partc/vec.hpp"

namespace bench {

inline std::vector<std::array<long double, 2>> seed_reference(
    const std::vector<partc::Vec<2>>& points, double rc, double c) {
  const std::size_t side = static_cast<std::size_t>(std::floor(1.0 / rc));
  std::vector<std::vector<std::size_t>> cells(side * side);
  const auto cell_of = [&](double x) {
    return std::min(side - 1, static_cast<std::size_t>(x * static_cast<double>(side)));
  };
  for (std::size_t k = 0; k < points.size(); ++k)
    cells[cell_of(points[k][0]) * side + cell_of(points[k][1])].push_back(k);
  const long double rcl = rc;
  std::vector<std::array<long double, 2>> sums(points.size(), {0.0L, 0.0L});
  partc::parallel_for(points.size(), partc::LoopWork::heavy, [&](std::size_t i) {
    const std::size_t cx = cell_of(points[i][0]), cy = cell_of(points[i][1]);
    for (std::size_t ox = side - 1; ox <= side + 1; ++ox)
      for (std::size_t oy = side - 1; oy <= side + 1; ++oy)
        for (const std::size_t j : cells[(cx + ox) % side * side + (cy + oy) % side]) {
          std::array<long double, 2> dx;
          for (int d = 0; d < 2; ++d) {
            dx[d] = static_cast<long double>(points[j][d]) - points[i][d];
            dx[d] -= std::nearbyint(dx[d]);  // the minimum image in the unit box
          }
          const long double r = std::sqrt(dx[0] * dx[0] + dx[1] * dx[1]);
          if (!(r < rcl && r > 0)) continue;
          const long double s = -std::exp(-r) / r;
          for (int d = 0; d < 2; ++d) sums[i][d] += c * s * dx[d];
        }
  });
  return sums;
}

// A computed increment's errors against the reference: the relative L2 over
// every component, ||v - ref|| / ||ref||, and the largest point's error
// relative to the largest increment, max |v_i - ref_i| / max |ref_i|.
struct SeedErrors {
  double relative_l2 = 0, relative_max = 0;
};

inline SeedErrors seed_errors(const std::vector<partc::Vec<2>>& v,
                              const std::vector<std::array<long double, 2>>& reference) {
  long double error = 0, norm = 0, largest_error = 0, largest = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    long double e2 = 0, r2 = 0;
    for (int d = 0; d < 2; ++d) {
      const long double e = v[i][d] - reference[i][d];
      e2 += e * e;
      r2 += reference[i][d] * reference[i][d];
    }
    error += e2;
    norm += r2;
    largest_error = std::max(largest_error, e2);
    largest = std::max(largest, r2);
  }
  return {static_cast<double>(std::sqrt(error / norm)),
          static_cast<double>(std::sqrt(largest_error / largest))};
}

}  // namespace bench
