// The seed benchmark's points, shared by the benches that time its velocity
// update on the runtime or on generated models: n points uniform in the unit
// square from a fixed seed, so that every bench (and every run) times the
// same configuration.
#pragma once

#include <cstddef>
#include <random>
#include <vector>

#include "partc/vec.hpp"

namespace bench {

inline std::vector<partc::Vec<2>> uniform_points(std::size_t n) {
  std::mt19937_64 random(2017);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<partc::Vec<2>> p(n);
  for (auto& x : p) x = partc::Vec<2>{{u(random), u(random)}};
  return p;
}

}  // namespace bench
