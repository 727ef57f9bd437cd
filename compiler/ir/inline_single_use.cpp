#include "ir/inline_single_use.hpp"

#include <algorithm>
#include <set>

#include "ir/mutator.hpp"
#include "ir/relabel.hpp"
#include "ir/terms.hpp"
#include "ir/visitor.hpp"

namespace partc::ir {

namespace {

using Position = std::pair<int, int>;  // stage, statement

// What an expression reads: variables (set, var) and observables.
struct Reads : Visitor {
  std::set<std::pair<int, int>> vars;
  std::set<int> observables;
  using Visitor::visit;
  void visit(const VarRef& n) override { vars.insert({n.set, n.var}); }
  void visit(const ObservableRef& n) override { observables.insert(n.observable); }
};

// How a statement reads one variable: where, and whether only at its own
// particle outside every sum.
struct UseOf : Visitor {
  int set, var;
  int uses = 0;
  bool only_home = true;
  int depth = 0;
  UseOf(int s, int v) : set(s), var(v) {}
  using Visitor::visit;
  void visit(const VarRef& n) override {
    if (n.set != set || n.var != var) return;
    ++uses;
    only_home = only_home && n.label == 0 && depth == 0;
  }
  void visit(const Accumulate& n) override {
    ++depth;
    Visitor::visit(n);
    --depth;
  }
};

struct Substitute : Mutator {
  int set, var;
  Expr value;
  using Mutator::mutate;
  Expr mutate(const VarRef& n, const Expr& self) override {
    return n.set == set && n.var == var ? value : self;
  }
};

// After a variable is removed, the ones after it in its set move down one.
struct Renumber : Mutator {
  int set, removed;
  using Mutator::mutate;
  Expr mutate(const VarRef& n, const Expr& self) override {
    if (n.set != set || n.var < removed) return self;
    return std::make_shared<VarRef>(n.type, n.set, n.var - 1, n.label, n.loc);
  }
};

bool default_schedule(const Schedule& s) {
  return s.search == SearchChoice::Auto && !s.skin && s.solver == SolverChoice::Auto &&
         !s.compensated && s.dense == DenseMethod::Direct;
}

class Inliner {
 public:
  explicit Inliner(Model& m) : m_(m) {}

  SingleUseReport run() {
    for (int s = 0; s < static_cast<int>(m_.sets.size()); ++s)
      for (int x = kFirstUserVar; x < static_cast<int>(m_.sets[s].vars.size());)
        if (try_inline(s, x))
          continue;  // x now names the next variable
        else
          ++x;
    return report_;
  }

 private:
  Statement& at(Position p) { return m_.stages[p.first].statements[p.second]; }

  bool refuse(int s, int x, const std::string& why) {
    report_.refused.push_back({m_.sets[s].name, m_.sets[s].vars[x].name, why});
    return false;
  }

  bool try_inline(int s, int x) {
    const Variable& var = m_.sets[s].vars[x];
    if (!var.effect_owned) return false;  // the scene's own variables are the user's to keep
    if (var.mirrored || var.storage != Precision::Double)
      return refuse(s, x, "stored as declared (mirrored or float)");
    for (const Frames& f : m_.frames)
      if (f.set == s && std::count(f.vars.begin(), f.vars.end(), x))
        return refuse(s, x, "written to VTK frames");
    std::vector<Position> writers, readers;
    for (int g = 0; g < static_cast<int>(m_.stages.size()); ++g)
      for (int k = 0; k < static_cast<int>(m_.stages[g].statements.size()); ++k) {
        const Statement& st = m_.stages[g].statements[k];
        if (st.observable < 0 && st.set == s && st.var == x) writers.push_back({g, k});
        UseOf use(s, x);
        use.visit(st.value);
        use.visit(st.solve_operator);
        if (use.uses) readers.push_back({g, k});
      }
    // A candidate is set by one statement and read by one other; the rest
    // (state carried across steps, read in many places) is plainly stored.
    if (writers.size() != 1 || readers.size() != 1) return false;
    for (const ParticleSet& set : m_.sets)
      for (const Variable& v : set.vars) {
        UseOf use(s, x);
        use.visit(v.initial);
        if (use.uses) return refuse(s, x, "an initial value reads it");
      }
    const Position w = writers.front(), r = readers.front();
    const Statement& writer = at(w);
    const Statement& reader = at(r);
    if (w == r) return refuse(s, x, "its writer reads it");
    if (m_.stages[w.first].kind != StageKind::Step || m_.stages[r.first].kind != StageKind::Step ||
        r < w)
      return refuse(s, x, "not set and then read within one step");
    if (m_.stages[w.first].in_loop(w.second) || m_.stages[r.first].in_loop(r.second))
      return refuse(s, x, "in an iterate block");
    if (writer.op != AssignOp::Set || writer.solve_operator || writer.value->type != var.type)
      return refuse(s, x, "its writer is not a plain assignment of its type");
    if (reader.observable >= 0 || reader.set != s || reader.solve_operator)
      return refuse(s, x, "its reader is not a statement over the same set");
    UseOf use(s, x);
    use.visit(reader.value);
    if (!use.only_home) return refuse(s, x, "its reader reads it at another particle or in a sum");
    if (use.uses > 1)
      return refuse(s, x, "its reader reads it more than once (each read would compute it again)");
    if (!default_schedule(writer.schedule) && !default_schedule(reader.schedule))
      return refuse(s, x, "both statements have a schedule");
    // Nothing between them may change what the writer reads.
    Reads reads;
    reads.visit(writer.value);
    for (Position p = {w.first, w.second + 1}; p < r;) {
      if (p.second >= static_cast<int>(m_.stages[p.first].statements.size())) {
        p = {p.first + 1, 0};
        continue;
      }
      const Statement& between = at(p);
      if (m_.stages[p.first].kind == StageKind::Step &&
          (between.observable >= 0 ? reads.observables.count(between.observable) > 0
                                   : reads.vars.count({between.set, between.var}) > 0))
        return refuse(
            s, x, "a statement between its writer and its reader changes what it is computed from");
      ++p.second;
    }

    // Fuse: the reader computes the writer's value where it read the variable.
    Statement fused = reader;
    const int base = static_cast<int>(fused.labels.size());
    auto into_reader = [&](const Expr& reader_value, const Expr& writer_value) {
      Substitute substitute;
      substitute.set = s;
      substitute.var = x;
      substitute.value = append_labels(writer_value, base);
      return substitute.mutate(reader_value);
    };
    fused.value = into_reader(reader.value, writer.value);
    fused.labels.insert(fused.labels.end(), writer.labels.begin() + 1, writer.labels.end());
    fused.origins = writer.origins;
    fused.terms_by_origin = false;
    fused.origins.insert(fused.origins.end(), reader.origins.begin(), reader.origins.end());
    // --profile's parts: the writer's, each in the reader (a writer of no
    // split terms leaves all its origins out at once: its type's zero); the
    // reader's that still read the writer, with all of it. Origins are
    // numbered as fused.origins.
    fused.without.clear();
    std::vector<Statement::Without> writer_parts = parts_without(writer);
    if (writer_parts.empty() && !writer.origins.empty()) {
      std::vector<std::size_t> all(writer.origins.size());
      for (std::size_t o = 0; o < all.size(); ++o) all[o] = o;
      writer_parts.push_back({all, zero_of(var.type, m_.dim, writer.value->loc)});
    }
    for (const Statement::Without& part : writer_parts)
      fused.without.push_back({part.origins, into_reader(reader.value, part.value)});
    for (Statement::Without part : parts_without(reader)) {
      UseOf still(s, x);
      still.visit(part.value);
      if (!still.uses) continue;  // the writer would go with that term: not the reader's alone
      for (std::size_t& o : part.origins) o += writer.origins.size();
      fused.without.push_back({part.origins, into_reader(part.value, writer.value)});
    }
    if (default_schedule(fused.schedule)) fused.schedule = writer.schedule;
    report_.inlined.push_back({m_.sets[s].name, var.name, writer.loc, reader.loc});
    at(r) = std::move(fused);
    m_.stages[w.first].statements.erase(m_.stages[w.first].statements.begin() + w.second);
    for (Iterate& loop : m_.stages[w.first].loops) {
      if (loop.first > w.second) --loop.first;
      if (loop.last > w.second) --loop.last;
    }
    remove_variable(s, x);
    return true;
  }

  void remove_variable(int s, int x) {
    Renumber renumber;
    renumber.set = s;
    renumber.removed = x;
    m_.sets[s].vars.erase(m_.sets[s].vars.begin() + x);
    for (Stage& stage : m_.stages)
      for (Statement& st : stage.statements) {
        st.value = renumber.mutate(st.value);
        st.solve_operator = renumber.mutate(st.solve_operator);
        for (Statement::Without& part : st.without) part.value = renumber.mutate(part.value);
        if (st.observable < 0 && st.set == s && st.var > x) --st.var;
      }
    for (ParticleSet& set : m_.sets)
      for (Variable& v : set.vars) v.initial = renumber.mutate(v.initial);
    for (Frames& f : m_.frames)
      if (f.set == s)
        for (int& v : f.vars)
          if (v > x) --v;
  }

  Model& m_;
  SingleUseReport report_;
};

}  // namespace

SingleUseReport inline_single_use(Model& model) { return Inliner(model).run(); }

}  // namespace partc::ir
