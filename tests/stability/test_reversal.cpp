// Time reversal of velocity Verlet (tests/stability/reversal.part): K steps
// forward, every velocity negated, K steps back must return every disc to its
// starting position and every velocity to minus its start (the scheme is
// time-reversible in exact arithmetic; the reference is the initial state).
// Rounding breaks the symmetry by ~1e-16 per step, and the collisions amplify
// it exponentially (measured for set A: 4e-14, 2e-11, 1e-6 after K = 200,
// 400, 800), so K = 200 and the bound 1e-11 is 40-70x what was measured
// (2.6e-13 with Verlet lists, 1.4e-13 with the cell list). A pair missed by a
// stale neighbour list, or a force from the wrong image, would cost a whole
// collision's change of course, ~dt k overlap ~ 1e-2.
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "reversal.hpp"

namespace {

template <class Set, class VTag>
double reversal_error(Reversal& model, Set& (Reversal::*set)(), int K, std::size_t& collisions) {
  const auto start = brute::positions_by_id<2>((model.*set)());
  const auto start_v = brute::values_by_id<VTag>((model.*set)());
  collisions = 0;
  for (int k = 0; k < K; ++k) {
    model.step();
    std::size_t now = 0;
    const auto q = brute::positions_by_id<2>((model.*set)());
    for (std::size_t i = 0; i < q.size(); ++i)
      for (std::size_t j = i + 1; j < q.size(); ++j)
        now += brute::norm(brute::minimum_image<2>({q[j][0] - q[i][0], q[j][1] - q[i][1]}, 10.0)) < 1;
    collisions += now;
  }
  for (auto& v : (model.*set)().template get<VTag>()) v = -v;
  for (int k = 0; k < K; ++k) model.step();
  model.check_finite();
  const auto back = brute::positions_by_id<2>((model.*set)());
  const auto back_v = brute::values_by_id<VTag>((model.*set)());
  double worst = 0;
  for (std::size_t i = 0; i < start.size(); ++i) {
    worst = std::max(worst, brute::norm(brute::minimum_image<2>(
                                {back[i][0] - start[i][0], back[i][1] - start[i][1]}, 10.0)));
    for (int d = 0; d < 2; ++d) worst = std::max(worst, std::abs(back_v[i][d] + start_v[i][d]));
  }
  return worst;
}

}  // namespace

TEST_CASE("velocity Verlet with Verlet lists, 200 steps forward and 200 back, returns every "
          "disc to its start",
          "[stability][reversal][verlet]") {
  Reversal model;
  model.set_seed(12);
  model.init();
  std::size_t collisions = 0;
  const double error = reversal_error<Reversal::ASet, Reversal::A_v>(model, &Reversal::A, 200, collisions);
  INFO("largest position or velocity error " << error << ", " << collisions << " pair-steps in contact");
  CHECK(collisions > 500);  // discs did collide: the forces mattered
  CHECK(error <= 1e-11);
  bool rebuilt = false;
  for (const auto& r : model.search_report())
    if (r.serves.rfind("force_lists", 0) == 0) rebuilt = r.builds > 2 && r.builds < 1000;
  CHECK(rebuilt);  // the lists were reused, and rebuilt as the discs moved
}

TEST_CASE("velocity Verlet with a cell list, 200 steps forward and 200 back, returns every "
          "disc to its start",
          "[stability][reversal]") {
  Reversal model;
  model.set_seed(12);
  model.init();
  std::size_t collisions = 0;
  const double error = reversal_error<Reversal::BSet, Reversal::B_v>(model, &Reversal::B, 200, collisions);
  INFO("largest position or velocity error " << error << ", " << collisions << " pair-steps in contact");
  CHECK(collisions > 500);
  CHECK(error <= 1e-11);
}
