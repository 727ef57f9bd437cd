// partc/fast_sum/direct_sum.hpp: the direct sum from a run of sources to one
// point, the inner loop of the near field (P2P) and of the cross-level
// interactions (M2P: a box's proxies at its nodes to points; P2L: points to
// a box's nodes).
//
// Sources come as one contiguous array per coordinate, so the loop over them
// has no branches and vectorises (GCC with -O3 -fno-math-errno; a kernel
// with exp needs glibc's vector exp, i.e. -ffast-math, to vectorise).
//
// Surprises:
// - the sum over sources is a SIMD reduction: its order is fixed by the
//   compiled vector width, not by the thread that runs it, so it is bitwise
//   reproducible for any thread count but not between builds.
// - the kernel is called with r = 0 for coincident points; it decides what
//   that means (1/r kernels return 0 there, say).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace partc::fast_sum {

// Without OpenMP (or -fopenmp-simd) the simd pragmas are plain loops.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunknown-pragmas"

// sum_j kernel(|y_j - x|) q_j over j < count.
template <int D, class Kernel>
double direct_potential(const Kernel& kernel, const double* x,
                        const std::array<const double*, D>& y, const double* q, std::size_t count) {
  double sum = 0;
#pragma omp simd reduction(+ : sum)
  for (std::size_t j = 0; j < count; ++j) {
    double r2 = 0;
    for (std::size_t d = 0; d < D; ++d) {
      const double dx = y[d][j] - x[d];
      r2 += dx * dx;
    }
    sum += kernel(std::sqrt(r2)) * q[j];
  }
  return sum;
}

// out[d] += sum_j kernel(|y_j - x|) (y_j - x)_d q_j over j < count.
template <int D, class Kernel>
void direct_field(const Kernel& kernel, const double* x, const std::array<const double*, D>& y,
                  const double* q, std::size_t count, double* out) {
  static_assert(D >= 1 && D <= 3, "fast sums are for 1 to 3 dimensions");
  double s0 = 0, s1 = 0, s2 = 0;
#pragma omp simd reduction(+ : s0, s1, s2)
  for (std::size_t j = 0; j < count; ++j) {
    double dx[D];
    double r2 = 0;
    for (std::size_t d = 0; d < D; ++d) {
      dx[d] = y[d][j] - x[d];
      r2 += dx[d] * dx[d];
    }
    const double f = kernel(std::sqrt(r2)) * q[j];
    s0 += f * dx[0];
    if constexpr (D > 1) s1 += f * dx[1];
    if constexpr (D > 2) s2 += f * dx[2];
  }
  out[0] += s0;
  if constexpr (D > 1) out[1] += s1;
  if constexpr (D > 2) out[2] += s2;
}

#pragma GCC diagnostic pop

}  // namespace partc::fast_sum
