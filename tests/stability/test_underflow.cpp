// Gaussian kernels with tiny widths (tests/stability/underflow.part):
// exp(-|dx|^2 / s) underflows to 0 for most pairs and to denormals for some.
// The sums must equal brute force computed here with the same expression,
// denormals kept (not flushed to zero), and nothing NaN.
#include <catch2/catch.hpp>

#include <cfloat>
#include <cmath>

#include "brute.hpp"
#include "underflow.hpp"

TEST_CASE("sums of exp(-|dx|^2 / s) with tiny s underflowing to 0 or to denormals match "
          "brute force, with no NaN",
          "[stability][underflow]") {
  Underflow model;
  model.set_seed(4);
  model.init();
  model.step();
  CHECK_NOTHROW(model.check_finite());
  const auto& params = model.params();

  SECTION("a random cloud, s = 1e-4") {
    const auto p = brute::positions_by_id<2>(model.Cloud());
    std::vector<double> g(p.size(), 0), g_far(p.size(), 0);
    int denormal_terms = 0, zero_terms = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = 0; j < p.size(); ++j) {
        const brute::Vec<2> dx = brute::minimum_image<2>({p[j][0] - p[i][0], p[j][1] - p[i][1]}, 1.0);
        const double d2 = dx[0] * dx[0] + dx[1] * dx[1];
        if (!(std::sqrt(d2) < params.rc)) continue;
        const double term = std::exp(-d2 / params.s);
        g[i] += term;
        if (d2 > 0) g_far[i] += term;
        denormal_terms += term > 0 && term < DBL_MIN;
        zero_terms += term == 0;
      }
    REQUIRE(denormal_terms > 10);
    REQUIRE(zero_terms > 1000);
    const auto mg = brute::values_by_id<Underflow::Cloud_g>(model.Cloud());
    const auto mf = brute::values_by_id<Underflow::Cloud_g_far>(model.Cloud());
    double worst = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      REQUIRE(std::isfinite(mg[i]));
      REQUIRE(std::isfinite(mf[i]));
      worst = std::max(worst, std::abs(mg[i] - g[i]) / g[i]);  // g >= 1: the particle itself
      CHECK(std::abs(mf[i] - g_far[i]) <= 1e-13 * g_far[i] + 1e-320);
    }
    CHECK(worst <= 1e-13);
  }
  SECTION("a ring whose every sum is two denormals exp(-720), and exactly 1 at s = 1e-300") {
    const auto p = brute::positions_by_id<2>(model.Ring());
    const double d = 1.0 / params.M;
    const double term = std::exp(-(d * d) / params.s2);
    REQUIRE(term > 0);
    REQUIRE(term < DBL_MIN);  // denormal
    const auto g = brute::values_by_id<Underflow::Ring_g>(model.Ring());
    const auto tiny = brute::values_by_id<Underflow::Ring_tiny>(model.Ring());
    for (std::size_t i = 0; i < p.size(); ++i) {
      INFO("ring particle " << i << ": " << g[i] << " against " << 2 * term);
      CHECK(g[i] > 0);  // not flushed to zero
      // A denormal near 2e-313 carries 35 bits: rounding of its argument moves it by ~1e-11.
      CHECK(std::abs(g[i] - 2 * term) <= 1e-9 * 2 * term);
      CHECK(tiny[i] == 1.0);
    }
  }
}
