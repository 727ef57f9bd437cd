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
// the two boxes, estimated at sampled point pairs of the sets (so that
// clustered points are sampled where they are): at each, the signed errors
// of one-dimensional interpolations (along each dimension, in the target and
// in the source box) summed, the first-order error of the tensor
// interpolation. sum^2 from up to 256 x 4096 sampled point pairs. Both
// depend on the kernel, which is why one model serves 1/r, a multiquadric
// and a Gaussian alike.
//
// Sampling: delta^2 is heavy-tailed, more so with the order (the closest
// point pairs of a box pair dominate), and 16 samples per level and offset
// gave predictions that jumped 5x from one order to the next (1/r, N = 1e4,
// orders 9 to 12: measured / predicted 0.25 to 2.3, so tol 1e-9 measured
// 1.08e-9). Now each kind of far pair gets a pilot of 16 samples, then a
// budget of 384 p more (p the order being planned, as the tail grows with
// it) is shared among the kinds by their part of the error (Neyman
// allocation): 40 to 130 ms a prediction (16 samples: 15 to 100 ms) at N =
// 1e4 to 1e5 on one loaded core, two to four predictions a plan.
//
// Calibration: measured against predicted (error_model_calibration = 1)
// for 1/r, multiquadrics (e = 1, 3) and a Gaussian (e = 3), uniform and
// Plummer points in 3D, orders 2 to 12 at N = 1e4 and 2 to 9 at 1e5 (1/r),
// the relative error pooled over three or four draws of charges in [-1, 1]:
// 0.5 to 1.1 at N = 1e4, up to 1.95 at 1e5 (1/r on a Plummer sphere), with
// no kernel family apart (so one constant, not one per family). Much of the
// spread is the draw's sum, not the error: far fields have few degrees of
// freedom, so a draw's sum^2 is typically 0.3 to 0.9 of its expected value
// (divided by that instead: 0.5 to 1.1, median 0.78, at N = 1e4; 0.7 to 1.2
// at 1e5). 2.5 puts every pooled measurement at or below 0.78 of the
// prediction. The M2L compression's error (low_rank.hpp) did not show:
// without it the measured error changed by 1 to 4%.
//
// Surprises:
// - cross-level pairs (M2P, P2L) interpolate only in the smaller box.
// - the model is right on average over charges, not for given charges: for
//   smooth kernels (multiquadrics) a sum is dominated by a few moments of the
//   charges (their total, their dipole), and charges whose moments nearly
//   cancel give a much smaller sum, so a larger relative error (measured up
//   to 20x the prediction for a multiquadric on a Plummer sphere); charges of
//   one sign give a larger sum and a smaller relative error. Even iid
//   charges in [-1, 1] do it: at N = 1e5, bench_fast_sum's draw has a total
//   0.22 of its standard deviation, and its multiquadric sums are 0.02 of
//   their expected square, so the measured error is 2 to 4x the prediction
//   (six other draws: sums 0.2 to 2.7 of their expected square, the error
//   itself as predicted). A plan given its charges measures how far they
//   cancel and scales the prediction by it (cancellation.hpp); the sample
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

// Adds weight times the squared interpolation error, for each order, of the
// kernel between the points x and y to error[b] (bases[b]'s order), where x
// is interpolated over the box `at_target` (if any) and y over `at_source`
// (if any): one-dimensional interpolations, along each dimension of each
// box, their signed errors summed. With field, the error of the vector
// kernel k(r) (y - x), squared and summed over components.
template <int D, class Kernel>
void add_sample_error(const Kernel& kernel, const double* x, const double* y,
                      const Span<D>* at_target, const Span<D>* at_source,
                      const std::vector<ChebyshevBasis>& bases, bool field, double weight,
                      double* error) {
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
  double exact[D], at_node[D], w[max_order(1)];
  value(x, y, exact);
  for (std::size_t b = 0; b < bases.size(); ++b) {
    const ChebyshevBasis& basis = bases[b];
    const int p = basis.order();
    double signed_error[D] = {};
    for (int side = 0; side < 2; ++side) {
      const Span<D>* span = side == 0 ? at_target : at_source;
      if (!span) continue;
      for (int d = 0; d < D; ++d) {
        double a[D], c[D];
        std::copy(x, x + D, a);
        std::copy(y, y + D, c);
        double* moved = side == 0 ? a : c;
        basis.weights(std::clamp((moved[d] - span->centre[d]) / span->half, -1.0, 1.0), w);
        double interpolated[D] = {};
        for (int m = 0; m < p; ++m) {
          moved[d] = span->centre[d] + span->half * basis.node(m);
          value(a, c, at_node);
          for (int i = 0; i < components; ++i) interpolated[i] += w[m] * at_node[i];
        }
        for (int i = 0; i < components; ++i) signed_error[i] += interpolated[i] - exact[i];
      }
    }
    double sum = 0;
    for (int i = 0; i < components; ++i) sum += signed_error[i] * signed_error[i];
    error[b] += weight * sum;
  }
}

}  // namespace detail

// predicted[p] for p = 0 .. max_order(D) (entries below 2 are unused), of
// the potential or (field) of the field; sharpest near planned_order.
template <int D, class Kernel>
std::vector<double> predict_errors(const Kernel& kernel, const Tree<D>& targets,
                                   const Tree<D>& sources, const Interactions& interactions,
                                   bool field, int planned_order) {
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
  // A kind of far pair (M2L at one level and canonical offset, M2P or P2L)
  // adds its total point pairs times the mean square error of its sample
  // point pairs, drawn from its box pairs (golden-ratio strided) and weighted
  // by their points: a pilot of 16, then the budget (see the head comment)
  // shared by each kind's largest part, over the orders, of the error.
  struct FarPair {
    int target, source;
    bool target_side, source_side;
  };
  struct Kind {
    const M2lGroup* group = nullptr;  // M2L pairs are read where they are, not copied
    std::vector<FarPair> pairs;       // else these
    double total = 0, weights = 0;
    std::vector<double> sum;  // weighted squared errors, by order
    std::size_t drawn = 0;
    std::size_t size() const { return group ? group->pairs.size() : pairs.size(); }
    FarPair at(std::size_t i) const {
      if (!group) return pairs[i];
      return {group->pairs[i].target, group->pairs[i].source, true, true};
    }
  };
  std::vector<Kind> kinds;
  auto draw = [&](Kind& kind, std::size_t count) {
    for (std::size_t end = kind.drawn + count; kind.drawn < end; ++kind.drawn) {
      const double position = std::fmod(double(kind.drawn) * 0.6180339887498949, 1.0);
      const FarPair fp =
          kind.at(std::min(kind.size() - 1, std::size_t(position * double(kind.size()))));
      const TreeBox<D>& tb = targets.boxes[static_cast<std::size_t>(fp.target)];
      const TreeBox<D>& sb = sources.boxes[static_cast<std::size_t>(fp.source)];
      const double weight = double(tb.count) * double(sb.count);
      double x[D], y[D];
      point(targets, tb, x);
      point(sources, sb, y);
      const auto ts = span(targets, tb), ss = span(sources, sb);
      detail::add_sample_error<D>(kernel, x, y, fp.target_side ? &ts : nullptr,
                                  fp.source_side ? &ss : nullptr, bases, field, weight,
                                  kind.sum.data());
      kind.weights += weight;
    }
  };
  auto add = [&](Kind kind) {
    if (kind.size() == 0) return;
    for (std::size_t i = 0; i < kind.size(); ++i) {
      const FarPair fp = kind.at(i);
      kind.total += double(targets.boxes[static_cast<std::size_t>(fp.target)].count) *
                    double(sources.boxes[static_cast<std::size_t>(fp.source)].count);
    }
    kind.sum.assign(bases.size(), 0.0);
    kinds.push_back(std::move(kind));
  };
  for (const M2lGroup& group : interactions.m2l) {
    Kind kind;
    kind.group = &group;
    add(std::move(kind));
  }
  Kind m2p, p2l;
  for (std::size_t t = 0; t < targets.boxes.size(); ++t) {
    for (int s : interactions.m2p[t]) m2p.pairs.push_back({int(t), s, false, true});
    for (int s : interactions.p2l[t]) p2l.pairs.push_back({int(t), s, true, false});
  }
  add(std::move(m2p));
  add(std::move(p2l));
  auto contribution = [&](const Kind& kind, std::size_t b) {
    return kind.weights > 0 ? kind.total * kind.sum[b] / kind.weights : 0.0;
  };
  for (Kind& kind : kinds) draw(kind, 16);
  // A kind's share: the largest, over the orders, of its part of the error.
  std::vector<double> share(kinds.size(), 0.0);
  double shares = 0;
  for (std::size_t b = 0; b < bases.size(); ++b) {
    double all = 0;
    for (const Kind& kind : kinds) all += contribution(kind, b);
    for (std::size_t k = 0; all > 0 && k < kinds.size(); ++k)
      share[k] = std::max(share[k], contribution(kinds[k], b) / all);
  }
  for (double s : share) shares += s;
  const double budget = 384.0 * planned_order;
  for (std::size_t k = 0; shares > 0 && k < kinds.size(); ++k)
    draw(kinds[k], std::size_t(std::lround(budget * share[k] / shares)));
  for (const Kind& kind : kinds)
    for (std::size_t b = 0; b < bases.size(); ++b) error[b] += contribution(kind, b);

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
