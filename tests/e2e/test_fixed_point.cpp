// A named stage whose iterate block relaxes x = cos(c x) per particle
// (tests/e2e/fixed_point.part), against the fixed points found here by
// bisection of x - cos(c x), which is increasing on [0, 1] for c <= 1.5.
#include <catch2/catch.hpp>

#include <cmath>

#include "fixed_point.hpp"
#include "reference.hpp"

TEST_CASE("a named stage iterates until its condition holds", "[e2e][stages]") {
  FixedPoint model;
  model.init();
  CHECK(FixedPoint::stage_names() == std::vector<std::string>{"settle"});
  model.run_stage("settle");
  CHECK(model.step_count() == 0);  // a named stage is not a step
  CHECK(model.observables().residual < 1e-12);
  CHECK(model.observables().passes > 10);
  CHECK(model.observables().passes < 500);
  const auto x = reference::values_by_id<FixedPoint::P_x>(model.P());
  const auto c = reference::values_by_id<FixedPoint::P_c>(model.P());
  for (std::size_t k = 0; k < x.size(); ++k) {
    double lo = 0, hi = 1;
    for (int b = 0; b < 200; ++b) {
      const double mid = 0.5 * (lo + hi);
      (mid - std::cos(c[k] * mid) < 0 ? lo : hi) = mid;
    }
    INFO("particle id " << k << ", c = " << c[k]);
    CHECK(x[k] == Approx(lo).margin(1e-11));
  }
  CHECK(std::abs(x[49] - std::cos(c[49] * x[49])) < 1e-12);
  CHECK_THROWS_AS(model.run_stage("relax"), partc::UsageError);
}

TEST_CASE("an iterate block that reaches its limit stops with a message", "[e2e][stages]") {
  FixedPoint model;
  model.params().max_passes = 3;
  model.init();
  CHECK_THROWS_WITH(model.run_stage("settle"),
                    Catch::Contains("fixed_point.part:28: iterate did not converge in 3 passes "
                                    "(until residual < tol); residual = "));
  CHECK(model.observables().passes == 3);
}
