// Decides, per statement, whether it may update its target in place.
//
// A statement `x[i] op= e` runs for every particle i. Updating in place is
// correct only if no evaluation of `e` reads x of *another* particle of the
// same set: otherwise particle i would see a mix of old and new values,
// depending on loop order. Such reads are x[j] through an accumulation
// label over the same set, and, when x is the position p, dx (which reads
// p[j]). A read of x[i] itself is harmless: each i reads its own old value
// before writing it, and so is a read inside a sum computed once before the
// loop (uniform_sums.cpp): it sees only old values. Buffered statements
// compute all new values first.
#include "analysis/aliasing.hpp"

#include "ir/visitor.hpp"

namespace partc {

namespace {

class FindsOtherParticleReads : public ir::Visitor {
 public:
  FindsOtherParticleReads(const ir::Statement& st, const UniformSumReport& uniform_sums)
      : st_(st), uniform_sums_(uniform_sums) {}
  std::string found;                 // the offending read, spelled as in .part
  bool read_in_uniform_sum = false;  // such a read, but in a sum computed once: harmless

 public:
  using ir::Visitor::visit;

 protected:
  void visit(const ir::VarRef& n) override {
    if (n.label != 0 && n.set == st_.set && n.var == st_.var && found.empty())
      found = st_.labels[n.label].name;
  }
  void visit(const ir::Dx& n) override {
    if (st_.var == ir::kPosition && st_.labels[n.to].set == st_.set && found.empty()) found = "dx";
  }
  void visit(const ir::Accumulate& n) override {
    if (!uniform_sums_.at(n.id).once) return ir::Visitor::visit(n);
    FindsOtherParticleReads inside(st_, uniform_sums_);
    inside.visit(n.condition);
    inside.visit(n.body);
    read_in_uniform_sum = read_in_uniform_sum || !inside.found.empty();
  }

 private:
  const ir::Statement& st_;
  const UniformSumReport& uniform_sums_;
};

}  // namespace

AliasReport detect_aliasing(const ir::Model& model, const UniformSumReport& uniform_sums) {
  AliasReport report;
  for (const ir::Stage& stage : model.stages) {
    auto& facts = report.emplace_back();
    for (const ir::Statement& st : stage.statements) {
      if (st.observable >= 0) {
        facts.push_back({false, "observable " + model.observables[st.observable].name +
                                    ": one value, computed once"});
        continue;
      }
      if (st.solve_operator) {
        facts.push_back({false, model.sets[st.set].vars[st.var].name +
                                    " of every particle at once, from a linear system"});
        continue;
      }
      FindsOtherParticleReads finder(st, uniform_sums);
      finder.visit(st.value);
      AliasFact fact;
      const std::string& var = model.sets[st.set].vars[st.var].name;
      if (finder.found.empty()) {
        fact.reason = var + "[" + st.labels[0].name + "] reads " +
                      (finder.read_in_uniform_sum
                           ? "other particles' " + var + " only in sums computed before the loop"
                           : "no other particle's " + var) +
                      ": updated in place";
      } else {
        fact.buffered = true;
        fact.reason = finder.found == "dx" ? "writes p while dx reads other particles' p: buffered"
                                           : "writes " + var + " while reading " + var + "[" +
                                                 finder.found + "]: buffered";
      }
      facts.push_back(std::move(fact));
    }
  }
  return report;
}

}  // namespace partc
