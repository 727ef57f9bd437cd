// Periodic, reflecting and open faces (tests/e2e/faces.part): free particles
// against their straight-line paths worked out here: along y a triangle wave
// between the faces (the velocity turning at each), along z gone at the first
// step that ends outside [0, 1).
#include <catch2/catch.hpp>

#include <cmath>
#include <map>

#include "faces.hpp"

namespace {

struct Expected {
  double x, y, vy;
};

// Where a particle starting at y0 with velocity vy is after time t between
// faces at 0 and L, and its velocity then.
Expected unfold(double x0, double y0, double vx, double vy, double t, double L) {
  const double free = y0 + vy * t;
  double y = std::fmod(free, 2 * L);
  if (y < 0) y += 2 * L;
  const bool turned = y > L;
  if (turned) y = 2 * L - y;
  double x = x0 + vx * t;
  x -= std::floor(x);
  return {x, y, turned ? -vy : vy};
}

}  // namespace

TEST_CASE("particles wrap along x, reflect along y and leave along z", "[e2e][faces]") {
  Faces model;
  model.set_seed(11);
  model.init();
  const auto& P = model.P();
  std::map<std::int64_t, std::array<double, 6>> start;  // id -> p, v
  for (std::size_t i = 0; i < P.size(); ++i) {
    const auto& p = P.positions()[i];
    const auto& v = P.get<Faces::P_v>()[i];
    start[P.ids()[i]] = {p[0], p[1], p[2], v[0], v[1], v[2]};
  }
  const int steps = 200;
  const double dt = model.params().dt;
  std::map<std::int64_t, bool> leaves;  // stepped exactly as the model steps z
  for (const auto& [id, s] : start) {
    double z = s[2];
    bool gone = false;
    for (int n = 0; n < steps && !gone; ++n) {
      z += dt * s[5];
      gone = z < 0 || z >= 1;
    }
    leaves[id] = gone;
  }
  for (int n = 0; n < steps; ++n) model.step();

  std::int64_t expected_left = 0;
  for (const auto& [id, gone] : leaves) expected_left += gone;
  REQUIRE(expected_left > 50);  // the test exercises the open faces
  CHECK(static_cast<std::int64_t>(P.size()) + expected_left == model.params().N);
  double worst = 0;
  int turned = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const std::int64_t id = P.ids()[i];
    REQUIRE_FALSE(leaves.at(id));
    const auto& s = start.at(id);
    const Expected e = unfold(s[0], s[1], s[3], s[4], steps * dt, 2.0);
    const auto& p = P.positions()[i];
    const auto& v = P.get<Faces::P_v>()[i];
    double dx = std::abs(p[0] - e.x);
    dx = std::min(dx, 1 - dx);
    worst = std::max({worst, dx, std::abs(p[1] - e.y)});
    CHECK(v[1] == e.vy);
    CHECK(v[0] == s[3]);
    CHECK(P.get<Faces::P_floor_gap>()[i] == p[1]);
    CHECK(p[1] >= 0);
    CHECK(p[1] <= 2);
    turned += v[1] != s[4];
  }
  CHECK(worst < 1e-11);
  CHECK(turned > 20);
}
