// Observed steps: which statements of the step run only on the steps whose
// end state is read (logged, written, returned), not every step.
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

// Keyed by (stage, statement): every step statement that assigns an
// observable, and every other one that runs only on observed steps.
using ObservedStepReport = std::map<std::pair<int, int>, ObservedStepFact>;

ObservedStepReport find_observed_steps(const ir::Model& model);

}  // namespace partc
