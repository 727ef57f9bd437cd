// Schedule entries from the command line merged into the model's schedule,
// before sema, so that a sweep over a schedule choice (a fast sum's
// tolerance, a skin, a precision) needs no edited copy of the model, and a
// bad entry is reported as the model's own would be.
#include "ast/schedule_overrides.hpp"

#include <algorithm>

#include "grammar/parser.hpp"
#include "support/diagnostics.hpp"

namespace partc::ast {

namespace {

bool same_subject(const ScheduleItem& a, const ScheduleItem& b) {
  if (!a.subject || !b.subject) return !a.subject && !b.subject;
  if (a.subject->name.name != b.subject->name.name) return false;
  if (!a.subject->member || !b.subject->member) return !a.subject->member && !b.subject->member;
  return a.subject->member->name == b.subject->member->name;
}

// The model's schedule item for the subject of `item`, or null.
ScheduleItem* scheduled(Program& program, const ScheduleItem& item) {
  for (Declaration& d : program.declarations)
    if (auto* block = boost::get<ScheduleBlock>(&d))
      for (ScheduleItem& own : block->items)
        if (same_subject(own, item)) return &own;
  return nullptr;
}

bool solve_named(const std::vector<BlockStatement>& body, const std::string& name) {
  for (const BlockStatement& s : body) {
    if (const auto* solve = boost::get<SolveStatement>(&s))
      if (solve->name && solve->name->name == name) return true;
    if (const auto* loop = boost::get<x3::forward_ast<IterateBlock>>(&s))
      if (solve_named(loop->get().body, name)) return true;
  }
  return false;
}

// Whether the item's subject is a solve statement of the model.
bool names_a_solve(const Program& program, const ScheduleItem& item) {
  if (!item.subject || item.subject->member) return false;
  for (const Declaration& d : program.declarations)
    if (const auto* stage = boost::get<StageBlock>(&d))
      if (solve_named(stage->body, item.subject->name.name)) return true;
  return false;
}

}  // namespace

void apply_schedule_overrides(Program& program, SourceFile& file,
                              const std::vector<std::string>& overrides) {
  for (const std::string& text : overrides) {
    const int segment = file.append("--schedule", "schedule { " + text + " }\n");
    Program parsed = parse_program(file, segment);
    for (Declaration& d : parsed.declarations) {
      auto* block = boost::get<ScheduleBlock>(&d);
      if (!block)  // text that closed the braces itself
        throw CompileError(Diagnostic{file.extent(segment),
                                      "--schedule takes schedule entries only",
                                      "as in --schedule 'force: skin = 0.4, search = cell_list'"});
      for (ScheduleItem& item : block->items) {
        ScheduleItem* own = scheduled(program, item);
        if (!own) {
          ScheduleBlock added;
          added.loc = item.loc;
          added.items.push_back(item);
          program.declarations.emplace_back(std::move(added));
          continue;
        }
        // A fast sum takes a tolerance or an order: asking one drops the
        // other. A solve takes both: the solver's tol and its fast sums' order.
        const bool solve = names_a_solve(program, item);
        for (ScheduleOption& option : item.options) {
          const std::string rival = solve                        ? ""
                                    : option.key.name == "tol"   ? "order"
                                    : option.key.name == "order" ? "tol"
                                                                 : "";
          own->options.erase(
              std::remove_if(own->options.begin(), own->options.end(),
                             [&](const ScheduleOption& o) { return o.key.name == rival; }),
              own->options.end());
          auto same_key =
              std::find_if(own->options.begin(), own->options.end(),
                           [&](const ScheduleOption& o) { return o.key.name == option.key.name; });
          if (same_key != own->options.end())
            *same_key = option;
          else
            own->options.push_back(option);
        }
      }
    }
  }
}

}  // namespace partc::ast
