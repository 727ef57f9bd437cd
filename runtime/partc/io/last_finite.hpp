// partc/io/last_finite.hpp: a copy of the last model state found finite, kept
// so that a numerical blow-up loses no work. The driver writes it as CSV,
// which --input reads back: resume with a smaller time step, or look at the
// particles just before the blow-up.
//
//   LastFinite kept;                       // holds nothing until the first take
//   kept.take(views_of_the_sets, step);    // after each check that passed
//   kept.write([](set) { return path; })   // on a blow-up
//
// Surprises:
// - A copy costs one pass over the state, as the check before it does; the
//   copy reuses its storage, so taking it allocates only when a set grows.
//   Copies are taken only when a check passes, so --check-every M thins both.
// - The copy holds the particles (ids, positions, variables), as bytes of
//   the sets' views (io/set_view.hpp), not observables or the model's time:
//   a resumed run starts its clock at 0.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "partc/io/set_view.hpp"

namespace partc {

class LastFinite {
 public:
  void take(const std::vector<SetView>& sets, std::int64_t step);

  bool empty() const { return step_ < 0; }
  std::int64_t step() const { return step_; }

  // Writes each set to path_of(set name); returns the paths written.
  std::vector<std::string> write(
      const std::function<std::string(const std::string&)>& path_of) const;

 private:
  struct Copy {
    SetView view;  // its ids and columns point into the vectors below
    std::vector<std::int64_t> ids;
    std::vector<std::vector<unsigned char>> columns;
  };

  std::vector<Copy> sets_;
  std::int64_t step_ = -1;
};

}  // namespace partc
