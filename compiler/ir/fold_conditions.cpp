#include "ir/fold_conditions.hpp"

#include "ir/constant.hpp"
#include "ir/mutator.hpp"

namespace partc::ir {

namespace {

class FoldConditions : public Mutator {
 public:
  explicit FoldConditions(const Model& model) : model_(model) {}
  using Mutator::mutate;
  std::vector<FoldedCondition> folded;  // in the order met, outermost first; no effect yet

 protected:
  Expr mutate(const Select& n, const Expr& self) override {
    if (const auto condition = evaluate_constant(n.condition, model_)) {
      const Expr& chosen = *condition != 0 ? n.then : n.otherwise;
      if (chosen->type == n.type) {
        folded.push_back({"", n.loc, *condition != 0});
        return mutate(chosen);
      }
    }
    return Mutator::mutate(n, self);
  }

 private:
  const Model& model_;
};

// The effect whose term holds `at`: instantiation placed it in its origin's text.
std::string effect_at(const Statement& st, Location at) {
  for (const Origin& o : st.origins)
    if (o.loc.begin <= at.begin && at.end <= o.loc.end) return o.effect;
  return "";
}

}  // namespace

std::vector<FoldedCondition> fold_conditions(Model& model) {
  std::vector<FoldedCondition> out;
  for (Stage& stage : model.stages)
    for (Statement& st : stage.statements) {
      FoldConditions fold(model);
      st.value = fold.mutate(st.value);
      st.solve_operator = fold.mutate(st.solve_operator);
      for (FoldedCondition& f : fold.folded) {
        f.effect = effect_at(st, f.loc);
        out.push_back(std::move(f));
      }
    }
  return out;
}

}  // namespace partc::ir
