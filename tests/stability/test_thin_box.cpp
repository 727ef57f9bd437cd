// A periodic box 150 times longer than wide (tests/stability/thin_box.part):
// every search must match brute force over minimum images in both axes, each
// step, with 3 cells across the short axis (rc = 0.0033, image shifts) or 2
// (rc = 0.0034 and 0.00499: per-pair minimum images there), and Verlet lists
// whose build radius rc + skin exceeds half the short side (their build
// search then reports several images of a j, and the list must keep one).
// Counts exactly; the weighted vector sums to 1e-17 absolute: a difference of
// x coordinates across the long axis's face (near 1.5 and near 0) rounds by
// up to half an ulp of 1.5, 1.1e-16, whichever image is formed first, and that
// moves a term (rc - |dx|) dx by up to 2 rc 1.1e-16 = 1.1e-18.
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "thin_box.hpp"

namespace {

using V = brute::Vec<2>;
constexpr double Lx = 1.5, Ly = 0.01;

V image(const V& a, const V& b) {
  V d{b[0] - a[0], b[1] - a[1]};
  d[0] -= Lx * std::round(d[0] / Lx);
  d[1] -= Ly * std::round(d[1] / Ly);
  return d;
}

struct Expected {
  std::vector<std::int64_t> n;
  std::vector<V> w;
};

Expected brute_force(const std::vector<V>& p, double rc) {
  Expected e{std::vector<std::int64_t>(p.size(), 0), std::vector<V>(p.size(), {0, 0})};
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      const V dx = image(p[i], p[j]);
      const double d = brute::norm(dx);
      if (!(d < rc)) continue;
      e.n[i] += d > 0;
      for (int k = 0; k < 2; ++k) e.w[i][k] += (rc - d) * dx[k];
    }
  return e;
}

double worst_difference(const std::vector<partc::Vec<2>>& got, const std::vector<V>& want) {
  double worst = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    for (int k = 0; k < 2; ++k) worst = std::max(worst, std::abs(got[i][k] - want[i][k]));
  return worst;
}

void run(double rc, int steps, std::size_t short_cells) {
  ThinBox model;
  model.params().rc = rc;
  model.set_seed(17);
  model.init();
  std::int64_t total = 0;
  for (int step = 0; step < steps; ++step) {
    INFO("rc = " << rc << ", step " << step);
    // The sums see the positions before the step's move.
    const auto p = brute::positions_by_id<2>(model.P());
    const auto q = brute::positions_by_id<2>(model.Q());
    model.step();
    model.check_finite();
    const Expected e = brute_force(p, rc), f = brute_force(q, rc);
    CHECK(brute::values_by_id<ThinBox::P_n_cells>(model.P()) == e.n);
    CHECK(brute::values_by_id<ThinBox::P_n_tree>(model.P()) == e.n);
    CHECK(brute::values_by_id<ThinBox::P_n_auto>(model.P()) == e.n);
    CHECK(brute::values_by_id<ThinBox::Q_n_lists>(model.Q()) == f.n);
    const double dw_cells = worst_difference(brute::values_by_id<ThinBox::P_w_cells>(model.P()), e.w);
    const double dw_lists = worst_difference(brute::values_by_id<ThinBox::Q_w_lists>(model.Q()), f.w);
    INFO("weighted sums: cell list off by " << dw_cells << ", Verlet lists by " << dw_lists);
    CHECK(dw_cells <= 1e-17);
    CHECK(dw_lists <= 1e-17);
    for (auto n : e.n) total += n;
  }
  CHECK(total > 3 * steps * model.params().N);  // a real neighbourhood: 3.4-8 per particle
  for (const auto& r : model.search_report()) {
    INFO(r.serves << ": " << r.structure << ", " << r.builds << " builds");
    if (r.serves.find("cell_list") != std::string::npos) {
      CHECK_THAT(r.structure, Catch::StartsWith("cell list, "));
      CHECK(std::atof(r.structure.c_str() + 11) == std::floor(Lx / rc) * short_cells);
    }
    if (r.serves.rfind("by_lists", 0) == 0) {
      CHECK(r.builds >= 2);  // moved past half the skin at some step...
      CHECK(r.builds < static_cast<std::size_t>(steps));  // ... but not at every one
    }
  }
}

}  // namespace

TEST_CASE("a 1.5 x 0.01 periodic box with rc near L_y / 3: 3 or 2 cells across, and every "
          "search as brute force",
          "[stability][periodic][thin]") {
  run(0.0033, 5, 3);
  run(0.0034, 5, 2);
}

TEST_CASE("a 1.5 x 0.01 periodic box with rc just below L_y / 2 and Verlet lists whose build "
          "radius exceeds it: each j once, as brute force",
          "[stability][periodic][thin][verlet]") {
  run(0.00499, 5, 2);
}
