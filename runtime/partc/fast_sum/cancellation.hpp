// partc/fast_sum/cancellation.hpp: how far given charges make a sum cancel,
// beyond what the error model (error_model.hpp) assumes; a plan made for
// known charges multiplies its predictions by it.
//
// The model predicts the error relative to the size a result has on average
// over charges drawn independently (with these charges' mean square):
//   expected = sum_i sum_j k(r_ij)^2 q_j^2,
// but what is asked is the error relative to the actual result
//   actual   = sum_i (sum_j k(r_ij) q_j)^2.
// For a smooth kernel (a multiquadric) the far field is mostly the charges'
// lowest moments, so charges whose total and dipole nearly cancel give a
// result far smaller than expected, while the error, which comes from each
// box's own charges, does not shrink with it: bench_fast_sum's charges at
// N = 1e5 (total 0.22 of its standard deviation) give multiquadric sums 0.02
// of their expected square (cancellation 5.5 to 7), and errors 1.7 to 2.4x
// the prediction (tol 1e-3, 1e-4 and 1e-8 missed). The cancellation is
// sqrt(expected / actual); the plan multiplies its predictions by it over
// typical_cancellation.
//
// Both sums at every stride-th target (up to `samples` of them) over every
// source: exact there, where a sample of the sources would miss the very
// cancellation it measures; at N = 1e5, 128 targets cost ~1e7 kernel calls.
//
// Surprises:
// - never below 1: charges of one sign give a result larger than expected,
//   but the model does not know how much their error grows with it; they
//   are planned as charges that do not cancel (a prediction 1 / 1.6 of one
//   without the charges).
// - a result that cancels to 0 exactly gives infinity: no order meets a
//   relative tolerance of it.
// - k is called with r = 0 for coincident points, as the near field does.
// - field: the same with k(r) (y_j - x_i), squared and summed over components.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "partc/parallel.hpp"
#include "partc/vec.hpp"

namespace partc::fast_sum {

// The cancellation the error model's calibration (2.5) allows for when the
// charges are not known (error_model.hpp): charges drawn in [-1, 1] give
// results typically 0.3 to 0.9 of their expected square, i.e. 1.05 to 1.8.
// A plan that knows its charges divides it out again. 1.6 puts the measured
// error at or below 0.78 of the prediction over bench_fast_sum's N = 1e4
// table (all kernels, uniform and Plummer, tol 1e-2 to 1e-10), as 2.5 did
// without the charges; the most at N = 1e5 was 0.86 (1/r, Plummer, tol 1e-4).
constexpr double typical_cancellation = 1.6;

template <int D, class Kernel, class T>
double measure_cancellation(const std::vector<Vec<D, T>>& sources,
                            const std::vector<Vec<D, T>>& targets, const Kernel& kernel,
                            const double* q, bool field, std::size_t samples = 128) {
  if (sources.empty() || targets.empty() || samples == 0) return 1.0;
  const std::size_t stride = std::max<std::size_t>(1, targets.size() / samples);
  const std::size_t picked = (targets.size() + stride - 1) / stride;
  // Per sampled target, then added in order: the same for any number of threads.
  std::vector<double> expected(picked, 0.0), actual(picked, 0.0);
  parallel_for(picked, LoopWork::blocks, [&](std::size_t s) {
    const Vec<D> x = widen(targets[s * stride]);
    double sum[D] = {}, squares = 0;
    for (std::size_t j = 0; j < sources.size(); ++j) {
      const Vec<D> dx = widen(sources[j]) - x;
      const double r = norm(dx), kq = kernel(r) * q[j];
      if (!field) {
        sum[0] += kq;
        squares += kq * kq;
      } else {
        for (int d = 0; d < D; ++d) sum[d] += kq * dx[d];
        squares += kq * kq * r * r;
      }
    }
    for (int d = 0; d < (field ? D : 1); ++d) actual[s] += sum[d] * sum[d];
    expected[s] = squares;
  });
  double e = 0, a = 0;
  for (std::size_t s = 0; s < picked; ++s) {
    e += expected[s];
    a += actual[s];
  }
  if (!(a > 0)) return e > 0 ? HUGE_VAL : 1.0;
  return std::max(1.0, std::sqrt(e / a));
}

}  // namespace partc::fast_sum
