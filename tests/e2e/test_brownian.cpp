// Brownian dynamics (examples/brownian_obstacles.part) against physics:
// free diffusion's mean squared displacement is 6 D t, within 4 standard
// errors estimated from the tracers themselves; among a simple-cubic array
// of reflecting spheres, the long-time D_eff / D is Maxwell's 2 / (2 + phi)
// within 3% (the exact value for such arrays differs from Maxwell's by
// less than 0.5% up to phi = 0.3, after Rayleigh); and no tracer is ever
// inside an obstacle at the end of a step.
#include <catch2/catch.hpp>

#include <cmath>

#include "brownian_obstacles.hpp"
#include "reference.hpp"

namespace {

// Runs `steps` steps, checking after each that no tracer is inside a sphere.
void run(BrownianObstacles& model, long steps) {
  for (long k = 0; k < steps; ++k) {
    model.step();
    if (model.observables().inside != 0) FAIL("a tracer is inside an obstacle at step " << k + 1);
  }
}

}  // namespace

TEST_CASE("free Brownian motion: msd = 6 D t within 4 standard errors", "[e2e][brownian]") {
  BrownianObstacles model;
  model.params().phi = 0;
  model.params().N = 4000;
  model.params().dt = 1e-3;
  model.set_seed(21);
  model.init();
  REQUIRE(model.O().size() == 0);
  run(model, 300);
  const auto d = reference::values_by_id<BrownianObstacles::T_d>(model.T());
  double mean = 0, square = 0;
  for (const auto& x : d) {
    const double r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    mean += r2;
    square += r2 * r2;
  }
  const double n = static_cast<double>(d.size());
  mean /= n;
  const double standard_error = std::sqrt((square / n - mean * mean) / n);
  const double expected = 6 * model.params().D * model.time();
  INFO("msd " << mean << " +- " << standard_error << ", 6 D t = " << expected);
  CHECK(model.observables().msd == Approx(mean).epsilon(1e-12));
  CHECK(std::abs(mean - expected) < 4 * standard_error);
}

TEST_CASE("Brownian motion among reflecting spheres: Maxwell's D_eff / D", "[e2e][brownian]") {
  for (const double phi : {0.1, 0.2, 0.3}) {
    BrownianObstacles model;
    model.params().phi = phi;
    model.params().N = 20000;
    model.params().dt = 1e-3;
    model.set_seed(5);
    model.init();
    REQUIRE(model.O().size() == 1);
    // msd / 6t at t = 2, long after the tracers met the obstacles (a^2 / D
    // is at most 0.17 here): the short-time excess then weighs < 1%.
    run(model, 2000);
    const double d_eff = model.observables().msd / (6 * model.time());
    const double maxwell = 2 / (2 + phi);
    INFO("phi " << phi << ": D_eff / D = " << d_eff / model.params().D << ", Maxwell " << maxwell);
    CHECK(d_eff / model.params().D == Approx(maxwell).epsilon(0.03));
  }
}
