// C++ names for the things a model names.
//
// Generated code keeps the model's own names (v, p, rc, i, j) so it reads
// like the .part file. A name that is a C++ keyword gets a trailing '_';
// names the generator itself introduces (accumulators, buffers) are drawn
// from a NameTable so they never collide with the model's.
#pragma once

#include <cstdint>
#include <set>
#include <string>

namespace partc::codegen {

// `name`, or `name_` when `name` is a C++ keyword or reserved identifier;
// an effect's qualified name (lj.eps) with '_' for '.' (lj_eps: the scene
// made sure no other name is spelled so).
std::string cpp_name(const std::string& name);

// The 64-bit FNV-1a hash of a name: an effect instance's random key.
std::uint64_t fnv1a64(const std::string& name);

// "LjMelt" -> "LJMELT": for macro names.
std::string upper_case(const std::string& name);

// "lj_melt" -> "LjMelt": the generated class.
std::string class_name(const std::string& model_name);

class NameTable {
 public:
  void reserve(const std::string& name) { taken_.insert(name); }
  // `wanted` if free, else wanted_2, wanted_3, ...; the result is reserved.
  std::string fresh(const std::string& wanted);

 private:
  std::set<std::string> taken_;
};

}  // namespace partc::codegen
