// Lennard-Jones at tiny separations (tests/stability/lj_close.part). At
// r = 1e-3 sigma the force 24 (2 r^-13 - r^-7) = 4.8e40 is finite and must
// match the formula evaluated in long double to relative 1e-12 (pow by
// multiplications costs a few ulps). At r = 1e-25 sigma, r^-14 = 1e350
// overflows: the force is an infinity, not a NaN and not a clamp, and
// check_finite (what the driver calls) stops the run with NumericalError.
#include <catch2/catch.hpp>

#include <cmath>

#include "lj_close.hpp"

TEST_CASE("LJ at r = 1e-3 sigma: a finite, huge force matching long double to 1e-12",
          "[stability][lj]") {
  LjClose model;
  model.params().r = 1e-3;
  model.init();
  model.step();
  CHECK_NOTHROW(model.check_finite());
  const auto& A = model.A();
  REQUIRE(A.size() == 2);
  const std::size_t a = A.ids()[0] == 0 ? 0 : 1, b = 1 - a;  // a at -r/2, b at +r/2
  const long double r = static_cast<long double>(A.positions()[b][0]) - A.positions()[a][0];
  REQUIRE(static_cast<double>(r) == 1e-3);
  const long double r2 = r * r;
  const long double force = -24 * (2 * std::pow(r2, -7.0L) - std::pow(r2, -4.0L)) * r;  // on a, along x
  const long double energy = 0.5L * 4 * (std::pow(r2, -6.0L) - std::pow(r2, -3.0L));
  const auto& f = A.get<LjClose::A_f>();
  const auto& u = A.get<LjClose::A_u>();
  INFO("force " << f[a][0] << " against " << static_cast<double>(force));
  CHECK(std::abs(force) > 4e40L);
  CHECK(std::abs((f[a][0] - force) / force) <= 1e-12L);
  CHECK(std::abs((f[b][0] + force) / force) <= 1e-12L);
  CHECK(f[a][1] == 0.0);
  CHECK(f[a][2] == 0.0);
  CHECK(std::abs((u[a] - energy) / energy) <= 1e-12L);
  CHECK(std::abs((u[b] - energy) / energy) <= 1e-12L);
}

TEST_CASE("LJ at r = 1e-25 sigma overflows to an infinite force and the run stops with "
          "NumericalError",
          "[stability][lj]") {
  LjClose model;
  model.params().r = 1e-25;
  model.init();
  model.step();
  const auto& A = model.A();
  const std::size_t a = A.ids()[0] == 0 ? 0 : 1;
  const double fx = A.get<LjClose::A_f>()[a][0];
  INFO("force on the left atom " << fx);
  CHECK(std::isinf(fx));
  CHECK(fx < 0);  // pushed left, away from its partner
  CHECK_THROWS_AS(model.check_finite(), partc::NumericalError);
  CHECK_THROWS_WITH(model.check_finite(), Catch::Contains("variable 'f' of particle id 0 is -inf"));
}
