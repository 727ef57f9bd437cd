// A benchmark's --n argument: sizes separated by commas, each a number
// such as 10000 or 1e4 (exponents read as doubles, then truncated).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace bench {

inline std::vector<std::size_t> parse_sizes(const std::string& text) {
  std::vector<std::size_t> sizes;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    sizes.push_back(static_cast<std::size_t>(std::atof(item.c_str())));
  return sizes;
}

}  // namespace bench
