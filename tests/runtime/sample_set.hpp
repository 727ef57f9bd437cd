// The particle set the runtime tests share: a 2D set with one variable of
// each storage kind (vec, real, int, bool), as a generated model declares
// them (one tag struct per variable).
#pragma once

#include <cstdint>

#include "partc/particle_set.hpp"
#include "partc/vec.hpp"

namespace sample {

struct P_v {
  using type = partc::Vec<2>;
  static constexpr const char* name = "v";
};
struct P_e {
  using type = double;
  static constexpr const char* name = "e";
};
struct P_hits {
  using type = std::int64_t;
  static constexpr const char* name = "hits";
};
struct P_moving {
  using type = bool;
  static constexpr const char* name = "moving";
};
using Set = partc::ParticleSet<2, P_v, P_e, P_hits, P_moving>;

}  // namespace sample
