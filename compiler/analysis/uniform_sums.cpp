// Decides which accumulations have one value for every particle i of their
// statement, so that the statement computes them once rather than once per
// particle: an O(N) pass instead of O(N^2) for `v[i] -= sum(j, true, v[j]) / N`.
//
// An accumulation is uniform when neither its condition nor its body reads
// anything of i: no variable through the statement's own label, and no dx
// (dx = p[j] - p[i] reads i's position). Such a sum reads the state as it is
// before the statement runs; that matches the statement's semantics because a
// statement whose sum reads the variable it writes is buffered (aliasing.cpp),
// so every particle's sum sees the old values anyway.
#include "analysis/uniform_sums.hpp"

#include "ir/visitor.hpp"

namespace partc {

namespace {

class FindsReadOfI : public ir::Visitor {
 public:
  FindsReadOfI(const ir::Model& model, const ir::Statement& st) : model_(model), st_(st) {}
  std::string found;  // the first read of i, spelled as in .part

 public:
  using ir::Visitor::visit;

 protected:
  void visit(const ir::VarRef& n) override {
    if (n.label == 0 && found.empty())
      found = model_.sets[n.set].vars[n.var].name + "[" + st_.labels[0].name + "]";
  }
  void visit(const ir::Dx&) override {
    if (found.empty()) found = "dx";
  }

 private:
  const ir::Model& model_;
  const ir::Statement& st_;
};

}  // namespace

UniformSumReport find_uniform_sums(const ir::Model& model) {
  UniformSumReport report;
  for (const ir::Stage& stage : model.stages)
    for (const ir::Statement& st : stage.statements) {
      for (const ir::Accumulate* acc : ir::accumulations_in(st.solve_operator))
        report[acc->id] = {false, "a sum in the operator of a solve: one row per particle"};
      for (const ir::Accumulate* acc : ir::accumulations_in(st.value)) {
        FindsReadOfI reads(model, st);
        reads.visit(acc->condition);
        reads.visit(acc->body);
        UniformSumFact& fact = report[acc->id];
        if (st.observable >= 0) {
          fact.once = true;
          fact.reason = "a reduction for observable " + model.observables[st.observable].name +
                        ": computed once";
          continue;
        }
        fact.once = reads.found.empty();
        fact.reason = fact.once ? "reads nothing of " + st.labels[0].name +
                                      ": computed once for all particles, not once per particle"
                                : "reads " + reads.found + ": computed per particle";
      }
    }
  return report;
}

}  // namespace partc
