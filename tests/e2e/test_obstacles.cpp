// Sums over a second particle set and over both sets at once
// (tests/e2e/obstacles.part): particles B pushed by obstacles O, against a
// brute-force reference over all (B, O) and (B, B) pairs written here.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "obstacles.hpp"
#include "reference.hpp"

namespace {

using reference::Vec2;

struct Reference {
  std::vector<Vec2> b, o;  // positions of B and O, by id
  std::vector<double> strength;
  std::vector<Vec2> push;
  std::vector<double> crowd, gap, lonely;

  void step(double r) {
    push.assign(b.size(), Vec2{0, 0});
    crowd.assign(b.size(), 0);
    gap.assign(b.size(), std::numeric_limits<double>::infinity());
    lonely.assign(b.size(), -1);  // max over no obstacle: the value given for none
    std::vector<bool> any(b.size(), false);
    // Over both sets: B's strength is 2 (its declared initial value).
    const auto both = [&](std::size_t i, const Vec2& q, double s) {
      const double d = reference::norm(reference::minimum_image({q[0] - b[i][0], q[1] - b[i][1]}));
      if (d < 2 * r && d > 0) crowd[i] += s * (2 * r - d);
      if (d > 0 && d < 4 * r) gap[i] = std::min(gap[i], d);
    };
    for (std::size_t i = 0; i < b.size(); ++i) {
      for (std::size_t k = 0; k < o.size(); ++k) {
        const Vec2 dx = reference::minimum_image({o[k][0] - b[i][0], o[k][1] - b[i][1]});
        const double d = reference::norm(dx);
        if (d < r && d > 0)
          for (int c = 0; c < 2; ++c) push[i][c] += -strength[k] * dx[c] / d;
        if (d < 0.2 * r) {
          lonely[i] = any[i] ? std::max(lonely[i], strength[k]) : strength[k];
          any[i] = true;
        }
        both(i, o[k], strength[k]);
      }
      for (std::size_t k = 0; k < b.size(); ++k) both(i, b[k], 2.0);
    }
    for (std::size_t i = 0; i < b.size(); ++i)
      for (int c = 0; c < 2; ++c) {
        b[i][c] += 0.01 * push[i][c];
        b[i][c] -= std::floor(b[i][c]);
      }
  }
};

}  // namespace

TEST_CASE("sums over another particle set match brute force over all pairs", "[e2e][sets]") {
  Obstacles model;
  model.set_seed(3);
  model.init();
  Reference ref{reference::positions_by_id(model.B()), reference::positions_by_id(model.O()),
                reference::values_by_id<Obstacles::O_strength>(model.O()), {}, {}, {}, {}};
  for (int step = 0; step < 4; ++step) {
    model.step();
    ref.step(model.params().r);
  }
  const auto b = reference::positions_by_id(model.B());
  const auto push = reference::values_by_id<Obstacles::B_push>(model.B());
  const auto crowd = reference::values_by_id<Obstacles::B_crowd>(model.B());
  const auto gap = reference::values_by_id<Obstacles::B_gap>(model.B());
  const auto lonely = reference::values_by_id<Obstacles::B_lonely>(model.B());
  double worst_b = 0, worst_push = 0, scale = 0, worst_crowd = 0, worst_gap = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    worst_b = std::max(worst_b, reference::norm(reference::minimum_image(
                                    {b[i][0] - ref.b[i][0], b[i][1] - ref.b[i][1]})));
    worst_push = std::max(worst_push, reference::norm({push[i][0] - ref.push[i][0],
                                                       push[i][1] - ref.push[i][1]}));
    scale = std::max(scale, reference::norm(ref.push[i]));
    worst_crowd = std::max(worst_crowd, std::abs(crowd[i] - ref.crowd[i]));
    worst_gap = std::max(worst_gap, std::abs(gap[i] - ref.gap[i]));
  }
  REQUIRE(scale > 0);
  CHECK(worst_b <= 1e-12);
  CHECK(worst_push <= 1e-12 * scale);
  CHECK(worst_crowd <= 1e-12);
  CHECK(worst_gap <= 1e-15);
  CHECK(lonely == ref.lonely);
  const auto none = std::count(ref.lonely.begin(), ref.lonely.end(), -1.0);
  CHECK(none > 0);  // both cases occur
  CHECK(none < static_cast<long>(ref.lonely.size()));
  REQUIRE(std::isfinite(*std::max_element(ref.gap.begin(), ref.gap.end())));
  // O never moves: the statements update B only.
  CHECK(reference::positions_by_id(model.O()) == ref.o);
}
