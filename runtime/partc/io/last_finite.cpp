// partc/io/last_finite.cpp: the copy of the last finite state (last_finite.hpp).
#include "partc/io/last_finite.hpp"

#include <cstring>

#include "partc/io/csv.hpp"

namespace partc {

void LastFinite::take(const std::vector<SetView>& sets, std::int64_t step) {
  sets_.resize(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const SetView& from = sets[s];
    Copy& copy = sets_[s];
    copy.view = from;
    copy.ids.assign(from.ids, from.ids + from.size);
    copy.view.ids = copy.ids.data();
    copy.columns.resize(from.columns.size());
    for (std::size_t c = 0; c < from.columns.size(); ++c) {
      const std::size_t bytes = from.columns[c].bytes(from.size);
      copy.columns[c].resize(bytes);
      if (bytes > 0) std::memcpy(copy.columns[c].data(), from.columns[c].data, bytes);
      copy.view.columns[c].data = copy.columns[c].data();
    }
  }
  step_ = step;
}

std::vector<std::string> LastFinite::write(
    const std::function<std::string(const std::string&)>& path_of) const {
  std::vector<std::string> paths;
  for (const Copy& copy : sets_) {
    paths.push_back(path_of(copy.view.name));
    write_csv(paths.back(), copy.view);
  }
  return paths;
}

}  // namespace partc
