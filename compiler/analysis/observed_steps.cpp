// Decides which observable statements of the step run only on observed
// steps: those whose end state something reads (the driver's log rows, the
// last step, a library user's observables()). `output e_kin every 100`
// then costs e_kin's sum once per 100 steps, not every step.
//
// Runs after fusion and zero-term folding, on the statements codegen emits
// (a read they removed is no read), and needs no other analysis: a search or
// a cell list a skipped statement would have built is built by the next
// statement that walks it, as every search checks its set's epoch and radius
// first. Codegen guards the statements with step(observed); step() alone
// observes every step, as before.
//
// A statement `o = value` of the step is observed-only when no value it
// writes can reach anything that runs every step. Its value is read by:
// - a statement of the step that reads o: fine only when that statement is
//   itself observed-only and runs after every statement of the step that
//   assigns o, so on an observed step it reads this step's o (a reader
//   before them, or the writer itself, reads the step before's);
// - an iterate condition (how many passes run would change), the timestep
//   (t would), a named stage (it may run between any two steps): never fine;
// - the log, check_finite and observables() after the step: fine, they are
//   what observed steps are for. The init blocks run before the first step:
//   what they read is never a step's.
// A compound `o += value` reads o as the step before left it: every step,
// and so is every other statement assigning o. A statement whose sums use
// Verlet lists runs every step: the lists must see each step's motion to
// rebuild in time (a move past half a periodic box looks like a small one).
#include "analysis/observed_steps.hpp"

#include <fmt/format.h>

#include <set>
#include <vector>

#include "ir/visitor.hpp"

namespace partc {

namespace {

class ObservablesRead : public ir::Visitor {
 public:
  std::set<int> found;

 public:
  using ir::Visitor::visit;

 protected:
  void visit(const ir::ObservableRef& n) override { found.insert(n.observable); }
};

std::set<int> observables_read(std::initializer_list<ir::Expr> exprs) {
  ObservablesRead reads;
  for (const ir::Expr& e : exprs) reads.visit(e);
  return reads.found;
}

// What a statement reads of the observables, its target too when it adds to it.
std::set<int> observables_read(const ir::Statement& st) {
  std::set<int> read = observables_read({st.value, st.solve_operator, st.schedule.skin,
                                         st.schedule.tolerance, st.schedule.max_iterations});
  if (st.observable >= 0 && st.op != ir::AssignOp::Set) read.insert(st.observable);
  return read;
}

struct StepStatement {
  std::pair<int, int> position;  // (stage, statement)
  const ir::Statement* st;
  std::set<int> reads;
};

}  // namespace

ObservedStepReport find_observed_steps(const ir::Model& model) {
  // The step's statements in the order they run (iterate loops in place),
  // and per observable why it is needed every step, whoever assigns it.
  std::vector<StepStatement> step;
  std::map<int, std::string> every_step;
  for (std::size_t g = 0; g < model.stages.size(); ++g) {
    const ir::Stage& stage = model.stages[g];
    if (stage.kind == ir::StageKind::Init) continue;
    for (const ir::Iterate& loop : stage.loops)
      for (int o : observables_read({loop.until, loop.limit}))
        every_step.emplace(o, fmt::format("the iterate condition on line {} reads it",
                                          model.stages[g].statements[loop.first].line));
    for (std::size_t k = 0; k < stage.statements.size(); ++k) {
      const ir::Statement& st = stage.statements[k];
      if (stage.kind == ir::StageKind::Named) {
        for (int o : observables_read(st))
          every_step.emplace(o, fmt::format("stage {} reads it (line {}), and may run between "
                                            "any two steps",
                                            stage.name, st.line));
        continue;
      }
      step.push_back({{static_cast<int>(g), static_cast<int>(k)}, &st, observables_read(st)});
    }
  }
  if (model.timestep)
    for (int o : observables_read({model.timestep}))
      every_step.emplace(o, "the timestep reads it after every step");
  // The last statement of the step assigning each observable.
  std::map<int, std::size_t> last_writer;
  for (std::size_t q = 0; q < step.size(); ++q) {
    const ir::Statement& st = *step[q].st;
    if (st.observable < 0) continue;
    last_writer[st.observable] = q;
    if (st.op != ir::AssignOp::Set)
      every_step.emplace(st.observable,
                         fmt::format("line {} adds to it ({}), to the value of the step before",
                                     st.line, ir::assign_op_spelling(st.op)));
    else if (st.schedule.skin)
      every_step.emplace(st.observable,
                         fmt::format("line {} uses Verlet lists, which must see every step's "
                                     "motion to rebuild in time",
                                     st.line));
  }
  // Every observable is observed-only until a reader that is not proves otherwise;
  // marking one can unmark those its statements read, so repeat until nothing changes.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t q = 0; q < step.size(); ++q) {
      const ir::Statement& reader = *step[q].st;
      const bool reader_observed_only =
          reader.observable >= 0 && !every_step.count(reader.observable);
      for (int o : step[q].reads) {
        if (every_step.count(o) || !last_writer.count(o)) continue;
        if (!reader_observed_only)
          every_step[o] = fmt::format("line {} reads it every step", reader.line);
        else if (q <= last_writer[o])
          every_step[o] =
              fmt::format("line {} reads it before line {} assigns it: the step before's value",
                          reader.line, step[last_writer[o]].st->line);
        else
          continue;
        changed = true;
      }
    }
  }
  ObservedStepReport report;
  for (const StepStatement& s : step) {
    const int o = s.st->observable;
    if (o < 0) continue;
    auto why = every_step.find(o);
    if (why != every_step.end()) {
      report[s.position] = {false, "every step: " + why->second};
      continue;
    }
    std::set<std::string> readers;
    for (const StepStatement& r : step)
      if (r.reads.count(o)) readers.insert(model.observables[r.st->observable].name);
    report[s.position] = {
        true, fmt::format("only on observed steps (the state after them is logged or read): {}",
                          readers.empty()
                              ? "nothing in a step reads " + model.observables[o].name
                              : fmt::format("only {} read{} it, themselves computed only then",
                                            fmt::join(readers, ", "),
                                            readers.size() == 1 ? "s" : ""))};
  }
  return report;
}

}  // namespace partc
