// partc/fast_sum/cost_model.hpp: what the fast sum's work costs, for the
// choices that trade one kind of work for another: the points per leaf, and
// whether two separated boxes are summed directly or through M2L.
//
// Times measured on one core of the development machine (an AVX-512 Xeon;
// tests/bench/bench_fast_sum.cpp, -O3 -march=native -fno-math-errno): a
// vectorised 1/r pair (exact sqrt and division) 1.8 ns, multiply_panel (the
// M2L product) 28 GFlop/s; gathering and scattering one node of one M2L
// pair (its symmetry's permutation) ~1 ns, from a profile at order 9 (N =
// 1e5, 2 ns a pair there). Only their ratios matter.
//
// An M2L product is 2 n^2 flops for n = p^D nodes, or 4 n k once its
// operator is compressed to rank k (low_rank.hpp). The rank is set by the
// accuracy, which grows with the order: in 3D the mean rank over the
// canonical offsets is ~p^2 / 2 (measured for 1/r at p = 4 to 10, as the
// p^2 terms of a multipole expansion would suggest), in 2D ~p; the plan
// needs it before the operators exist, so it is this estimate.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace partc::fast_sum {

constexpr double pair_ns = 1.8, flop_ns = 1 / 28.0, gather_ns = 1.0;

// The estimated rank of a compressed operator with n = p^dims nodes.
inline double estimated_rank(int dims, std::size_t nodes) {
  const double p = std::pow(double(nodes), 1.0 / dims);
  return dims == 3 ? p * p / 2 : p;
}

// The estimated time of one M2L pair with n = p^dims nodes.
inline double m2l_pair_ns(int dims, std::size_t nodes) {
  const double n = double(nodes), rank = estimated_rank(dims, nodes);
  const double flops = 2 * rank < n ? 4 * n * rank : 2 * n * n;
  return flops * flop_ns + n * gather_ns;
}

// Whether compressing an operator pays back within one evaluation of
// `products` products with it (its pairs, times D + 1 for a field):
// compression costs about as much as 8 x 2 n^2 (k + 16) flops of
// multiply_panel (measured at order 9 in 3D), and saves 2 n^2 - 4 n k a
// product. A plan evaluated many times would gain from compressing more.
inline bool compression_pays(int dims, std::size_t nodes, std::size_t products) {
  const double n = double(nodes), rank = estimated_rank(dims, nodes);
  return 2 * rank < n &&
         double(products) * (2 * n * n - 4 * n * rank) > 8 * 2 * n * n * (rank + 16);
}

// Points per leaf at order p: a leaf's near field (3^D neighbours, s^2 pairs
// each) against its M2L ((6^D - 3^D) pairs) balance at
// s = sqrt((6^D - 3^D) m2l_pair_ns / (3^D pair_ns)); but at least 48, since
// below that the plan's traversal (~1 us a box pair) outweighs both.
inline std::size_t leaf_size_for_order(int dims, int p) {
  const double nodes = std::pow(double(p), dims);
  const double near_boxes = std::pow(3.0, dims), far_boxes = std::pow(6.0, dims) - near_boxes;
  return std::max<std::size_t>(
      48, std::size_t(std::sqrt(far_boxes * m2l_pair_ns(dims, std::size_t(nodes)) /
                                (near_boxes * pair_ns))));
}

// Whether two separated same-level boxes are cheaper summed directly than
// through one M2L pair.
inline bool direct_is_cheaper(int dims, std::size_t targets, std::size_t sources,
                              std::size_t nodes) {
  return double(targets) * double(sources) * pair_ns < m2l_pair_ns(dims, nodes);
}

}  // namespace partc::fast_sum
