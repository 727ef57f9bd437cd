// One build per search per position change (tests/e2e/two_cutoffs.part): the
// density at rc and the force at rf = 5 rc / 3 over A have a search each (the
// run's radii decide: (rf / rc)^2 > 1.2), each built once per step, and the
// count at rc / 2 scheduled apart has its own, also built once per step; over L, the search beside Verlet lists keeps L's order, so the lists
// are not rebuilt every step. Every sum against a brute-force loop over all
// pairs, from the positions before the step.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "reference.hpp"
#include "two_cutoffs.hpp"

namespace {

using reference::Vec2;
using Model = TwoCutoffs;

// sum(j, |dx| < r, 1 - |dx| / r), the force -(1 - s / r) dx / s over 0 < s < r,
// and count(j, |dx| < r), in the periodic unit square.
struct Sums {
  std::vector<double> weight;
  std::vector<Vec2> force;
  std::vector<std::int64_t> count;
};

Sums brute_force(const std::vector<Vec2>& p, double r) {
  Sums sums{std::vector<double>(p.size(), 0.0), std::vector<Vec2>(p.size(), Vec2{0, 0}),
            std::vector<std::int64_t>(p.size(), 0)};
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      const Vec2 d = reference::minimum_image({p[j][0] - p[i][0], p[j][1] - p[i][1]});
      const double s = reference::norm(d);
      if (s >= r) continue;
      sums.weight[i] += 1 - s / r;
      ++sums.count[i];
      if (s > 0)
        for (int k = 0; k < 2; ++k) sums.force[i][k] += -(1 - s / r) * d[k] / s;
    }
  return sums;
}

double largest_difference(const std::vector<double>& got, const std::vector<double>& want) {
  double w = 0;
  for (std::size_t i = 0; i < got.size(); ++i) w = std::max(w, std::abs(got[i] - want[i]));
  return w;
}

// Builds so far of the search (or lists) whose report starts with `serves`.
std::size_t builds(const Model& model, const std::string& serves) {
  for (const partc::SearchReport& s : model.search_report())
    if (s.serves.rfind(serves, 0) == 0) return s.builds;
  FAIL("no search serves " << serves);
  return 0;
}

}  // namespace

TEST_CASE("two cutoffs over one set: one build per step, results as brute force", "[e2e][search]") {
  Model model;
  const double rc = model.params().rc, rf = model.params().rf;
  model.set_seed(3);
  model.init();
  const int steps = 12;
  for (int step = 1; step <= steps; ++step) {
    const auto a = reference::positions_by_id(model.A());
    const auto l = reference::positions_by_id(model.L());
    model.step();
    INFO("step " << step);
    const Sums at_rc = brute_force(a, rc), at_rf = brute_force(a, rf),
               at_half = brute_force(a, 0.5 * rc);
    CHECK(largest_difference(reference::values_by_id<Model::A_rho>(model.A()), at_rc.weight) <=
          1e-12);
    CHECK(reference::worst(reference::values_by_id<Model::A_f>(model.A()), at_rf.force) <= 1e-12);
    CHECK(reference::values_by_id<Model::A_near>(model.A()) == at_half.count);
    CHECK(reference::worst(reference::values_by_id<Model::L_g>(model.L()),
                           brute_force(l, rc).force) <= 1e-12);
    CHECK(largest_difference(reference::values_by_id<Model::L_w>(model.L()),
                             brute_force(l, 1.5 * rc).weight) <= 1e-12);
    // Once per position change: the positions move once per step.
    CHECK(builds(model, "sums over A at line 36") == static_cast<std::size_t>(step));
    CHECK(builds(model, "sums over A at line 37") == static_cast<std::size_t>(step));
    CHECK(builds(model, "sums over A at line 38") == static_cast<std::size_t>(step));
    CHECK(builds(model, "sums over L") == static_cast<std::size_t>(step));
  }
  // speed 0.0002 a step: the fastest particle moves half the skin (0.005) in
  // about 40 steps, so the first build serves all 12 (a search that reordered
  // L would have forced a rebuild every step).
  CHECK(builds(model, "listed at") == 1);
}
