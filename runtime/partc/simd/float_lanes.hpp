// partc/simd/float_lanes.hpp: what a pair term computed on floats
// (schedule: arithmetic = float) reads from a PairBatch, whose walk stays in
// double: a vector of floats as wide as one of doubles holds twice the pairs,
// so each load takes two vectors' worth of doubles and rounds them to float,
// and a condition decided on those two vectors of doubles becomes one mask;
// and gathers of particle variables in either storage, converted to the lanes
// the term is computed on (a float variable widened for double lanes, a
// double one rounded for float lanes).
//
// Surprises:
// - A float vector covers hn::Lanes(Float()) pairs: the loop steps by that
//   and runs to PairBatch::padded(hn::Lanes(Float())), which the batch's
//   padding covers.
// - Float lanes index particles with 32-bit integers (gathers of floats take
//   lanes of their width): a set may hold at most 2^31 particles.
// - Highway 1.0.3 has no OrderedDemote2To for doubles: two halves are
//   demoted and combined instead (the same values, in order).
#pragma once

#include <cstdint>

#include "partc/simd/highway.hpp"

namespace partc::simd {

// Signed index lanes for GatherIndex in vectors of tag D.
template <class D>
using IndexLanes = hn::Vec<hn::RebindToSigned<D>>;

// Two vectors of doubles as one of floats, each rounded to the nearest
// float (low: the first pairs).
HWY_INLINE hn::Vec<Float> demote(hn::Vec<Real> low, hn::Vec<Real> high) {
#if HWY_TARGET == HWY_SCALAR
  (void)high;  // one lane: a vector of floats covers one pair, as one of doubles
  return hn::DemoteTo(Float(), low);
#else
  const hn::Rebind<float, Real> half;
  return hn::Combine(Float(), hn::DemoteTo(half, high), hn::DemoteTo(half, low));
#endif
}

// Lanes(Float()) doubles from p, each rounded to the nearest float.
HWY_INLINE hn::Vec<Float> load_demoted(const double* p) {
  const Real d;
  return demote(hn::LoadU(d, p), hn::LoadU(d, p + hn::Lanes(d)));
}

// The mask of a vector of floats from those of the two vectors of doubles
// it covers (low: its first pairs): conditions are decided in double.
HWY_INLINE hn::Mask<Float> demote_mask(hn::Mask<Real> low, hn::Mask<Real> high) {
  const auto one = hn::Set(Real(), 1.0);
  return hn::Ne(demote(hn::IfThenElseZero(low, one), hn::IfThenElseZero(high, one)),
                hn::Zero(Float()));
}

// The batch's particle indices from p (its i() or j(), plus k), one per lane.
HWY_INLINE IndexLanes<Real> index_lanes(Real, const std::uint64_t* p) {
  return hn::BitCast(hn::RebindToSigned<Real>(), hn::LoadU(Index(), p));
}
HWY_INLINE IndexLanes<Float> index_lanes(Float, const std::uint64_t* p) {
  const hn::RebindToSigned<Float> di;
#if HWY_TARGET == HWY_SCALAR
  return hn::BitCast(di, hn::TruncateTo(hn::RebindToUnsigned<Float>(), hn::LoadU(Index(), p)));
#else
  const hn::Rebind<std::uint32_t, Index> half;
  const hn::RebindToSigned<decltype(half)> signed_half;
  const auto lo = hn::BitCast(signed_half, hn::TruncateTo(half, hn::LoadU(Index(), p)));
  const auto hi =
      hn::BitCast(signed_half, hn::TruncateTo(half, hn::LoadU(Index(), p + hn::Lanes(Index()))));
  return hn::Combine(di, hi, lo);
#endif
}

// base[index] per lane, in the lanes of the tag: as stored, widened or rounded.
HWY_INLINE hn::Vec<Real> gather(Real d, const double* base, IndexLanes<Real> index) {
  return hn::GatherIndex(d, base, index);
}
HWY_INLINE hn::Vec<Float> gather(Float f, const float* base, IndexLanes<Float> index) {
  return hn::GatherIndex(f, base, index);
}
HWY_INLINE hn::Vec<Real> gather(Real d, const float* base, IndexLanes<Real> index) {
  const hn::Rebind<float, Real> narrow;
  const hn::Rebind<std::int32_t, Real> narrow_index;
  const auto at =
      hn::BitCast(narrow_index, hn::TruncateTo(hn::Rebind<std::uint32_t, Real>(),
                                               hn::BitCast(hn::RebindToUnsigned<Real>(), index)));
  return hn::PromoteTo(d, hn::GatherIndex(narrow, base, at));
}
HWY_INLINE hn::Vec<Float> gather(Float f, const double* base, IndexLanes<Float> index) {
  const Real d;
  const hn::RebindToSigned<Real> wide_index;
#if HWY_TARGET == HWY_SCALAR
  return hn::DemoteTo(f, hn::GatherIndex(d, base, hn::PromoteTo(wide_index, index)));
#else
  const hn::Rebind<float, Real> half;
  const hn::Half<hn::RebindToSigned<Float>> half_index;
  const auto lo = hn::GatherIndex(d, base, hn::PromoteTo(wide_index, hn::LowerHalf(index)));
  const auto hi =
      hn::GatherIndex(d, base, hn::PromoteTo(wide_index, hn::UpperHalf(half_index, index)));
  return hn::Combine(f, hn::DemoteTo(half, hi), hn::DemoteTo(half, lo));
#endif
}

}  // namespace partc::simd
