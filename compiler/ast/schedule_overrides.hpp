// partc --schedule 'force: skin = 0.4': schedule entries given on the
// command line, over the model's own schedule.
#pragma once

#include <string>
#include <vector>

#include "ast/ast.hpp"
#include "support/source.hpp"

namespace partc::ast {

// Parses each text as the items of a schedule block (appended to `file`, so
// that messages point into it) and merges them into `program`: an option of
// an entry the model schedules already replaces the model's value of that
// option, or is added to the entry; an entry for a subject the model does not
// schedule is added. The program then reads as if its schedule had been
// written so: every check sema makes applies to what was asked here.
void apply_schedule_overrides(Program& program, SourceFile& file,
                              const std::vector<std::string>& overrides);

}  // namespace partc::ast
