// The seed benchmark's box and points, shared by the benches that time its
// velocity update on the runtime or on generated models: the periodic unit
// square, and n points uniform in it from a fixed seed, so that every bench
// (and every run) times the same configuration.
#pragma once

#include <cstddef>
#include <random>
#include <vector>

#include "partc/domain.hpp"
#include "partc/vec.hpp"

namespace bench {

inline partc::Domain<2> periodic_unit_square() {
  partc::Domain<2> domain;
  domain.lo = partc::Vec<2>{{0, 0}};
  domain.hi = partc::Vec<2>{{1, 1}};
  domain.periodic = {true, true};
  return domain;
}

inline std::vector<partc::Vec<2>> uniform_points(std::size_t n) {
  std::mt19937_64 random(2017);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<partc::Vec<2>> p(n);
  for (auto& x : p) x = partc::Vec<2>{{u(random), u(random)}};
  return p;
}

}  // namespace bench
