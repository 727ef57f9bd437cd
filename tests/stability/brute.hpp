// Helpers for the stability cases: tests/e2e/reference.hpp's, for any
// dimension: a set's state as plain arrays in id order, and the periodic
// minimum image written out independently of the runtime's.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "reference.hpp"

namespace brute {

template <int D>
using Vec = std::array<double, D>;

// Shortest image of d along each periodic axis of length L.
template <int D>
Vec<D> minimum_image(Vec<D> d, double L) {
  for (double& x : d) x -= L * std::round(x / L);
  return d;
}

template <std::size_t D>
double norm(const std::array<double, D>& d) {
  double s = 0;
  for (double x : d) s += x * x;
  return std::sqrt(s);
}

using reference::by_id;  // tests/e2e/reference.hpp
using reference::values_by_id;

template <int D, class Set>
std::vector<Vec<D>> positions_by_id(const Set& set) {
  std::vector<Vec<D>> out;
  for (std::size_t i : by_id(set)) {
    Vec<D> p;
    for (int k = 0; k < D; ++k) p[k] = set.positions()[i][k];
    out.push_back(p);
  }
  return out;
}

template <int D, class V>
Vec<D> as_array(const V& v) {
  Vec<D> out;
  for (int k = 0; k < D; ++k) out[k] = v[k];
  return out;
}

}  // namespace brute
