// partc/fast_sum/error_model.hpp: the predicted relative L2 error of a fast
// sum at each order, for one kernel and one pair of trees, before any charge
// is known; the plan picks the cheapest order whose prediction meets tol.
//
// The model treats the errors of the far pairs as uncorrelated (as they are
// for charges of mixed sign):
//   error^2 = sum over far box pairs  n_t n_s delta^2(pair, p)
//   sum^2   = sum over all point pairs k(r)^2
//   predicted(p) = calibration * sqrt(error^2 / sum^2)
// delta^2 is the mean square error of the order-p interpolation of k between
// the two boxes, estimated from one-dimensional interpolations (along each
// dimension, in the target and in the source box) at 16 point pairs of the
// sets per level and canonical offset (so that clustered points are sampled
// where they are); sum^2 from up to 256 x 4096 sampled point pairs. Both depend on the kernel,
// which is why one model serves 1/r, a multiquadric and a Gaussian alike.
//
// Calibration: the predictions were compared with the measured error (500
// sampled targets, charges uniform in [-1, 1]) for 1/r, multiquadrics (e = 1,
// 3) and a Gaussian (e = 3), uniform and Plummer points, N = 2e3 to 2e4, D =
// 1, 2, 3, orders 2 to 14 (/tmp calibration runs, the table bench_fast_sum
// prints is the same comparison). measured / uncalibrated prediction was 0.6
// to 4 for 1/r and the Gaussian (median ~1.8), so calibration = 2.5 puts
// nearly all of them at or below tol.
//
// Surprises:
// - cross-level pairs (M2P, P2L) interpolate only in the smaller box.
// - the model is right on average over charges, not for given charges: for
//   smooth kernels (multiquadrics) a sum is dominated by a few moments of the
//   charges (their total, their dipole), and charges whose moments nearly
//   cancel give a much smaller sum, so a larger relative error (measured up
//   to 20x the prediction for a multiquadric on a Plummer sphere); charges of
//   one sign give a larger sum and a smaller relative error. The sample
//   check (accuracy.hpp) measures the realised error.
// - the field (the vector kernel) uses the potential's prediction.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "partc/fast_sum/chebyshev.hpp"
#include "partc/fast_sum/fmm_tree.hpp"
#include "partc/fast_sum/interactions.hpp"
#include "partc/fast_sum/m2l_operators.hpp"

namespace partc::fast_sum {

constexpr double error_model_calibration = 2.5;

// Orders the model considers: p^D nodes must stay affordable (an M2L operator
// is p^(2D) doubles, 16 of them per level in 3D).
constexpr int max_order(int dims) { return dims == 1 ? 40 : dims == 2 ? 24 : 12; }

namespace detail {

// A fixed sequence of numbers in [-1, 1] (a 64-bit LCG), so plans are reproducible.
class Jitter {
 public:
  double next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state_ >> 11) * 0x1p-52 - 1.0;
  }

 private:
  std::uint64_t state_ = 0x853c49e6748fea9bULL;
};

// A box along which a sample pair's point is interpolated: centre and half side.
template <int D>
struct Span {
  double centre[D];
  double half;
};

// The squared interpolation error, for each order, of the kernel between the
// points x and y, where x is interpolated over the box `at_target` (if any)
// and y over `at_source` (if any): one-dimensional interpolations, along each
// dimension of each box, their squared errors summed. With field, the error
// of the vector kernel k(r) (y - x), summed over components.
template <int D, class Kernel>
std::vector<double> sample_error(const Kernel& kernel, const double* x, const double* y,
                                 const Span<D>* at_target, const Span<D>* at_source,
                                 const std::vector<ChebyshevBasis>& bases, bool field) {
  auto value = [&](const double* a, const double* b, double* out) {
    double r2 = 0, dx[D];
    for (int d = 0; d < D; ++d) {
      dx[d] = b[d] - a[d];
      r2 += dx[d] * dx[d];
    }
    const double k = kernel(std::sqrt(r2));
    if (!field) out[0] = k;
    for (int d = 0; field && d < D; ++d) out[d] = k * dx[d];
  };
  const int components = field ? D : 1;
  double exact[D], at_node[D];
  value(x, y, exact);
  std::vector<double> error(bases.size(), 0.0);
  for (std::size_t b = 0; b < bases.size(); ++b) {
    const ChebyshevBasis& basis = bases[b];
    const int p = basis.order();
    std::vector<double> w(static_cast<std::size_t>(p));
    for (int side = 0; side < 2; ++side) {
      const Span<D>* span = side == 0 ? at_target : at_source;
      if (!span) continue;
      for (int d = 0; d < D; ++d) {
        double a[D], c[D];
        std::copy(x, x + D, a);
        std::copy(y, y + D, c);
        double* moved = side == 0 ? a : c;
        basis.weights(std::clamp((moved[d] - span->centre[d]) / span->half, -1.0, 1.0), w.data());
        double interpolated[D] = {};
        for (int m = 0; m < p; ++m) {
          moved[d] = span->centre[d] + span->half * basis.node(m);
          value(a, c, at_node);
          for (int i = 0; i < components; ++i)
            interpolated[i] += w[static_cast<std::size_t>(m)] * at_node[i];
        }
        for (int i = 0; i < components; ++i)
          error[b] += (interpolated[i] - exact[i]) * (interpolated[i] - exact[i]);
      }
    }
  }
  return error;
}

}  // namespace detail

// predicted[p] for p = 0 .. max_order(D) (entries below 2 are unused), of
// the potential or (field) of the field.
template <int D, class Kernel>
std::vector<double> predict_errors(const Kernel& kernel, const Tree<D>& targets,
                                   const Tree<D>& sources, const Interactions& interactions,
                                   bool field) {
  std::vector<ChebyshevBasis> bases;
  for (int p = 2; p <= max_order(D); ++p) bases.emplace_back(p);
  std::vector<double> error(bases.size(), 0.0);
  detail::Jitter jitter;
  auto span = [](const Tree<D>& tree, const TreeBox<D>& box) {
    detail::Span<D> s;
    for (int d = 0; d < D; ++d) s.centre[d] = tree.centre(box, d);
    s.half = tree.box_side(box.level) / 2;
    return s;
  };
  auto point = [&](const Tree<D>& tree, const TreeBox<D>& box, double* x) {
    const std::size_t k =
        box.first +
        std::min(box.count - 1, std::size_t((jitter.next() + 1) / 2 * double(box.count)));
    for (std::size_t d = 0; d < D; ++d) x[d] = tree.coords[d][k];
  };
  // A kind of far pair (pairs of boxes, and which side is interpolated) adds
  // its total point pairs times the mean square error of up to 16 sample
  // point pairs, drawn from evenly spaced box pairs weighted by their points.
  struct FarPair {
    int target, source;
    bool target_side, source_side;
  };
  auto add = [&](const std::vector<FarPair>& pairs) {
    if (pairs.empty()) return;
    constexpr std::size_t samples = 16;
    std::vector<double> mean(bases.size(), 0.0);
    double total = 0, sampled = 0;
    for (const FarPair& fp : pairs)
      total += double(targets.boxes[static_cast<std::size_t>(fp.target)].count) *
               double(sources.boxes[static_cast<std::size_t>(fp.source)].count);
    const std::size_t stride = std::max<std::size_t>(1, pairs.size() / samples);
    for (std::size_t i = 0; i < pairs.size(); i += stride) {
      const FarPair& fp = pairs[i];
      const TreeBox<D>& tb = targets.boxes[static_cast<std::size_t>(fp.target)];
      const TreeBox<D>& sb = sources.boxes[static_cast<std::size_t>(fp.source)];
      const double weight = double(tb.count) * double(sb.count);
      double x[D], y[D];
      point(targets, tb, x);
      point(sources, sb, y);
      const auto ts = span(targets, tb), ss = span(sources, sb);
      const auto e = detail::sample_error<D>(kernel, x, y, fp.target_side ? &ts : nullptr,
                                             fp.source_side ? &ss : nullptr, bases, field);
      for (std::size_t b = 0; b < bases.size(); ++b) mean[b] += weight * e[b];
      sampled += weight;
    }
    for (std::size_t b = 0; b < bases.size(); ++b) error[b] += total * mean[b] / sampled;
  };
  for (const M2lGroup& group : interactions.m2l) {
    std::vector<FarPair> pairs;
    for (const M2lPair& pair : group.pairs) pairs.push_back({pair.target, pair.source, true, true});
    add(pairs);
  }
  std::vector<FarPair> m2p, p2l;
  for (std::size_t t = 0; t < targets.boxes.size(); ++t) {
    for (int s : interactions.m2p[t]) m2p.push_back({int(t), s, false, true});
    for (int s : interactions.p2l[t]) p2l.push_back({int(t), s, true, false});
  }
  add(m2p);
  add(p2l);

  // sum^2 from a strided sample of target and source points.
  const std::size_t nt = targets.index.size(), ns = sources.index.size();
  const std::size_t st = std::max<std::size_t>(1, nt / 256),
                    ss = std::max<std::size_t>(1, ns / 4096);
  double sampled = 0, count = 0;
  for (std::size_t i = 0; i < nt; i += st)
    for (std::size_t j = 0; j < ns; j += ss) {
      double r2 = 0;
      for (std::size_t d = 0; d < D; ++d) {
        const double dx = sources.coords[d][j] - targets.coords[d][i];
        r2 += dx * dx;
      }
      const double k = kernel(std::sqrt(r2));
      sampled += field ? k * k * r2 : k * k;
      count += 1;
    }
  const double sum2 = count > 0 ? sampled / count * double(nt) * double(ns) : 0;

  std::vector<double> predicted(static_cast<std::size_t>(max_order(D) + 1), 0.0);
  for (std::size_t b = 0; b < bases.size(); ++b)
    predicted[static_cast<std::size_t>(bases[b].order())] =
        sum2 > 0 ? error_model_calibration * std::sqrt(error[b] / sum2) : 0.0;
  return predicted;
}

}  // namespace partc::fast_sum
