// Float lanes (simd/float_lanes.hpp) against the obvious scalar code, lane by
// lane: loads rounded to float, the two double masks as one float mask, and
// gathers from double and float arrays into either lane type, through the
// batch's 64-bit indices. Built with the runtime's flags and with
// -march=native (test_pair_batches.cpp says what that covers).
#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <vector>

#include "partc/simd/float_lanes.hpp"

namespace simd = partc::simd;
namespace hn = partc::simd::hn;

namespace {

constexpr std::size_t particles = 1000;

// Two vectors of doubles' worth of values, the stored arrays they index, and
// indices into them (as a PairBatch holds j).
struct Lanes {
  std::size_t doubles = hn::Lanes(simd::Real());
  std::size_t floats = hn::Lanes(simd::Float());
  std::vector<double> values, stored_double;
  std::vector<float> stored_float;
  std::vector<std::uint64_t> index;

  Lanes() {
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<std::uint64_t> at(0, particles - 1);
    for (std::size_t k = 0; k < 2 * doubles; ++k) values.push_back(u(random) / 3.0);
    for (std::size_t k = 0; k < particles; ++k) {
      stored_double.push_back(u(random) / 7.0);
      stored_float.push_back(static_cast<float>(u(random) / 7.0));
    }
    for (std::size_t k = 0; k < 2 * doubles; ++k) index.push_back(at(random));
  }
};

template <class D>
std::vector<hn::TFromD<D>> stored(D d, hn::Vec<D> v) {
  std::vector<hn::TFromD<D>> out(hn::Lanes(d));
  hn::StoreU(v, d, out.data());
  return out;
}

}  // namespace

TEST_CASE("float lanes: doubles rounded to float, in order", "[simd]") {
  const Lanes l;
  const std::vector<float> got = stored(simd::Float(), simd::load_demoted(l.values.data()));
  for (std::size_t k = 0; k < l.floats; ++k) CHECK(got[k] == static_cast<float>(l.values[k]));
  // Rounded, not truncated: some value's float differs from its double.
  bool rounded = false;
  for (std::size_t k = 0; k < l.floats; ++k) rounded |= double{got[k]} != l.values[k];
  CHECK(rounded);
}

TEST_CASE("float lanes: a condition's two double masks as one float mask", "[simd]") {
  const Lanes l;
  const simd::Real d;
  const auto zero = hn::Zero(d);
  const auto low = hn::Gt(hn::LoadU(d, l.values.data()), zero);
  const auto high = hn::Gt(hn::LoadU(d, l.values.data() + l.doubles), zero);
  const simd::Float f;
  const std::vector<float> got =
      stored(f, hn::IfThenElseZero(simd::demote_mask(low, high), hn::Set(f, 1.0f)));
  for (std::size_t k = 0; k < l.floats; ++k) CHECK((got[k] == 1.0f) == (l.values[k] > 0));
}

TEST_CASE("float lanes: gathers from either storage into either lanes", "[simd]") {
  const Lanes l;
  const simd::Real d;
  const simd::Float f;
  const auto wide = simd::index_lanes(d, l.index.data());
  const auto narrow = simd::index_lanes(f, l.index.data());
  const std::vector<double> dd = stored(d, simd::gather(d, l.stored_double.data(), wide));
  const std::vector<double> fd = stored(d, simd::gather(d, l.stored_float.data(), wide));
  const std::vector<float> ff = stored(f, simd::gather(f, l.stored_float.data(), narrow));
  const std::vector<float> df = stored(f, simd::gather(f, l.stored_double.data(), narrow));
  for (std::size_t k = 0; k < l.doubles; ++k) {
    CHECK(dd[k] == l.stored_double[l.index[k]]);
    CHECK(fd[k] == double{l.stored_float[l.index[k]]});
  }
  for (std::size_t k = 0; k < l.floats; ++k) {
    CHECK(ff[k] == l.stored_float[l.index[k]]);
    CHECK(df[k] == static_cast<float>(l.stored_double[l.index[k]]));
  }
}
