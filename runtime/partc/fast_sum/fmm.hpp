// partc/fast_sum/fmm.hpp: dense radial sums out[i] = sum_j k(|x_j - x_i|) q[j]
// in O(N) by the black-box fast multipole method (Fong & Darve 2009):
// expansions are values at Chebyshev nodes (chebyshev.hpp), so any smooth
// radial kernel works, given only as a function of r.
//
//   partc::fast_sum::Fmm<3, Kernel> fmm(sources, targets, kernel, {1e-6});
//   fmm.potential(q.data(), phi.data());  // as often as wanted, for new charges
//   fmm.field(q.data(), e.data());        // sum_j k(r) (x_j - x_i) q[j]
//   Fmm<3, Kernel> for_q(sources, targets, kernel, {1e-6}, q.data());  // planned for q
//
// The plan (the constructor) builds a tree over the sources and one over the
// targets (fmm_tree.hpp), finds how their boxes interact
// (interactions.hpp), picks the order from the error model
// (error_model.hpp) unless one is given, and computes the M2L operators
// (m2l_operators.hpp). An evaluation is then: P2M at source leaves, M2M up
// the source tree, M2L (batched: one matrix product per level and canonical
// offset) and P2L into target boxes, L2L down the target tree, and at target
// leaves L2P, the direct near field (P2P) and M2P.
//
// The field needs no derivative of k: with nodes x_m = c_t + a_m of the
// target box and y_n = c_s + b_n of the source box,
//   sum_n k(|y_n - x_m|) (y_n - x_m)_d W_n
//     = [G (b_d W)]_m + ((c_s - c_t)_d - a_md) [G W]_m,  G_mn = k(|y_n - x_m|),
// so one field M2L is D + 1 products with the potential's operator.
//
// M2L operators are compressed (low_rank.hpp) to the rank that keeps their
// error below compression_share of the interpolation's, so a product costs
// 4 p^D k flops instead of 2 p^(2D), k ~ p^2 / 2 in 3D; the prediction the
// plan reports and meets is the interpolation's times 1 + compression_share.
//
// Charges known when planning: the model predicts the error relative to
// the result's size on average over charges, and charges that cancel (their
// total near 0, under a smooth kernel) give a smaller result and a larger
// relative error; given the charges, the plan measures how far they cancel
// (cancellation.hpp, a direct sum at 128 targets) and multiplies its
// predictions by that over the typical cancellation the model's calibration
// already allows for, so the order meets tol for them. A plan evaluated for
// charges it is not given (a solve's products) is planned without them.
//
// Order and leaf size: the cheapest order whose predicted error is <= tol
// (leaf_size_for_order, cost_model.hpp, balances the near field against M2L); the tree
// depends on the leaf size and the prediction on the tree, so the choice is
// repeated (at most three times) until it settles.
//
// Surprises:
// - results are bitwise the same for any number of threads: every box and
//   point accumulates its contributions in one fixed order.
// - a plan given charges predicts for those charges: others that cancel
//   more have a larger error than predicted, as with a plan given none.
// - the order is chosen for the sum the plan serves (Accuracy::field): a
//   plan for potentials can give fields too, at the potential's order, and
//   their error is then not what tol asked.
// - the kernel is called with r = 0 only for coincident pairs in the near field.
// - memory: an operator is 2 p^D k doubles compressed, p^(2D) where
//   compression does not pay (at order 10 in 3D, ~0.8 MB compressed, 8 MB
//   not; up to 16 per level).
// - planning at high order is mostly the compression (~0.3 s per level at
//   order 9 in 3D on one core).
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <vector>

#include "partc/fast_sum/cancellation.hpp"
#include "partc/fast_sum/chebyshev.hpp"
#include "partc/fast_sum/cost_model.hpp"
#include "partc/fast_sum/direct_sum.hpp"
#include "partc/fast_sum/error_model.hpp"
#include "partc/fast_sum/fmm_tree.hpp"
#include "partc/fast_sum/interactions.hpp"
#include "partc/fast_sum/low_rank.hpp"
#include "partc/fast_sum/m2l_operators.hpp"
#include "partc/parallel.hpp"
#include "partc/vec.hpp"

namespace partc::fast_sum {

struct Accuracy {
  double tol = 1e-6;   // requested relative L2 error of the sum over all targets
  int order = 0;       // Chebyshev nodes per dimension; 0: chosen from tol
  bool field = false;  // the plan serves field(), whose error tol bounds; else potential()
};

struct FmmStats {
  int order = 0;
  std::size_t leaf_size = 0;
  int source_levels = 0, target_levels = 0;
  std::size_t source_boxes = 0, target_boxes = 0;
  std::size_t m2l_pairs = 0, m2p_pairs = 0, p2l_pairs = 0;
  double near_point_pairs = 0;  // point pairs summed directly
  std::size_t operators = 0;    // M2L matrices stored
  double operator_bytes = 0;
  double cancellation = 1;  // cancellation.hpp's, for the charges planned for (1: none given)
  double plan_seconds = 0;
};

template <int D, class Kernel>
class Fmm {
  static_assert(D >= 1 && D <= 3, "fast sums are for 1 to 3 dimensions");

 public:
  // charges: those the plan is for (indexed like sources), if known; then
  // the predictions are for them (see the head comment).
  template <class T>
  Fmm(const std::vector<Vec<D, T>>& sources, const std::vector<Vec<D, T>>& targets, Kernel kernel,
      Accuracy accuracy, const double* charges = nullptr)
      : kernel_(std::move(kernel)), basis_(2), symmetries_(basis_) {
    const auto start = std::chrono::steady_clock::now();
    if (charges)
      stats_.cancellation =
          measure_cancellation(sources, targets, kernel_, charges, accuracy.field);
    if (charges) cancellation_factor_ = stats_.cancellation / typical_cancellation;
    const Cube<D> cube = bounding_cube(sources, targets);
    auto plan = [&](int p) {
      order_ = p;
      basis_ = ChebyshevBasis(p);
      symmetries_ = Symmetries<D>(basis_);
      const std::size_t leaf = leaf_size_for_order(D, p);
      if (leaf != stats_.leaf_size || source_tree_.boxes.empty()) {
        source_tree_ = build_tree(sources, cube, leaf);
        target_tree_ = build_tree(targets, cube, leaf);
      }
      stats_.leaf_size = leaf;
      interactions_ = find_interactions(target_tree_, source_tree_, symmetries_, nodes());
      predicted_ =
          predict_errors<D>(kernel_, target_tree_, source_tree_, interactions_, accuracy.field, p);
      for (double& e : predicted_) e *= (1 + compression_share) * cancellation_factor_;
    };
    auto cheapest = [&] {
      for (int p = 2; p < max_order(D); ++p)
        if (predicted_error(p) <= accuracy.tol) return p;
      return max_order(D);
    };
    if (accuracy.order > 0) {
      plan(std::min(accuracy.order, max_order(D)));
    } else {
      plan(std::clamp(int(std::ceil(-std::log10(accuracy.tol))), 2, max_order(D)));
      for (int round = 0; round < 3 && cheapest() != order_; ++round) plan(cheapest());
      // Settle upwards on the last tree, so that the prediction meets tol.
      while (order_ < max_order(D) && predicted_error() > accuracy.tol) plan(order_ + 1);
    }
    build_operators(accuracy.field);
    stats_.order = order_;
    stats_.source_levels = source_tree_.levels();
    stats_.target_levels = target_tree_.levels();
    stats_.source_boxes = source_tree_.boxes.size();
    stats_.target_boxes = target_tree_.boxes.size();
    stats_.m2l_pairs = interactions_.m2l_pairs;
    stats_.m2p_pairs = interactions_.m2p_pairs;
    stats_.p2l_pairs = interactions_.p2l_pairs;
    stats_.near_point_pairs = interactions_.near_point_pairs;
    stats_.operators = operators_.size();
    for (std::size_t g = 0; g < operators_.size(); ++g)
      stats_.operator_bytes +=
          double(operators_[g].size() + compressed_[g].left.size() + compressed_[g].right.size()) *
          sizeof(double);
    stats_.plan_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // out[i] = sum_j kernel(|x_j - x_i|) q[j] (q indexed like sources, out like targets).
  void potential(const double* q, double* out) const { evaluate<false>(q, out); }

  // out[i] = sum_j kernel(|x_j - x_i|) (x_j - x_i) q[j].
  void field(const double* q, Vec<D>* out) const {
    std::vector<double> flat(target_tree_.index.size() * D);
    evaluate<true>(q, flat.data());
    for (std::size_t i = 0; i < target_tree_.index.size(); ++i)
      for (int d = 0; d < D; ++d) out[i][d] = flat[i * D + std::size_t(d)];
  }

  int order() const { return order_; }
  // The model's prediction (error_model.hpp) of the error of the sum the plan
  // serves (Accuracy::field): the potential's, or the field's.
  double predicted_error() const { return predicted_error(order_); }
  // The same at another order, on this plan's trees; -1 outside 2 ... max_order.
  double predicted_error(int p) const {
    return p >= 2 && p <= max_order(D) ? predicted_[static_cast<std::size_t>(p)] : -1.0;
  }
  const FmmStats& stats() const { return stats_; }

 private:
  int nodes() const {
    int n = 1;
    for (int d = 0; d < D; ++d) n *= order_;
    return n;
  }
  // Node m's coordinate along d, relative to its box centre, in half box sides.
  double node_coordinate(int m, int d) const {
    return node_coordinates_[std::size_t(m) * D + std::size_t(d)];
  }

  // Each group's operator, compressed (low_rank.hpp) where that pays within
  // one evaluation (cost_model.hpp): its dropped singular values, relative to
  // the largest, are below compression_share of the interpolation's
  // predicted error for charges not known: the operators' own, which the
  // charges' cancellation magnifies alike.
  void build_operators(bool field) {
    operators_.assign(interactions_.m2l.size(), {});
    compressed_.assign(interactions_.m2l.size(), {});
    const double eps =
        compression_share / (1 + compression_share) * predicted_error() / cancellation_factor_;
    parallel_for(operators_.size(), LoopWork::blocks, [&](std::size_t g) {
      const M2lGroup& group = interactions_.m2l[g];
      operators_[g] =
          m2l_matrix<D>(kernel_, basis_, target_tree_.box_side(group.level), group.code);
      const std::size_t products = group.pairs.size() * (field ? D + 1 : 1);
      if (eps > 0 && compression_pays(D, std::size_t(nodes()), products))
        compressed_[g] = compress(operators_[g], nodes(), eps);
      if (compressed_[g].rank > 0) operators_[g] = {};
    });
    node_coordinates_.resize(std::size_t(nodes()) * D);
    for (int m = 0; m < nodes(); ++m)
      for (int d = 0, rest = m; d < D; ++d, rest /= order_)
        node_coordinates_[std::size_t(m) * D + std::size_t(d)] = basis_.node(rest % order_);
    transfer_[0] = basis_.child_transfer(0);
    transfer_[1] = basis_.child_transfer(1);
  }

  // The source box's or target box's coordinates of a point, in [-1, 1].
  void box_coordinates(const Tree<D>& tree, const TreeBox<D>& box, std::size_t k, double* t) const {
    const double half = tree.box_side(box.level) / 2;
    for (int d = 0; d < D; ++d)
      t[d] = std::clamp((tree.coords[static_cast<std::size_t>(d)][k] - tree.centre(box, d)) / half,
                        -1.0, 1.0);
  }

  // result[C i + c], i in the caller's target order: the potential (C = 1) or the field (C = D).
  template <bool Field>
  void evaluate(const double* q, double* result) const {
    constexpr int C = Field ? D : 1;
    const std::size_t n_targets = target_tree_.index.size(), n_sources = source_tree_.index.size();
    std::fill(result, result + n_targets * C, 0.0);
    if (n_targets == 0 || n_sources == 0) return;
    const int p = order_;
    const std::size_t n = std::size_t(nodes());
    const Tree<D>& st = source_tree_;
    const Tree<D>& tt = target_tree_;

    std::vector<double> charge(n_sources);
    for (std::size_t k = 0; k < n_sources; ++k) charge[k] = q[st.index[k]];
    std::array<const double*, D> source_coords;
    for (std::size_t d = 0; d < D; ++d) source_coords[d] = st.coords[d].data();

    // Upward: P2M at the source leaves, then M2M level by level.
    std::vector<double> multipole(st.boxes.size() * n, 0.0);
    parallel_for(st.leaves.size(), LoopWork::blocks, [&](std::size_t l) {
      const TreeBox<D>& box = st.boxes[static_cast<std::size_t>(st.leaves[l])];
      std::vector<double> s(n), scratch(static_cast<std::size_t>(p));
      double* w = multipole.data() + std::size_t(st.leaves[l]) * n;
      for (std::size_t k = box.first; k < box.first + box.count; ++k) {
        double t[D];
        box_coordinates(st, box, k, t);
        tensor_weights<D>(basis_, t, s.data(), scratch.data());
        for (std::size_t m = 0; m < n; ++m) w[m] += s[m] * charge[k];
      }
    });
    for (int level = st.levels() - 2; level >= 0; --level) {
      const std::size_t begin = st.level_begin[static_cast<std::size_t>(level)];
      parallel_for(st.level_begin[static_cast<std::size_t>(level) + 1] - begin, LoopWork::blocks,
                   [&](std::size_t i) {
                     const TreeBox<D>& box = st.boxes[begin + i];
                     std::vector<double> a(n), b(n);
                     for (int c = box.first_child; c < box.first_child + box.children; ++c) {
                       const double* mats[D];
                       for (std::size_t d = 0; d < D; ++d)
                         mats[d] = transfer_[st.boxes[std::size_t(c)].cell[d] & 1].data();
                       tensor_apply_add<D>(p, mats, false, multipole.data() + std::size_t(c) * n,
                                           multipole.data() + (begin + i) * n, a.data(), b.data());
                     }
                   });
    }

    // Far field into the target boxes' local expansions: M2L, then P2L.
    std::vector<double> local(tt.boxes.size() * C * n, 0.0);
    std::vector<double> panels_in, panels_out;
    for (std::size_t g = 0; g < interactions_.m2l.size(); ++g)
      apply_m2l<Field>(g, multipole, local, panels_in, panels_out);
    parallel_for(tt.boxes.size(), LoopWork::blocks, [&](std::size_t t) {
      const auto& list = interactions_.p2l[t];
      if (list.empty()) return;
      const TreeBox<D>& box = tt.boxes[t];
      const double half = tt.box_side(box.level) / 2;
      for (std::size_t m = 0; m < n; ++m) {
        double x[D];
        for (int d = 0; d < D; ++d) x[d] = tt.centre(box, d) + half * node_coordinate(int(m), d);
        double sum[C] = {};
        for (int s : list) {
          const TreeBox<D>& source = st.boxes[static_cast<std::size_t>(s)];
          accumulate<Field>(x, shifted(source_coords, source.first), charge.data() + source.first,
                            source.count, sum);
        }
        for (int c = 0; c < C; ++c) local[(t * C + std::size_t(c)) * n + m] += sum[c];
      }
    });

    // Downward: L2L level by level, each child from its parent.
    for (int level = 1; level < tt.levels(); ++level) {
      const std::size_t begin = tt.level_begin[static_cast<std::size_t>(level)];
      parallel_for(
          tt.level_begin[static_cast<std::size_t>(level) + 1] - begin, LoopWork::blocks,
          [&](std::size_t i) {
            const TreeBox<D>& box = tt.boxes[begin + i];
            std::vector<double> a(n), b(n);
            const double* mats[D];
            for (std::size_t d = 0; d < D; ++d) mats[d] = transfer_[box.cell[d] & 1].data();
            for (int c = 0; c < C; ++c)
              tensor_apply_add<D>(
                  p, mats, true, local.data() + (std::size_t(box.parent) * C + std::size_t(c)) * n,
                  local.data() + ((begin + i) * C + std::size_t(c)) * n, a.data(), b.data());
          });
    }

    // At the target leaves: L2P, then the near field, then M2P.
    parallel_for(tt.leaves.size(), LoopWork::blocks, [&](std::size_t l) {
      const std::size_t t = static_cast<std::size_t>(tt.leaves[l]);
      const TreeBox<D>& box = tt.boxes[t];
      std::vector<double> sum(box.count * C, 0.0), s(n), scratch(static_cast<std::size_t>(p));
      for (std::size_t k = 0; k < box.count; ++k) {
        double u[D];
        box_coordinates(tt, box, box.first + k, u);
        tensor_weights<D>(basis_, u, s.data(), scratch.data());
        for (int c = 0; c < C; ++c) {
          const double* expansion = local.data() + (t * C + std::size_t(c)) * n;
          double value = 0;
          for (std::size_t m = 0; m < n; ++m) value += s[m] * expansion[m];
          sum[k * C + std::size_t(c)] = value;
        }
      }
      auto at_points = [&](const std::array<const double*, D>& y, const double* weight,
                           std::size_t count) {
        for (std::size_t k = 0; k < box.count; ++k) {
          double x[D];
          for (std::size_t d = 0; d < D; ++d) x[d] = tt.coords[d][box.first + k];
          accumulate<Field>(x, y, weight, count, sum.data() + k * C);
        }
      };
      for (const PointRange& r : interactions_.near[t])
        at_points(shifted(source_coords, r.first), charge.data() + r.first, r.count);
      std::array<std::vector<double>, D> proxy;
      for (auto& c : proxy) c.resize(n);
      for (int s_id : interactions_.m2p[t]) {
        const TreeBox<D>& source = st.boxes[static_cast<std::size_t>(s_id)];
        const double half = st.box_side(source.level) / 2;
        std::array<const double*, D> y;
        for (std::size_t d = 0; d < D; ++d) {
          for (std::size_t m = 0; m < n; ++m)
            proxy[d][m] = st.centre(source, int(d)) + half * node_coordinate(int(m), int(d));
          y[d] = proxy[d].data();
        }
        at_points(y, multipole.data() + std::size_t(s_id) * n, n);
      }
      for (std::size_t k = 0; k < box.count; ++k)
        for (int c = 0; c < C; ++c)
          result[tt.index[box.first + k] * C + std::size_t(c)] = sum[k * C + std::size_t(c)];
    });
  }

  static std::array<const double*, D> shifted(std::array<const double*, D> y, std::size_t first) {
    for (auto& c : y) c += first;
    return y;
  }

  template <bool Field>
  void accumulate(const double* x, const std::array<const double*, D>& y, const double* q,
                  std::size_t count, double* sum) const {
    if constexpr (!Field)
      sum[0] += direct_potential<D>(kernel_, x, y, q, count);
    else
      direct_field<D>(kernel_, x, y, q, count, sum);
  }

  // One M2L group: gather the (permuted) multipoles of its pairs as the
  // columns of panels, multiply them by the group's operator, and add the
  // (permuted back) products to the targets' locals, pair by pair in order.
  // A potential takes one column per pair, a field D + 1 (W, then b_d W).
  // x and z: the panels, kept by the caller from group to group.
  template <bool Field>
  void apply_m2l(std::size_t g, const std::vector<double>& multipole, std::vector<double>& local,
                 std::vector<double>& x, std::vector<double>& z) const {
    constexpr std::size_t C = Field ? D : 1;
    const M2lGroup& group = interactions_.m2l[g];
    const LowRank& low = compressed_[g];
    const std::size_t n = std::size_t(nodes());
    constexpr std::size_t columns = Field ? D + 1 : 1;
    const std::size_t chunk_pairs =
        std::max<std::size_t>(1, (1024 / columns / panel_width) * panel_width);
    const double h = target_tree_.box_side(group.level);
    for (std::size_t first = 0; first < group.pairs.size(); first += chunk_pairs) {
      const std::size_t pairs = std::min(chunk_pairs, group.pairs.size() - first);
      const std::size_t panels = (pairs * columns + panel_width - 1) / panel_width;
      x.assign(panels * n * panel_width, 0.0);
      z.resize(x.size());
      auto entry = [&](std::vector<double>& v, std::size_t column, std::size_t node) -> double& {
        return v[(column / panel_width * n + node) * panel_width + column % panel_width];
      };
      parallel_for(pairs, LoopWork::blocks, [&](std::size_t j) {
        const M2lPair& pair = group.pairs[first + j];
        const std::vector<int>& pi = symmetries_.node_map(pair.symmetry);
        const double* w = multipole.data() + std::size_t(pair.source) * n;
        for (std::size_t m = 0; m < n; ++m) {
          const std::size_t image = std::size_t(pi[m]);
          entry(x, j * columns, image) = w[m];
          if constexpr (Field)
            for (int d = 0; d < D; ++d)
              entry(x, j * columns + 1 + std::size_t(d), image) =
                  h / 2 * node_coordinate(int(m), d) * w[m];
        }
      });
      parallel_for(panels, LoopWork::blocks, [&](std::size_t panel) {
        double* in = x.data() + panel * n * panel_width;
        double* out = z.data() + panel * n * panel_width;
        if (low.rank == 0) return multiply_panel(operators_[g].data(), int(n), int(n), in, out);
        std::vector<double> coefficients(std::size_t(low.rank) * panel_width);
        multiply_panel(low.right.data(), low.rank, int(n), in, coefficients.data());
        multiply_panel(low.left.data(), int(n), low.rank, coefficients.data(), out);
      });
      // Runs of pairs with one target, each run added in order by one thread.
      std::vector<std::size_t> runs{0};
      for (std::size_t j = 1; j < pairs; ++j)
        if (group.pairs[first + j].target != group.pairs[first + j - 1].target) runs.push_back(j);
      runs.push_back(pairs);
      parallel_for(runs.size() - 1, LoopWork::blocks, [&](std::size_t r) {
        for (std::size_t j = runs[r]; j < runs[r + 1]; ++j) {
          const M2lPair& pair = group.pairs[first + j];
          const std::vector<int>& pi = symmetries_.node_map(pair.symmetry);
          const TreeBox<D>& tb = target_tree_.boxes[static_cast<std::size_t>(pair.target)];
          const TreeBox<D>& sb = source_tree_.boxes[static_cast<std::size_t>(pair.source)];
          double* l = local.data() + std::size_t(pair.target) * C * n;
          for (std::size_t m = 0; m < n; ++m) {
            const std::size_t image = std::size_t(pi[m]);
            const double g0 = entry(z, j * columns, image);
            if constexpr (!Field) {
              l[m] += g0;
            } else {
              for (int d = 0; d < D; ++d) {
                const double offset =
                    h * double(sb.cell[std::size_t(d)] - tb.cell[std::size_t(d)]) -
                    h / 2 * node_coordinate(int(m), d);
                l[std::size_t(d) * n + m] +=
                    entry(z, j * columns + 1 + std::size_t(d), image) + offset * g0;
              }
            }
          }
        }
      });
    }
  }

  Kernel kernel_;
  int order_ = 0;
  ChebyshevBasis basis_;
  Symmetries<D> symmetries_;
  Tree<D> source_tree_, target_tree_;
  Interactions interactions_;
  std::vector<double> predicted_;                // by order
  double cancellation_factor_ = 1;               // cancellation / typical; 1 without charges
  std::vector<std::vector<double>> operators_;   // one per M2L group, empty if compressed
  std::vector<LowRank> compressed_;              // one per M2L group, rank 0 if not
  std::array<std::vector<double>, 2> transfer_;  // child_transfer(0), child_transfer(1)
  std::vector<double> node_coordinates_;         // node m's along d at m * D + d
  FmmStats stats_;
};

}  // namespace partc::fast_sum
