// partc/simd/highway.hpp: the portable SIMD of partc's vectorised loops,
// Google Highway (libhwy), for the compiler's target only (static dispatch):
// the vectors are as wide as the flags allow, so -march=native (CMake's
// PARTC_NATIVE, on by default) gives AVX2 or AVX-512 here, NEON on ARM, and
// the default x86-64 flags SSE2. Highway rather than intrinsics, so that one
// generated file runs on all of them; its contrib math gives exp, log and the
// other elementary functions on vectors (a few ulp, where std:: gives < 1).
//
// hn names the target's ops; Real is a vector tag of doubles, Index one of
// unsigned integers of the same width (a lane per pair in both); Float one
// of floats, as wide as Real's vectors (twice the lanes: float_lanes.hpp).
#pragma once

// Only the static target: no dispatch tables, and Highway 1.0.3's check of
// them fails under -march=native on AVX-512 machines ("best baseline should
// be included in dynamic targets").
#ifndef HWY_COMPILE_ONLY_STATIC
#define HWY_COMPILE_ONLY_STATIC 1
#endif
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

namespace partc::simd {

namespace hn = hwy::HWY_NAMESPACE;

using Real = hn::ScalableTag<double>;
using Index = hn::RebindToUnsigned<Real>;
#if HWY_TARGET == HWY_SCALAR
using Float = hn::Rebind<float, Real>;  // one lane, as Real's
#else
using Float = hn::Repartition<float, Real>;
#endif

// Lanes of a Real vector: a batch's buffers are padded by this many entries.
inline std::size_t lanes() { return hn::Lanes(Real()); }

}  // namespace partc::simd
