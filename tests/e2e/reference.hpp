// Helpers for comparing a generated model with a hand-written reference:
// the state of a set as plain arrays ordered by particle id, and the
// periodic minimum image written out independently of the runtime's.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

namespace reference {

using Vec2 = std::array<double, 2>;

// Shortest image of d in a periodic box of side L along each axis.
inline Vec2 minimum_image(Vec2 d, double L = 1.0) {
  for (double& x : d) x -= L * std::round(x / L);
  return d;
}

inline double norm(const Vec2& d) { return std::sqrt(d[0] * d[0] + d[1] * d[1]); }

// Indices of a set's particles in increasing id order.
template <class Set>
std::vector<std::size_t> by_id(const Set& set) {
  std::vector<std::size_t> order(set.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return set.ids()[a] < set.ids()[b]; });
  return order;
}

template <class Set>
std::vector<Vec2> positions_by_id(const Set& set) {
  std::vector<Vec2> out;
  for (std::size_t i : by_id(set)) out.push_back({set.positions()[i][0], set.positions()[i][1]});
  return out;
}

template <class Var, class Set>
auto values_by_id(const Set& set) {
  std::vector<typename std::decay_t<decltype(set.template get<Var>())>::value_type> out;
  for (std::size_t i : by_id(set)) out.push_back(set.template get<Var>()[i]);
  return out;
}

// The largest distance between a generated vec variable and its reference.
template <class V>
double worst(const std::vector<V>& got, const std::vector<Vec2>& want) {
  double w = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    w = std::max(w, norm({got[i][0] - want[i][0], got[i][1] - want[i][1]}));
  return w;
}

}  // namespace reference
