// Sums partc computes once per statement (tests/e2e/uniform_sums.part),
// checked against what they must give: zero total momentum and the set
// kinetic energy after init (as in an MD code's velocity initialisation),
// and counts and shares computed here by brute force from the masses.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>

#include "reference.hpp"
#include "uniform_sums.hpp"

TEST_CASE("sums that read nothing of i: once per statement, right for every particle",
          "[e2e][uniform]") {
  UniformSums model;
  model.set_seed(11);
  model.init();
  const auto v = reference::values_by_id<UniformSums::P_v>(model.P());
  const auto m = reference::values_by_id<UniformSums::P_m>(model.P());
  const std::size_t n = m.size();
  REQUIRE(n == 400);

  double momentum[2] = {0, 0}, kinetic = 0, speed = 0;
  for (std::size_t k = 0; k < n; ++k) {
    for (int d = 0; d < 2; ++d) momentum[d] += m[k] * v[k][d];
    kinetic += 0.5 * m[k] * (v[k][0] * v[k][0] + v[k][1] * v[k][1]);
    speed = std::max(speed, norm(v[k]));
  }
  REQUIRE(speed > 0.5);  // the velocities are not all zero
  CHECK(std::abs(momentum[0]) < 1e-12 * n * speed);
  CHECK(std::abs(momentum[1]) < 1e-12 * n * speed);
  CHECK(std::abs(kinetic / n - model.params().E) < 1e-12 * model.params().E);

  model.step();
  const auto heavy = reference::values_by_id<UniformSums::P_heavy>(model.P());
  const auto share = reference::values_by_id<UniformSums::P_share>(model.P());
  const auto lighter = reference::values_by_id<UniformSums::P_lighter>(model.P());
  double total = 0;
  std::int64_t heavy_count = 0;
  for (double mass : m) total += mass, heavy_count += mass > 1.5;
  REQUIRE(heavy_count > 0);
  REQUIRE(heavy_count < static_cast<std::int64_t>(n));
  double share_sum = 0;
  for (std::size_t k = 0; k < n; ++k) {
    INFO("particle id " << k);
    CHECK(heavy[k] == heavy_count);
    CHECK(std::abs(share[k] - m[k] / total) <= 1e-15);
    std::int64_t below = 0;
    for (double mass : m) below += mass < m[k];
    CHECK(lighter[k] == below);
    share_sum += share[k];
  }
  CHECK(std::abs(share_sum - 1) < 1e-12);
}
