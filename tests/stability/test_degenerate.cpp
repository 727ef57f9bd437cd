// Degenerate radii and an overflowing kernel (tests/stability/degenerate.part).
// - A radius of 0 (or -0.0): count(j, |dx| <= r) holds for j == i and i's
//   coincident twin only, by every search: each count is exactly 2, and the
//   nearest other particle is at 0. Reference: brute force over the model's
//   positions, exact (only d == 0 counts).
// - A negative radius: no pair satisfies |dx| <= r, so every count is 0 and
//   min / max over the empty neighbourhood give the value written for none
//   (-1, -2), never +-inf.
// - exp(s / |dx|) with s = 0.5 is e^500 = 1.4e217 for the close pair, finite,
//   and every sum matches a long double brute force to 1.5e-13 (the argument's
//   own rounding, 500 x 2^-53 relative, scaled by exp); with s = 1 it is e^1000 = inf,
//   and check_finite throws NumericalError whose fields name set H, variable
//   hot, a particle of the close pair (id 0 or 1), step 1 and +inf.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "brute.hpp"
#include "degenerate.hpp"

namespace {

using V = brute::Vec<2>;

// Exact: whether two positions are one point of the torus.
std::vector<std::int64_t> coincident_counts(const std::vector<V>& p) {
  std::vector<std::int64_t> n(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j)
      n[i] += brute::norm(brute::minimum_image<2>({p[j][0] - p[i][0], p[j][1] - p[i][1]}, 1.0)) == 0;
  return n;
}

}  // namespace

TEST_CASE("a zero radius counts exactly the coincident particles, by every search",
          "[stability][degenerate]") {
  for (const double r : {0.0, -0.0}) {
    INFO("r = " << r << (std::signbit(r) ? " (negative zero)" : ""));
    Degenerate model;
    model.params().r = r;
    model.init();
    model.step();
    CHECK_NOTHROW(model.check_finite());
    const auto p = brute::positions_by_id<2>(model.C());
    const auto expected = coincident_counts(p);
    for (std::size_t i = 0; i < p.size(); ++i) REQUIRE(expected[i] == 2);  // itself and its twin
    CHECK(brute::values_by_id<Degenerate::C_n_cells>(model.C()) == expected);
    CHECK(brute::values_by_id<Degenerate::C_n_tree>(model.C()) == expected);
    CHECK(brute::values_by_id<Degenerate::C_n_brute>(model.C()) == expected);
    CHECK(brute::values_by_id<Degenerate::C_n_auto>(model.C()) == expected);
    for (double d : brute::values_by_id<Degenerate::C_nearest>(model.C())) CHECK(d == 0.0);
    for (double d : brute::values_by_id<Degenerate::C_farthest>(model.C())) CHECK(d == 0.0);
  }
}

TEST_CASE("a negative radius gives empty neighbourhoods: counts 0, min and max give "
          "their value for none",
          "[stability][degenerate]") {
  for (const double r : {-0.5, -std::numeric_limits<double>::min(), -1e300}) {
    INFO("r = " << r);
    Degenerate model;
    model.params().r = r;
    model.init();
    model.step();
    CHECK_NOTHROW(model.check_finite());
    const std::vector<std::int64_t> none(model.params().N, 0);
    CHECK(brute::values_by_id<Degenerate::C_n_cells>(model.C()) == none);
    CHECK(brute::values_by_id<Degenerate::C_n_tree>(model.C()) == none);
    CHECK(brute::values_by_id<Degenerate::C_n_brute>(model.C()) == none);
    CHECK(brute::values_by_id<Degenerate::C_n_auto>(model.C()) == none);
    for (double d : brute::values_by_id<Degenerate::C_nearest>(model.C())) CHECK(d == -1.0);
    for (double d : brute::values_by_id<Degenerate::C_farthest>(model.C())) CHECK(d == -2.0);
  }
}

TEST_CASE("exp(s / |dx|) at e^500 matches brute force; at e^1000 it overflows and the "
          "finite check names the set, variable, particle and step",
          "[stability][degenerate][overflow]") {
  const auto brute_hot = [](const std::vector<V>& p, double s) {
    std::vector<long double> hot(p.size(), 0);
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = 0; j < p.size(); ++j) {
        const double d = brute::norm(brute::minimum_image<2>({p[j][0] - p[i][0], p[j][1] - p[i][1]}, 1.0));
        if (d < 0.15 && d > 0) hot[i] += std::exp(static_cast<long double>(s) / d);
      }
    return hot;
  };
  SECTION("s = 0.5: finite, e^500 for the close pair") {
    Degenerate model;
    model.params().s = 0.5;
    model.init();
    model.step();
    CHECK_NOTHROW(model.check_finite());
    const auto p = brute::positions_by_id<2>(model.H());
    const auto want = brute_hot(p, 0.5);
    const auto got = brute::values_by_id<Degenerate::H_hot>(model.H());
    CHECK(want[0] > 1e217L);
    double worst = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      worst = std::max(worst, static_cast<double>(std::abs(got[i] - want[i]) / want[i]));
    INFO("largest relative error " << worst);
    // s / |dx| = 500 rounds by half an ulp (5.7e-14 absolute); exp turns that into
    // a relative 5.7e-14; |dx| and exp round once more each.
    CHECK(worst <= 1.5e-13);
  }
  SECTION("s = 1: e^1000 overflows") {
    Degenerate model;
    model.params().s = 1;
    model.init();
    model.step();
    const auto got = brute::values_by_id<Degenerate::H_hot>(model.H());
    CHECK(got[0] == std::numeric_limits<double>::infinity());
    CHECK(got[1] == std::numeric_limits<double>::infinity());
    for (std::size_t i = 2; i < got.size(); ++i) CHECK(std::isfinite(got[i]));
    try {
      model.check_finite();
      FAIL("check_finite did not throw");
    } catch (const partc::NumericalError& e) {
      INFO(e.what());
      CHECK(e.set == "H");
      CHECK(e.variable == "hot");
      CHECK((e.id == 0 || e.id == 1));
      CHECK(e.step == 1);
      CHECK(e.value == std::numeric_limits<double>::infinity());
      CHECK_THAT(e.what(), Catch::Contains("variable 'hot' of particle id") &&
                               Catch::Contains("is inf at step 1 (set H)"));
    }
  }
}
