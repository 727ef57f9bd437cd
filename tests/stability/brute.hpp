// Helpers for the stability cases: a set's state as plain arrays in id order,
// and the periodic minimum image written out independently of the runtime's.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

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

template <class Set>
std::vector<std::size_t> by_id(const Set& set) {
  std::vector<std::size_t> order(set.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return set.ids()[a] < set.ids()[b]; });
  return order;
}

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

template <class Var, class Set>
auto values_by_id(const Set& set) {
  std::vector<typename std::decay_t<decltype(set.template get<Var>())>::value_type> out;
  for (std::size_t i : by_id(set)) out.push_back(set.template get<Var>()[i]);
  return out;
}

template <int D, class V>
Vec<D> as_array(const V& v) {
  Vec<D> out;
  for (int k = 0; k < D; ++k) out[k] = v[k];
  return out;
}

}  // namespace brute
