// DEM (examples/dem_collision.part): the restitution coefficient of a
// head-on collision of two unequal spheres against the closed form of the
// linear spring-dashpot, e = exp(-pi zeta / sqrt(1 - zeta^2)), within 0.5%.
#include <catch2/catch.hpp>

#include <cmath>

#include "dem_collision.hpp"
#include "reference.hpp"

TEST_CASE("a head-on collision's restitution coefficient is the spring-dashpot's",
          "[e2e][dem]") {
  for (const double zeta : {0.01, 0.1, 0.3, 0.6}) {
    DemCollision model;
    model.params().zeta = zeta;
    model.params().dt = 2e-6;
    model.init();
    const double approach = 2 * model.params().speed;
    // Step until the spheres have met and parted again.
    bool met = false;
    double separation = 0;
    for (long k = 0; k < 200000; ++k) {
      model.step();
      const auto& x = model.S().positions();
      separation = std::abs(x[1][0] - x[0][0]);
      met = met || separation < 0.2;
      if (met && separation > 0.2) break;
    }
    REQUIRE(met);
    REQUIRE(separation > 0.2);
    const auto v = reference::values_by_id<DemCollision::S_v>(model.S());
    const double e = (v[1][0] - v[0][0]) / approach;
    const double expected = std::exp(-M_PI * zeta / std::sqrt(1 - zeta * zeta));
    INFO("zeta " << zeta << ": e = " << e << ", closed form " << expected);
    CHECK(e == Approx(expected).epsilon(0.005));
    // Momentum is conserved through the contact (masses 1 and 2).
    CHECK(v[0][0] * 1 + v[1][0] * 2 == Approx(1 * 1.0 - 2 * 1.0).margin(1e-9));
  }
}

TEST_CASE("a settled pile: the floor carries its weight", "[e2e][dem]") {
  DemCollision model;
  model.params().scene = 1;
  model.params().N = 48;
  model.params().g = 9.81;
  model.params().gamma = 2;
  model.params().zeta = 0.3;
  model.params().dt = 2e-5;
  model.set_seed(8);
  model.init();
  for (long k = 0; k < 125000; ++k) model.step();  // t = 2.5: dropped, bounced, settled
  const double weight = 48 * 9.81;
  CHECK(model.observables().weight == Approx(weight).epsilon(1e-12));
  INFO("floor force " << model.observables().floor_force << ", kinetic energy "
                      << model.observables().e_kin);
  CHECK(model.observables().e_kin < 1e-3 * weight * 0.1);  // at rest, against m g r
  CHECK(model.observables().floor_force == Approx(weight).epsilon(0.01));
}
