// Decides which statements of the step run only on observed steps: those
// whose end state something reads (the driver's log rows and VTK frames, the
// last step, a library user's observables()). `output e_kin every 100` then
// costs e_kin's sum once per 100 steps, not every step; and a pair energy,
// per particle u[i] = sum(j, ...) and then e = sum(i, u[i]), its pair walk.
//
// Runs after fusion and zero-term folding, on the statements codegen emits
// (a read they removed is no read), and needs no other analysis: a search or
// a cell list a skipped statement would have built is built by the next
// statement that walks it, as every search checks its set's epoch and radius
// first. Codegen guards the statements with step(observed); step() alone
// observes every step, as before.
//
// A statement `x = value` of the step, x an observable or a particle
// variable of the model's own, is observed-only when nothing that runs every
// step can read what it writes. Its value is read by:
// - a statement of the step that reads x: fine only when that statement is
//   itself observed-only and runs after every statement of the step that
//   assigns x, so on an observed step it reads this step's x (a reader
//   before them, or the writer itself, reads the step before's);
// - an iterate condition (how many passes run would change), the timestep
//   (t would), a named stage (it may run between any two steps): never fine;
// - the log, VTK frames, --output, check_finite and observables() after the
//   step: fine, they are what observed steps are for (a check of a value not
//   recomputed checks one already checked). The init blocks run before the
//   first step: what they read is never a step's.
// A variable no statement of the step reads is the model's particle state,
// its output: kept current every step, as a --last-finite state needs; only a
// variable that observed-only statements read is theirs to skip.
// A compound `x += value` reads x as the step before left it: every step,
// and so is every other statement assigning x. Positions, ids, alive and
// variables turned at reflecting faces are read outside statements (every
// dx, the faces): never observed-only. Nor is a solve, whose result the
// driver reports, or a statement whose sums use Verlet lists: the lists must
// see each step's motion to rebuild in time (a move past half a periodic box
// looks like a small one).
#include "analysis/observed_steps.hpp"

#include <fmt/format.h>

#include <set>
#include <vector>

#include "ir/visitor.hpp"

namespace partc {

namespace {

// What a statement may write and read: an observable (-1, o) or a particle
// variable (set, var).
using Value = std::pair<int, int>;

class ValuesRead : public ir::Visitor {
 public:
  std::set<Value> found;

 public:
  using ir::Visitor::visit;

 protected:
  void visit(const ir::ObservableRef& n) override { found.insert({-1, n.observable}); }
  void visit(const ir::VarRef& n) override { found.insert({n.set, n.var}); }
};

std::set<Value> values_read(std::initializer_list<ir::Expr> exprs) {
  ValuesRead reads;
  for (const ir::Expr& e : exprs) reads.visit(e);
  return reads.found;
}

Value target(const ir::Statement& st) {
  return st.observable >= 0 ? Value{-1, st.observable} : Value{st.set, st.var};
}

// What a statement reads, its target too when it adds to it.
std::set<Value> values_read(const ir::Statement& st) {
  std::set<Value> read = values_read({st.value, st.solve_operator, st.schedule.skin,
                                      st.schedule.tolerance, st.schedule.max_iterations,
                                      st.schedule.order});
  if (st.op != ir::AssignOp::Set) read.insert(target(st));
  return read;
}

std::string name_of(const ir::Model& model, Value v) {
  if (v.first < 0) return model.observables[v.second].name;
  return (model.sets.size() > 1 ? model.sets[v.first].name + "." : "") +
         model.sets[v.first].vars[v.second].name;
}

// Why a statement of the step runs every step whatever reads its target; "" if not.
std::string every_step_by_itself(const ir::Model& model, const ir::Statement& st) {
  if (st.op != ir::AssignOp::Set)
    return fmt::format("line {} adds to it ({}), to the value of the step before", st.line,
                       ir::assign_op_spelling(st.op));
  if (st.solve_operator) return fmt::format("line {} solves for it", st.line);
  if (st.schedule.skin)
    return fmt::format("line {} uses Verlet lists, which must see every step's motion to "
                       "rebuild in time",
                       st.line);
  if (st.observable >= 0) return "";
  if (st.var < ir::kFirstUserVar)
    return "a builtin variable, read by every dx, search and face";
  if (model.sets[st.set].vars[st.var].mirrored) return "the reflecting faces turn it";
  return "";
}

struct StepStatement {
  std::pair<int, int> position;  // (stage, statement)
  const ir::Statement* st;
  std::set<Value> reads;
};

}  // namespace

ObservedStepReport find_observed_steps(const ir::Model& model) {
  // The step's statements in the order they run (iterate loops in place),
  // and per value why it is needed every step, whoever assigns it.
  std::vector<StepStatement> step;
  std::map<Value, std::string> every_step;
  for (std::size_t g = 0; g < model.stages.size(); ++g) {
    const ir::Stage& stage = model.stages[g];
    if (stage.kind == ir::StageKind::Init) continue;
    for (const ir::Iterate& loop : stage.loops)
      for (Value v : values_read({loop.until, loop.limit}))
        every_step.emplace(v, fmt::format("an iterate condition reads it (the loop of line {})",
                                          stage.statements[loop.first].line));
    for (std::size_t k = 0; k < stage.statements.size(); ++k) {
      const ir::Statement& st = stage.statements[k];
      if (stage.kind == ir::StageKind::Named) {
        for (Value v : values_read(st))
          every_step.emplace(v, fmt::format("stage {} reads it (line {}), and may run between "
                                            "any two steps",
                                            stage.name, st.line));
        continue;
      }
      step.push_back({{static_cast<int>(g), static_cast<int>(k)}, &st, values_read(st)});
    }
  }
  if (model.timestep)
    for (Value v : values_read({model.timestep}))
      every_step.emplace(v, "the timestep reads it after every step");
  // The last statement of the step assigning each value.
  std::map<Value, std::size_t> last_writer;
  for (std::size_t q = 0; q < step.size(); ++q) {
    last_writer[target(*step[q].st)] = q;
    const std::string why = every_step_by_itself(model, *step[q].st);
    if (!why.empty()) every_step.emplace(target(*step[q].st), why);
  }
  std::set<Value> read_in_step;
  for (const StepStatement& s : step) read_in_step.insert(s.reads.begin(), s.reads.end());
  for (const auto& [v, q] : last_writer)
    if (v.first >= 0 && !read_in_step.count(v))
      every_step.emplace(v, "particle state no statement of the step reads");
  // Every value is needed only on observed steps until a reader that is not
  // proves otherwise; marking one can mark those its statements read, so
  // repeat until nothing changes.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t q = 0; q < step.size(); ++q) {
      const ir::Statement& reader = *step[q].st;
      const bool reader_observed_only = !every_step.count(target(reader));
      for (Value v : step[q].reads) {
        if (every_step.count(v) || !last_writer.count(v)) continue;
        if (!reader_observed_only)
          every_step[v] = fmt::format("line {} reads it every step", reader.line);
        else if (q == last_writer[v] && target(reader) == v)
          every_step[v] = fmt::format("line {} reads the value the step before left", reader.line);
        else if (q <= last_writer[v])
          every_step[v] =
              fmt::format("line {} reads it before line {} assigns it: the step before's value",
                          reader.line, step[last_writer[v]].st->line);
        else
          continue;
        changed = true;
      }
    }
  }
  ObservedStepReport report;
  for (const StepStatement& s : step) {
    const Value v = target(*s.st);
    if (auto why = every_step.find(v); why != every_step.end()) {
      if (v.first < 0) report[s.position] = {false, "every step: " + why->second};
      continue;
    }
    std::set<std::string> readers;
    for (const StepStatement& r : step)
      if (r.reads.count(v)) readers.insert(name_of(model, target(*r.st)));
    report[s.position] = {
        true, fmt::format("only on observed steps (the state after them is logged or read): {}",
                          readers.empty()
                              ? "nothing in a step reads " + name_of(model, v)
                              : fmt::format("only {} read{} it, computed only then too",
                                            fmt::join(readers, ", "),
                                            readers.size() == 1 ? "s" : ""))};
  }
  return report;
}

}  // namespace partc
