// partc/fast_sum/accuracy.hpp: how accurate a fast sum was, measured against
// the direct sum at a sample of targets; what --check-accuracy reports.
//
//   const auto measured = measure_potential(fmm, sources, targets, kernel, q, phi);
//   if (measured.rel_l2 > tol)  // "asked tol 1e-6, measured 3e-6 (relative L2 over
//     ...                       //  500 targets); order 9 would meet it"
//       order_to_meet(fmm, tol, measured.rel_l2);
//
// The sample is deterministic: every (N / samples)-th target, in the caller's
// order. The direct sums are plain loops, written apart from the FMM's near
// field, so that a bug there cannot hide itself.
//
// Surprises:
// - max_rel is the largest error over the sample relative to the largest
//   |exact| value of the sample (not pointwise relative: sums may vanish).
// - order_to_meet scales the model's predictions by measured / predicted at
//   the plan's order; -1 if no order up to max_order meets tol.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "partc/fast_sum/fmm.hpp"
#include "partc/vec.hpp"

namespace partc::fast_sum {

struct MeasuredError {
  double rel_l2 = 0;   // sqrt(sum |fmm - exact|^2 / sum |exact|^2) over the sample
  double max_rel = 0;  // max |fmm - exact| / max |exact| over the sample
  std::size_t targets = 0;
};

namespace detail {

inline std::vector<std::size_t> sample_targets(std::size_t n, std::size_t samples) {
  std::vector<std::size_t> picked;
  const std::size_t stride = std::max<std::size_t>(1, n / std::max<std::size_t>(1, samples));
  for (std::size_t i = 0; i < n && picked.size() < samples; i += stride) picked.push_back(i);
  return picked;
}

// fast(i, c) and exact(i, value): component c of target i's fast sum, and the
// C components of its direct sum.
template <int C, class Fast, class Exact>
MeasuredError compare(std::size_t n_targets, std::size_t samples, Fast fast, Exact exact) {
  MeasuredError e;
  double error2 = 0, exact2 = 0, max_error = 0, max_exact = 0;
  for (std::size_t i : sample_targets(n_targets, samples)) {
    double value[C];
    exact(i, value);
    for (int c = 0; c < C; ++c) {
      const double diff = fast(i, c) - value[c];
      error2 += diff * diff;
      exact2 += value[c] * value[c];
      max_error = std::max(max_error, std::abs(diff));
      max_exact = std::max(max_exact, std::abs(value[c]));
    }
    ++e.targets;
  }
  e.rel_l2 = exact2 > 0 ? std::sqrt(error2 / exact2) : std::sqrt(error2);
  e.max_rel = max_exact > 0 ? max_error / max_exact : max_error;
  return e;
}

}  // namespace detail

// fast: the potential as Fmm::potential gave it, for the same q.
template <int D, class Kernel, class T>
MeasuredError measure_potential(const std::vector<Vec<D, T>>& sources,
                                const std::vector<Vec<D, T>>& targets, const Kernel& kernel,
                                const double* q, const double* fast, std::size_t samples = 500) {
  auto at = [&](std::size_t i, int) { return fast[i]; };
  return detail::compare<1>(targets.size(), samples, at, [&](std::size_t i, double* value) {
    value[0] = 0;
    for (std::size_t j = 0; j < sources.size(); ++j)
      value[0] += kernel(norm(widen(sources[j]) - widen(targets[i]))) * q[j];
  });
}

// fast: the field as Fmm::field gave it, for the same q.
template <int D, class Kernel, class T>
MeasuredError measure_field(const std::vector<Vec<D, T>>& sources,
                            const std::vector<Vec<D, T>>& targets, const Kernel& kernel,
                            const double* q, const Vec<D>* fast, std::size_t samples = 500) {
  auto at = [&](std::size_t i, int c) { return fast[i][c]; };
  return detail::compare<D>(targets.size(), samples, at, [&](std::size_t i, double* value) {
    Vec<D> sum = Vec<D>::zero();
    for (std::size_t j = 0; j < sources.size(); ++j) {
      const Vec<D> r = widen(sources[j]) - widen(targets[i]);
      sum += r * (kernel(norm(r)) * q[j]);
    }
    for (int d = 0; d < D; ++d) value[d] = sum[d];
  });
}

// The lowest order whose prediction, scaled by how far the plan's order was
// off (measured / predicted), meets tol; -1 if none up to max_order(D) does.
template <int D, class Kernel>
int order_to_meet(const Fmm<D, Kernel>& fmm, double tol, double measured) {
  const double predicted = fmm.predicted_error();
  const double scale = predicted > 0 ? measured / predicted : 1.0;
  for (int p = 2; p <= max_order(D); ++p)
    if (fmm.predicted_error(p) * scale <= tol) return p;
  return -1;
}

}  // namespace partc::fast_sum
