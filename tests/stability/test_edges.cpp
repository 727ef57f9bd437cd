// Particles exactly on the periodic faces and on cell edges, moved several
// box lengths in one step (tests/stability/edges.part): after wrapping, the
// positions are where x - L floor(x / L) puts them (a lattice point on hi
// lands exactly on lo), and every search's counts and sums equal brute force
// over minimum images, the lattice neighbours at exactly rc included by <=
// and excluded by <.
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "edges.hpp"

namespace {

using V = brute::Vec<2>;
constexpr double L = 2.0;

double wrapped(double x) { return x - L * std::floor(x / L); }

struct Expected {
  std::vector<std::int64_t> close, strict;
  std::vector<V> w;
};

Expected brute_force(const std::vector<V>& p, double rc) {
  Expected e{std::vector<std::int64_t>(p.size()), std::vector<std::int64_t>(p.size()), std::vector<V>(p.size())};
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      const V dx = brute::minimum_image<2>({p[j][0] - p[i][0], p[j][1] - p[i][1]}, L);
      const double d = brute::norm(dx);
      e.close[i] += d <= rc && d > 0;
      e.strict[i] += d < rc && d > 0;
      if (d < 2 * rc)
        for (int k = 0; k < 2; ++k) e.w[i][k] += (2 * rc - d) * dx[k];
    }
  return e;
}

}  // namespace

TEST_CASE("particles on periodic faces and cell edges, moved 3.25 box lengths a step, "
          "wrap exactly and match brute force with minimum images",
          "[stability][periodic]") {
  Edges model;
  model.set_seed(5);
  model.init();
  const int G = model.params().G;
  const double rc = model.params().rc;
  REQUIRE(G * rc == L + rc);  // the last lattice row and column lie on hi

  std::vector<V> expected = brute::positions_by_id<2>(model.P());
  // The lattice as written, with hi wrapped to lo exactly.
  for (int id = 0; id < G * G; ++id) {
    const V at{std::fmod((id % G) * rc, L), std::fmod((id / G) * rc, L)};
    INFO("lattice particle " << id);
    CHECK(expected[id] == at);
  }
  for (int step = 1; step <= 3; ++step) {
    for (V& q : expected) q = {wrapped(q[0] + 3.25 * L), wrapped(q[1] - 2.75 * L)};
    model.step();
    model.check_finite();
    const auto p = brute::positions_by_id<2>(model.P());
    REQUIRE(p.size() == expected.size());
    double worst = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      for (int k = 0; k < 2; ++k) {
        CHECK(p[i][k] >= 0.0);
        CHECK(p[i][k] < L);
      }
      if (static_cast<int>(i) < G * G) CHECK(p[i] == expected[i]);  // the lattice stays exact
      worst = std::max(worst, brute::norm(brute::minimum_image<2>(
                                  {p[i][0] - expected[i][0], p[i][1] - expected[i][1]}, L)));
    }
    CHECK(worst <= 4e-15);  // x + 6.5 rounds once, to half an ulp of 8

    const Expected e = brute_force(p, rc);
    CHECK(brute::values_by_id<Edges::P_n_cells>(model.P()) == e.close);
    CHECK(brute::values_by_id<Edges::P_n_tree>(model.P()) == e.close);
    CHECK(brute::values_by_id<Edges::P_n_brute>(model.P()) == e.close);
    CHECK(brute::values_by_id<Edges::P_n_auto>(model.P()) == e.close);
    CHECK(brute::values_by_id<Edges::P_strict_cells>(model.P()) == e.strict);
    // A lattice point away from the random ones has its 4 lattice neighbours at exactly rc.
    int lattice_four = 0;
    for (int id = 0; id < G * G; ++id) lattice_four += e.close[id] >= 4 && e.strict[id] < 4;
    CHECK(lattice_four > 0);
    const auto wc = brute::values_by_id<Edges::P_w_cells>(model.P());
    const auto wa = brute::values_by_id<Edges::P_w_auto>(model.P());
    double worst_w = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (int k = 0; k < 2; ++k)
        worst_w = std::max({worst_w, std::abs(wc[i][k] - e.w[i][k]), std::abs(wa[i][k] - e.w[i][k])});
    CHECK(worst_w <= 1e-13);  // terms of size <= rc^2, at most ~60 of them
  }
}
