// CounterRng: Philox4x32-10 against the published Random123 answers, the
// documented counter layout, statistics, and that no two tuples share a draw.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <vector>

#include "partc/rng.hpp"

using partc::CounterRng;
using partc::PhiloxCounter;
using partc::PhiloxKey;

TEST_CASE("philox4x32_10 matches the Random123 known-answer vectors", "[rng]") {
  CHECK(partc::philox4x32_10({0, 0, 0, 0}, {0, 0}) ==
        PhiloxCounter{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8});
  CHECK(partc::philox4x32_10({0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff},
                             {0xffffffff, 0xffffffff}) ==
        PhiloxCounter{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd});
  CHECK(partc::philox4x32_10({0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344},
                             {0xa4093822, 0x299f31d0}) ==
        PhiloxCounter{0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1});
}

TEST_CASE("uniform reads the documented counter layout and key", "[rng]") {
  const std::uint64_t seed = 0x0123456789abcdefULL;
  const std::uint64_t id = 0x0000ba9876543210ULL, step = 0x0000fedcba987654ULL;
  const std::uint32_t stream = 0x1234, k = 0xbeef;
  const PhiloxCounter bits = partc::philox4x32_10(
      {0x76543210, 0x0000ba98 | (stream << 16), 0xba987654, 0x0000fedc | (k << 16)},
      {0x89abcdef, 0x01234567});
  const std::uint64_t top53 = ((std::uint64_t{bits[1]} << 32) | bits[0]) >> 11;
  CHECK(CounterRng(seed).uniform(id, step, stream, k) == std::ldexp(double(top53), -53));
  CHECK(CounterRng(seed).seed() == seed);
}

TEST_CASE("draws are pure functions of the tuple", "[rng]") {
  const CounterRng a(7), b(7);
  CHECK(a.uniform(3, 4, 5, 6) == b.uniform(3, 4, 5, 6));
  CHECK(a.normal(3, 4, 5, 6) == a.normal(3, 4, 5, 6));
  CHECK(a.uniform(3, 4, 5) == a.uniform(3, 4, 5, 0));  // k defaults to 0
}

TEST_CASE("every coordinate of the tuple changes the draw, at every bit boundary", "[rng]") {
  // Values on both sides of the 32-bit word boundaries and at the top of each
  // field catch a layout in which two fields overlap.
  const std::vector<std::uint64_t> wide = {
      0, 1, 2, 0xffffffffULL, 0x100000000ULL, 0xffffffffffffULL};
  const std::vector<std::uint32_t> narrow = {0, 1, 2, 0x7fff, 0x8000, 0xffff};
  const CounterRng rng(42);
  std::set<double> draws;
  std::size_t tuples = 0;
  for (const auto id : wide)
    for (const auto step : wide)
      for (const auto stream : narrow)
        for (const auto k : narrow) {
          draws.insert(rng.uniform(id, step, stream, k));
          ++tuples;
        }
  CHECK(draws.size() == tuples);
  CHECK(CounterRng(1).uniform(0, 0, 0) != CounterRng(2).uniform(0, 0, 0));
  CHECK(CounterRng(1).uniform(0, 0, 0) != CounterRng(1ULL << 32).uniform(0, 0, 0));
}

TEST_CASE("tuples outside the collision-free range are refused", "[rng]") {
  const CounterRng rng;
  CHECK_THROWS_AS(rng.uniform(1ULL << 48, 0, 0), std::out_of_range);
  CHECK_THROWS_AS(rng.uniform(0, 1ULL << 48, 0), std::out_of_range);
  CHECK_THROWS_AS(rng.normal(0, 0, 1U << 16), std::out_of_range);
  CHECK_THROWS_WITH(rng.uniform(0, 0, 0, 1U << 16),
                    Catch::Contains("id and step < 2^48, stream and k < 2^16"));
  // A particle id of -1 (an int64 cast to the uint64 parameter) is caught too.
  CHECK_THROWS_AS(rng.uniform(static_cast<std::uint64_t>(std::int64_t{-1}), 0, 0),
                  std::out_of_range);
}

namespace {

struct Moments {
  double mean, variance;
};

template <class Draw>
Moments moments(std::size_t n, Draw&& draw) {
  double sum = 0, sum_squares = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = draw(i);
    sum += x;
    sum_squares += x * x;
  }
  const double mean = sum / double(n);
  return {mean, sum_squares / double(n) - mean * mean};
}

}  // namespace

TEST_CASE("uniform: [0, 1), mean 1/2 and variance 1/12 within 4 standard errors", "[rng]") {
  const CounterRng rng(2024);
  const std::size_t n = 100000;
  // Consecutive ids at one step, as particles of one set use them.
  double low = 1, high = 0;
  const Moments m = moments(n, [&](std::size_t i) {
    const double u = rng.uniform(i, 17, 3);
    low = std::min(low, u);
    high = std::max(high, u);
    return u;
  });
  CHECK(low >= 0.0);
  CHECK(high < 1.0);
  CHECK(std::abs(m.mean - 0.5) < 4 * std::sqrt(1.0 / 12 / n));
  // The sample variance averages (u - 1/2)^2, whose own variance is 1/180.
  CHECK(std::abs(m.variance - 1.0 / 12) < 4 * std::sqrt(1.0 / 180 / n));

  // Ten equal bins: chi-squared with 9 degrees of freedom, 99.9% point 27.9.
  std::vector<double> bins(10, 0);
  for (std::size_t i = 0; i < n; ++i) bins[std::size_t(rng.uniform(5, i, 0) * 10)] += 1;
  double chi2 = 0;
  for (const double count : bins) chi2 += (count - n / 10.0) * (count - n / 10.0) / (n / 10.0);
  CHECK(chi2 < 27.9);
}

TEST_CASE("normal: mean 0, variance 1, no correlation between streams", "[rng]") {
  const CounterRng rng(99);
  const std::size_t n = 100000;
  const Moments m = moments(n, [&](std::size_t i) { return rng.normal(i, 0, 1); });
  CHECK(std::abs(m.mean) < 4 * std::sqrt(1.0 / n));
  // The sample variance averages x^2, whose own variance is 2.
  CHECK(std::abs(m.variance - 1.0) < 4 * std::sqrt(2.0 / n));

  const Moments product =
      moments(n, [&](std::size_t i) { return rng.normal(i, 0, 1) * rng.normal(i, 0, 2); });
  CHECK(std::abs(product.mean) < 4 * std::sqrt(1.0 / n));

  // Tails: P(|x| > 3) = 0.0027, so 270 expected; 4 standard errors is about 66.
  std::size_t beyond_three = 0;
  for (std::size_t i = 0; i < n; ++i) beyond_three += std::abs(rng.normal(i, 1, 0)) > 3;
  CHECK(std::abs(double(beyond_three) - 270.0) < 66);
}
