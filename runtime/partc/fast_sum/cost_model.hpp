// partc/fast_sum/cost_model.hpp: what the fast sum's work costs, for the
// choices that trade one kind of work for another: the points per leaf, and
// whether two separated boxes are summed directly or through M2L.
//
// Times measured on one core of the development machine (an AVX-512 Xeon;
// tests/bench/bench_fast_sum.cpp, -O3 -march=native -fno-math-errno): a
// vectorised 1/r pair (exact sqrt and division) 1.8 ns, multiply_panel (the
// M2L product) 28 GFlop/s. Only their ratio matters.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace partc::fast_sum {

constexpr double pair_ns = 1.8, flop_ns = 1 / 28.0;

// Points per leaf at order p: a leaf's near field (3^D neighbours, s^2 pairs
// each) against its M2L ((6^D - 3^D) products of 2 p^(2D) flops) balance at
// s = p^D sqrt(2 (6^D - 3^D) flop_ns / (3^D pair_ns)); but at least 48, since
// below that the plan's traversal (~1 us a box pair) outweighs both.
inline std::size_t leaf_size_for_order(int dims, int p) {
  const double nodes = std::pow(double(p), dims);
  const double near_boxes = std::pow(3.0, dims), far_boxes = std::pow(6.0, dims) - near_boxes;
  return std::max<std::size_t>(
      48, std::size_t(nodes * std::sqrt(2 * far_boxes * flop_ns / (near_boxes * pair_ns))));
}

// Whether two separated same-level boxes are cheaper summed directly than
// through one M2L product of `nodes` x `nodes`.
inline bool direct_is_cheaper(std::size_t targets, std::size_t sources, std::size_t nodes) {
  return double(targets) * double(sources) * pair_ns < 2 * double(nodes) * double(nodes) * flop_ns;
}

}  // namespace partc::fast_sum
