// Every search structure a schedule can choose gives the same sums
// (tests/e2e/search_choices.part), checked against a brute-force loop over
// all pairs written here, while the particles move and Verlet lists are
// reused and rebuilt; so do half Verlet lists and, on a small set, the pair
// walks of each search (each pair once), for an odd force, an even count and
// an even weighted sum.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "reference.hpp"
#include "search_choices.hpp"

namespace {

using reference::Vec2;
using Model = SearchChoices;

// The sums of the model, from positions (and m) by id, periodic in x only.
struct Sums {
  std::vector<Vec2> force;
  std::vector<std::int64_t> close;
  std::vector<double> weight, overlap;  // overlap: the sum of 1 - s / r, then over close
};

Sums reference_sums(const std::vector<Vec2>& p, const std::vector<double>& m, double r) {
  Sums sums{std::vector<Vec2>(p.size(), Vec2{0, 0}), std::vector<std::int64_t>(p.size(), 0),
            std::vector<double>(p.size(), 0.0), std::vector<double>(p.size(), 0.0)};
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      Vec2 d{p[j][0] - p[i][0], p[j][1] - p[i][1]};
      d[0] -= std::round(d[0]);  // periodic in x, box length 1
      const double s = reference::norm(d);
      if (s >= r) continue;
      ++sums.close[i];
      sums.weight[i] += m[i] * m[j] * (1 - s / r);
      sums.overlap[i] += 1 - s / r;
      if (s > 0)
        for (int k = 0; k < 2; ++k) sums.force[i][k] += -(1 - s / r) * d[k] / s;
    }
  for (std::size_t i = 0; i < p.size(); ++i) sums.overlap[i] /= static_cast<double>(sums.close[i]);
  return sums;
}

double relative_error(const std::vector<double>& got, const std::vector<double>& want) {
  double w = 0;
  for (std::size_t k = 0; k < got.size(); ++k) w = std::max(w, std::abs(got[k] - want[k]) / want[k]);
  return w;
}

}  // namespace

TEST_CASE("auto, brute force, cell list, k-d tree and Verlet lists agree with brute force",
          "[e2e][search]") {
  // Statements that may take each pair once walk the pairs of the cell list
  // (auto, cells) at both sizes, in parallel slabs; those of brute force and
  // the k-d tree only at 150 particles (few enough for one thread), with a
  // larger radius so that each particle still has a few neighbours.
  const auto [n, r] = GENERATE(std::make_pair(1500, 0.04), std::make_pair(150, 0.12));
  Model model;
  model.params().N = n;
  model.params().r = r;
  model.set_seed(9);
  model.init();
  for (int step = 0; step < 12; ++step) {
    const auto before = reference::positions_by_id(model.P());
    const auto m = reference::values_by_id<Model::P_m>(model.P());
    model.step();  // forces at `before`, then the particles move
    const Sums sums = reference_sums(before, m, r);
    const std::vector<Vec2>& want = sums.force;
    double scale = 0;
    for (const Vec2& f : want) scale = std::max(scale, reference::norm(f));
    REQUIRE(scale > 0);
    INFO("N = " << n << ", step " << step);
    CHECK(reference::worst(reference::values_by_id<Model::P_f_auto>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_f_brute>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_f_cells>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_f_tree>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_f_lists>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_f_pairs>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_g_auto>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_g_brute>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_g_cells>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::worst(reference::values_by_id<Model::P_g_tree>(model.P()), want) <= 1e-12 * scale);
    CHECK(reference::values_by_id<Model::P_close>(model.P()) == sums.close);
    CHECK(reference::values_by_id<Model::P_close_auto>(model.P()) == sums.close);
    CHECK(relative_error(reference::values_by_id<Model::P_weight>(model.P()), sums.weight) <= 1e-12);
    CHECK(relative_error(reference::values_by_id<Model::P_weight_auto>(model.P()), sums.weight) <=
          1e-12);
    CHECK(relative_error(reference::values_by_id<Model::P_overlap>(model.P()), sums.overlap) <=
          1e-12);
  }
}
