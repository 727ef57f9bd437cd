// Vec<D> arithmetic and Domain<D>'s periodic maps, against values worked out by
// hand and an independent reference (rounding the quotient d / L).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "partc/domain.hpp"
#include "partc/vec.hpp"

using partc::Domain;
using partc::Vec;

namespace {

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();
constexpr double inf_value = std::numeric_limits<double>::infinity();

Domain<1> periodic_1d(double lo, double hi) { return Domain<1>{{{lo}}, {{hi}}, {{true}}}; }

double image_1d(const Domain<1>& domain, double d) { return domain.minimum_image(Vec<1>{{d}})[0]; }
double wrap_1d(const Domain<1>& domain, double x) { return domain.wrap(Vec<1>{{x}})[0]; }

}  // namespace

template <int D>
using Dim = std::integral_constant<int, D>;

TEMPLATE_TEST_CASE("Vec arithmetic works component-wise", "[vec]", Dim<1>, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = TestType::value;
  Vec<D> a{}, b{};
  for (int k = 0; k < D; ++k) {
    CHECK(a[k] == 0.0);  // Vec<D>{} is zero
    a[k] = 1.5 + k;
    b[k] = -0.25 * (k + 1);
  }
  double expected_dot = 0.0;
  for (int k = 0; k < D; ++k) expected_dot += (1.5 + k) * (-0.25 * (k + 1));

  const Vec<D> sum = a + b, diff = a - b, neg = -a, scaled = a * 2.0, scaled2 = 2.0 * a,
               divided = a / 4.0;
  for (int k = 0; k < D; ++k) {
    CHECK(sum[k] == a[k] + b[k]);
    CHECK(diff[k] == a[k] - b[k]);
    CHECK(neg[k] == -a[k]);
    CHECK(scaled[k] == 2.0 * a[k]);
    CHECK(scaled2[k] == 2.0 * a[k]);
    CHECK(divided[k] == a[k] / 4.0);
    CHECK(Vec<D>::zero()[k] == 0.0);
    CHECK(Vec<D>::filled(7.5)[k] == 7.5);
  }
  Vec<D> c = a;
  c += b;
  CHECK(c == sum);
  c -= b;
  CHECK(c == a);
  c *= 3.0;
  CHECK(c == a * 3.0);
  c /= 3.0;
  CHECK(c == a);
  CHECK(a != b);
  CHECK(dot(a, b) == Approx(expected_dot));
  CHECK(squared_norm(a) == Approx(dot(a, a)));
  CHECK(norm(a) == Approx(std::sqrt(dot(a, a))));
  CHECK(is_finite(a));
  c[D - 1] = nan_value;
  CHECK_FALSE(is_finite(c));
  CHECK(c != c);  // NaN never equals itself
  c[D - 1] = -inf_value;
  CHECK_FALSE(is_finite(c));
}

TEST_CASE("Vec division divides rather than multiplying by the reciprocal", "[vec]") {
  // 3 / 10 is 0.3 but 3 * (1 / 10.0) is not.
  REQUIRE(3.0 * (1.0 / 10.0) != 0.3);
  CHECK((Vec<1>{{3.0}} / 10.0)[0] == 0.3);
}

TEST_CASE("norm is exact to rounding where the squares would underflow or overflow", "[vec]") {
  using partc::Vec;
  CHECK(partc::norm(Vec<2>{{1e-162, 0}}) == 1e-162);  // its square is 0
  CHECK(partc::norm(Vec<2>{{0, -1e-320}}) == 1e-320);  // a denormal component
  CHECK(partc::norm(Vec<2>{{3e-170, 4e-170}}) == Approx(5e-170).epsilon(1e-15));
  CHECK(partc::norm(Vec<3>{{1e-160, 1e-160, 1e-160}}) ==
        Approx(std::sqrt(3.0) * 1e-160).epsilon(1e-15));  // square denormal: 6e-6 off
  CHECK(partc::norm(Vec<2>{{3e200, -4e200}}) == Approx(5e200).epsilon(1e-15));
  CHECK(partc::norm(Vec<2>{{0, 0}}) == 0);
  CHECK(std::isinf(partc::norm(Vec<2>{{INFINITY, 1}})));
  CHECK(std::isnan(partc::norm(Vec<2>{{NAN, 1}})));
  CHECK(std::isnan(partc::norm(Vec<2>{{INFINITY, NAN}})));
  CHECK(partc::norm(Vec<2>{{0.6, 0.8}}) == std::sqrt(0.6 * 0.6 + 0.8 * 0.8));  // the usual path
}

TEST_CASE("Domain::length is hi - lo", "[domain]") {
  const Domain<2> d{{{-1.0, 0.5}}, {{3.0, 0.75}}, {{true, false}}};
  CHECK(d.length() == Vec<2>{{4.0, 0.25}});
}

TEST_CASE("minimum_image maps periodic components into [-L/2, L/2]", "[domain]") {
  const Domain<1> d = periodic_1d(-0.5, 0.25);  // L = 0.75, dyadic so the cases are exact
  const double L = 0.75;
  SECTION("short displacements are returned bit for bit") {
    for (double x : {0.0, -0.0, 0.1, -0.3, 0.375, -0.375}) CHECK(image_1d(d, x) == x);
  }
  SECTION("exactly half a box stays on its side") {
    CHECK(image_1d(d, L / 2) == L / 2);
    CHECK(image_1d(d, -L / 2) == -L / 2);
  }
  SECTION("displacements of many box lengths are exact") {
    for (long k : {1L, -1L, 2L, -2L, 3L, 17L, -1000L, 123456789L, -987654321L, 1L << 40}) {
      for (double x : {0.125, -0.25, 0.0, 0.3671875}) {
        const double displaced = x + static_cast<double>(k) * L;  // exact for these values
        INFO("k = " << k << ", x = " << x);
        CHECK(image_1d(d, displaced) == x);
      }
    }
  }
  SECTION("random displacements land in range and differ from the input by whole boxes") {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> exponent(-3.0, 9.0);
    std::uniform_int_distribution<int> sign(0, 1);
    for (int i = 0; i < 20000; ++i) {
      const double dist = (sign(rng) ? 1.0 : -1.0) * std::pow(10.0, exponent(rng));
      const double image = image_1d(d, dist);
      const double boxes = std::nearbyint(dist / L);  // independent reference
      INFO("d = " << dist);
      REQUIRE(std::abs(image) <= L / 2);
      REQUIRE(std::abs(image - (dist - boxes * L)) <=
              4 * std::numeric_limits<double>::epsilon() * std::abs(dist));
    }
  }
  SECTION("NaN stays NaN, infinity becomes NaN") {
    CHECK(std::isnan(image_1d(d, nan_value)));
    CHECK(std::isnan(image_1d(d, inf_value)));
    CHECK(std::isnan(image_1d(d, -inf_value)));
  }
}

TEST_CASE("minimum_image leaves non-periodic components alone", "[domain]") {
  const Domain<3> d{{{0.0, 0.0, 0.0}}, {{1.0, 1.0, 1.0}}, {{false, true, false}}};
  const Vec<3> image = d.minimum_image(Vec<3>{{5.25, 5.25, -7.5}});
  CHECK(image == Vec<3>{{5.25, 0.25, -7.5}});
}

TEST_CASE("wrap maps periodic components into [lo, hi)", "[domain]") {
  const Domain<1> d = periodic_1d(-0.5, 0.25);
  const double L = 0.75;
  SECTION("values inside are returned bit for bit") {
    for (double x : {-0.5, 0.0, 0.1, 0.2499999}) CHECK(wrap_1d(d, x) == x);
  }
  SECTION("hi is lo") { CHECK(wrap_1d(d, 0.25) == -0.5); }
  SECTION("many box lengths away") {
    for (long k : {1L, -1L, 2L, -5L, 1000L, -123456789L, 1L << 40}) {
      for (double x : {-0.5, -0.125, 0.0, 0.1875}) {
        INFO("k = " << k << ", x = " << x);
        CHECK(wrap_1d(d, x + static_cast<double>(k) * L) == x);
      }
    }
  }
  SECTION("the x == hi round-off case: a hair below lo") {
    // -tiny + L rounds to exactly L: the naive x + L would return hi.
    const Domain<1> unit = periodic_1d(0.0, 1.0);
    for (double x : {-1e-17, -std::numeric_limits<double>::denorm_min(), std::nextafter(0.0, -1.0),
                     -1.0 - 1e-16, std::nextafter(1.0, 2.0), 3.0}) {
      const double w = wrap_1d(unit, x);
      INFO("x = " << x << ", wrapped = " << w);
      CHECK(w >= 0.0);
      CHECK(w < 1.0);
    }
    CHECK(wrap_1d(unit, -1e-17) == 0.0);
  }
  SECTION("random values land in [lo, hi) and differ from the input by whole boxes") {
    const Domain<1> odd = periodic_1d(-1.3, 0.7);  // not dyadic: sums round
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> exponent(-20.0, 8.0);
    std::uniform_int_distribution<int> sign(0, 1);
    for (int i = 0; i < 20000; ++i) {
      const double x = (sign(rng) ? 1.0 : -1.0) * std::pow(10.0, exponent(rng)) - 1.3;
      const double w = wrap_1d(odd, x);
      INFO("x = " << x << ", wrapped = " << w);
      REQUIRE(w >= -1.3);
      REQUIRE(w < 0.7);
      const double boxes = (x - w) / 2.0;
      REQUIRE(std::abs(boxes - std::nearbyint(boxes)) <= 1e-9 * (1.0 + std::abs(boxes)));
    }
  }
  SECTION("NaN stays NaN, infinity becomes NaN") {
    CHECK(std::isnan(wrap_1d(d, nan_value)));
    CHECK(std::isnan(wrap_1d(d, inf_value)));
  }
}

TEST_CASE("wrap leaves non-periodic components alone", "[domain]") {
  const Domain<2> d{{{0.0, 0.0}}, {{1.0, 1.0}}, {{true, false}}};
  CHECK(d.wrap(Vec<2>{{1.25, 1.25}}) == Vec<2>{{0.25, 1.25}});
  CHECK(d.wrap(Vec<2>{{-0.75, -3.0}}) == Vec<2>{{0.25, -3.0}});
}

TEST_CASE("check_search_arguments rejects bad radii and periodic lengths", "[domain]") {
  const Domain<2> ok{{{0.0, 0.0}}, {{1.0, 1.0}}, {{true, false}}};
  CHECK_NOTHROW(partc::check_search_arguments(ok, 0.1));
  CHECK_NOTHROW(partc::check_search_arguments(ok, inf_value));
  CHECK_THROWS_AS(partc::check_search_arguments(ok, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(partc::check_search_arguments(ok, -1.0), std::invalid_argument);
  CHECK_THROWS_WITH(partc::check_search_arguments(ok, nan_value), Catch::Contains("radius"));
  const Domain<2> flat_periodic{{{0.0, 0.0}}, {{0.0, 1.0}}, {{true, false}}};
  CHECK_THROWS_WITH(partc::check_search_arguments(flat_periodic, 0.1),
                    Catch::Contains("periodic dimension 0"));
  const Domain<2> flat_open{{{0.0, 0.0}}, {{1.0, -1.0}}, {{true, false}}};
  CHECK_NOTHROW(partc::check_search_arguments(flat_open, 0.1));  // non-periodic: no length needed
}
