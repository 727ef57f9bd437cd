// A huge periodic box with few particles (tests/stability/sparse_huge.part):
// 60 particles in [-1e6, 1e6)^3 with rc = 1. The cell list must cap its cells
// at 2 N + 64 (not 8e18) and a step must stay quick. Reference, analytic: each
// particle's neighbours are its two group mates, at 0.5, 0.75 or sqrt(0.8125)
// by construction, so the sums are e^-0.5 + e^-0.75 and so on. Placing a
// particle at 1e6 rounds it by half an ulp there (5.8e-11), which moves each
// distance by at most 2e-10: the sums must match to 5e-10, and match brute
// force over the model's own positions to 1e-15 relative. The corner group
// wraps across all three faces: its members must come out at lo + 0.25.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>

#include "brute.hpp"
#include "sparse_huge.hpp"

TEST_CASE("60 particles in a periodic box of side 2e6 with rc = 1: cells capped, quick, and "
          "sums equal to the analytic ones",
          "[stability][sparse]") {
  SparseHuge model;
  const auto start = std::chrono::steady_clock::now();
  model.init();
  model.step();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  model.check_finite();
  CHECK(seconds < 1.0);
  const auto p = brute::positions_by_id<3>(model.P());
  REQUIRE(p.size() == 60);
  // Group 0: (hi - 0.25) + 0.5 along x wraps to lo + 0.25; member 2's y likewise.
  CHECK(p[1][0] == -1e6 + 0.25);
  CHECK(p[2][1] == -1e6 + 0.5);
  CHECK(p[0][2] == 1e6 - 0.25);

  const double d01 = 0.5, d02 = 0.75, d12 = std::sqrt(0.8125);
  const double analytic[3] = {std::exp(-d01) + std::exp(-d02), std::exp(-d01) + std::exp(-d12),
                              std::exp(-d02) + std::exp(-d12)};
  std::vector<double> s(60, 0);
  std::vector<std::int64_t> n(60, 0);
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j) {
      const double d = brute::norm(brute::minimum_image<3>(
          {p[j][0] - p[i][0], p[j][1] - p[i][1], p[j][2] - p[i][2]}, 2e6));
      if (d < 1 && d > 0) {
        ++n[i];
        s[i] += std::exp(-d);
      }
    }
  const std::vector<std::int64_t> two(60, 2);
  CHECK(n == two);
  CHECK(brute::values_by_id<SparseHuge::P_n_cells>(model.P()) == two);
  CHECK(brute::values_by_id<SparseHuge::P_n_tree>(model.P()) == two);
  CHECK(brute::values_by_id<SparseHuge::P_n_auto>(model.P()) == two);
  for (const auto& values : {brute::values_by_id<SparseHuge::P_s_cells>(model.P()),
                             brute::values_by_id<SparseHuge::P_s_tree>(model.P()),
                             brute::values_by_id<SparseHuge::P_s_auto>(model.P())})
    for (int i = 0; i < 60; ++i) {
      INFO("particle " << i << ": " << values[i] << " against " << analytic[i % 3]);
      CHECK(std::abs(values[i] - analytic[i % 3]) <= 5e-10);
      CHECK(std::abs(values[i] - s[i]) <= 1e-15 * s[i]);
    }
  for (const auto& r : model.search_report()) {
    INFO(r.serves << ": " << r.structure);
    if (r.structure.rfind("cell list, ", 0) == 0) CHECK(std::atof(r.structure.c_str() + 11) <= 2 * 60 + 64);
  }
}
