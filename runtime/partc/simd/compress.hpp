// partc/simd/compress.hpp: Compressor, the compress of vectors of 64-bit
// lanes (doubles and pair indices) that PairBatch packs hits with: the lanes a
// mask selects moved to the front, in order, by one table lookup per vector.
//
// Why not hn::Compress: Highway 1.0.3 (Debian 12's libhwy) keeps its compress
// tables in non-static constexpr locals, which GCC 12 copies to the stack at
// every call: 2 KiB a call on AVX-512 (a memcpy), 512 B on AVX2 (rep movsq).
// Measured on the seed's pair walk (tests/bench/bench_pair_batches, N = 1e5,
// AVX-512): the packed walk ran at 4.5e6 points/s against 1.0e7 for the
// scalar one. Here the table is a static constant built once at compile time.
// Vectors wider than 8 lanes (none for 64 bits today) use hn::Compress.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "partc/simd/highway.hpp"

namespace partc::simd {

namespace detail {

// Row m: the lanes whose bit is set in m, in order, then the others.
template <std::size_t L>
struct CompressTable {
  static constexpr std::array<std::int32_t, L << L> make() {
    std::array<std::int32_t, L << L> rows{};
    for (std::size_t m = 0; m < (std::size_t{1} << L); ++m) {
      std::size_t next = m * L;
      for (std::size_t lane = 0; lane < L; ++lane)
        if (m >> lane & 1) rows[next++] = static_cast<std::int32_t>(lane);
      for (std::size_t lane = 0; lane < L; ++lane)
        if (!(m >> lane & 1)) rows[next++] = static_cast<std::int32_t>(lane);
    }
    return rows;
  }
  static constexpr std::array<std::int32_t, L << L> rows = make();
};

}  // namespace detail

// One mask's compress, applied to any number of vectors of 64-bit lanes.
class Compressor {
 public:
  explicit Compressor(hn::Mask<Real> keep) : keep_(keep), count_(hn::CountTrue(Real(), keep)) {
    if constexpr (by_table) {
      std::uint8_t bits[8] = {};
      hn::StoreMaskBits(Real(), keep, bits);
      const hn::Rebind<std::int32_t, Signed> d32;
      lanes_ = hn::PromoteTo(Signed(), hn::LoadU(d32, table.data() + bits[0] * max_lanes));
    }
  }
  std::size_t count() const { return count_; }

  hn::Vec<Real> operator()(hn::Vec<Real> v) const {
    if constexpr (by_table)
      return hn::TableLookupLanes(v, hn::IndicesFromVec(Real(), lanes_));
    else
      return hn::Compress(v, keep_);
  }
  hn::Vec<Index> operator()(hn::Vec<Index> v) const {
    if constexpr (by_table)
      return hn::TableLookupLanes(v, hn::IndicesFromVec(Index(), lanes_));
    else
      return hn::Compress(v, hn::RebindMask(Index(), keep_));
  }

 private:
  using Signed = hn::RebindToSigned<Real>;
  static constexpr std::size_t max_lanes = hn::MaxLanes(Real());
  static constexpr bool by_table = max_lanes >= 2 && max_lanes <= 8;
  static constexpr const auto& table = detail::CompressTable < by_table ? max_lanes : 1 > ::rows;

  hn::Mask<Real> keep_;
  std::size_t count_;
  hn::Vec<Signed> lanes_;
};

}  // namespace partc::simd
