// Velocity Verlet is second order: over one period of a Lennard-Jones dimer
// (tests/e2e/lj_dimer.part) the largest energy error falls 4x each time dt
// halves. The period comes from the energy integral, computed here by
// quadrature, not from the simulation.
#include <catch2/catch.hpp>

#include <cmath>

#include "lj_dimer.hpp"

namespace {

double lj(double r) { return 4 * (std::pow(r, -12) - std::pow(r, -6)); }

// T = 2 * integral from r0 to r1 of dr / rdot, with rdot = sqrt(2 (E - U) / mu)
// and mu = 1/2; r = r0 + (r1 - r0) (1 - cos phi) / 2 takes the square-root
// singularities at both turning points away.
double period(double r0) {
  const double energy = lj(r0);
  double lo = std::pow(2.0, 1.0 / 6.0), hi = 3.0;  // the outer turning point r1: U(r1) = E
  for (int k = 0; k < 200; ++k) (lj(0.5 * (lo + hi)) < energy ? lo : hi) = 0.5 * (lo + hi);
  const double r1 = 0.5 * (lo + hi);
  const int n = 200000;
  double integral = 0;
  for (int k = 0; k < n; ++k) {
    const double phi = M_PI * (k + 0.5) / n;  // midpoints: the ends are never evaluated
    const double r = r0 + 0.5 * (r1 - r0) * (1 - std::cos(phi));
    const double dr = 0.5 * (r1 - r0) * std::sin(phi) * M_PI / n;
    integral += dr / std::sqrt(4 * (energy - lj(r)));
  }
  return 2 * integral;
}

// The largest |E - E0| over one period, stepped with dt.
double energy_error(double dt, double T) {
  LjDimer model;
  model.params().dt = dt;
  model.init();
  const auto steps = static_cast<long>(std::lround(T / dt));
  for (long k = 0; k < steps; ++k) model.step();
  CHECK(model.time() == Approx(T).epsilon(dt / T));
  return model.observables().e_err;
}

}  // namespace

TEST_CASE("velocity Verlet's energy error on an LJ dimer is second order", "[e2e][md]") {
  LjDimer model;
  const double T = period(model.params().r0);
  INFO("period " << T);
  REQUIRE(T > 0.5);
  REQUIRE(T < 0.8);  // about 2 pi / sqrt(U''(2^1/6) / mu) = 0.59, longer for the anharmonic swing
  const double coarse = energy_error(2e-3, T), medium = energy_error(1e-3, T),
               fine = energy_error(5e-4, T);
  INFO("max energy errors " << coarse << ", " << medium << ", " << fine);
  REQUIRE(fine > 0);
  CHECK(coarse / medium == Approx(4).epsilon(0.03));
  CHECK(medium / fine == Approx(4).epsilon(0.03));
  CHECK(coarse < 1e-2 * std::abs(lj(model.params().r0)));
}
