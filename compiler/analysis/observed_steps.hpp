// Observed steps: which observable statements of the step run only on the
// steps whose end state is read (logged, checked, returned), not every step.
#pragma once

#include <map>
#include <string>
#include <utility>

#include "ir/ir.hpp"

namespace partc {

struct ObservedStepFact {
  // Run only when step(observed) is told the state after the step is read;
  // else every step.
  bool observed_only = false;
  std::string reason;  // why, in the model's terms (for --explain)
};

// Keyed by (stage, statement), for every step statement that assigns an observable.
using ObservedStepReport = std::map<std::pair<int, int>, ObservedStepFact>;

ObservedStepReport find_observed_steps(const ir::Model& model);

}  // namespace partc
