// The kernels and point sets the fast sum's tests and benchmark share:
// 1/r, multiquadrics and a Gaussian as plain function objects (copyable, as
// the compiler emits them); uniform points in the unit cube and a Plummer
// sphere (a dense core and a sparse halo); charges, all from a seed.
#pragma once

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "partc/vec.hpp"

namespace fast_sum_cases {

using partc::Vec;

struct Coulomb {
  double operator()(double r) const { return r > 0 ? 1 / r : 0.0; }
};
struct Multiquadric {
  double e;
  double operator()(double r) const { return std::sqrt(1 + (e * r) * (e * r)); }
};
struct Gaussian {
  double e;
  double operator()(double r) const { return std::exp(-(e * r) * (e * r)); }
};

template <int D>
std::vector<Vec<D>> uniform_points(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec<D>> x(n);
  for (auto& p : x)
    for (int d = 0; d < D; ++d) p[d] = u(rng);
  return x;
}

// Plummer's sphere (radius law r = (u^(-2/3) - 1)^(-1/2), cut at r = 10),
// centred in the unit cube at scale 0.05: a dense core and a sparse halo.
template <int D>
std::vector<Vec<D>> plummer_points(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  std::vector<Vec<D>> x;
  while (x.size() < n) {
    const double r = 1 / std::sqrt(std::pow(u(rng), -2.0 / 3) - 1);
    if (!(r < 10)) continue;
    Vec<D> dir;
    double len = 0;
    for (int d = 0; d < D; ++d) {
      dir[d] = g(rng);
      len += dir[d] * dir[d];
    }
    len = std::sqrt(len);
    Vec<D> p;
    for (int d = 0; d < D; ++d) p[d] = 0.5 + 0.05 * r * dir[d] / len;
    x.push_back(p);
  }
  return x;
}

std::vector<double> charges(std::size_t n, unsigned seed, double lowest = -1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lowest, 1);
  std::vector<double> q(n);
  for (double& v : q) v = u(rng);
  return q;
}

}  // namespace fast_sum_cases
