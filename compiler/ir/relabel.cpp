#include "ir/relabel.hpp"

#include "ir/mutator.hpp"

namespace partc::ir {

namespace {

struct Relabel : Mutator {
  int base;
  explicit Relabel(int b) : base(b) {}
  int map(int label) const { return label == 0 ? 0 : base + label - 1; }
  using Mutator::mutate;
  Expr mutate(const VarRef& n, const Expr&) override {
    return std::make_shared<VarRef>(n.type, n.set, n.var, map(n.label), n.loc);
  }
  Expr mutate(const Dx& n, const Expr&) override {
    return std::make_shared<Dx>(map(n.from), map(n.to), n.loc);
  }
  Expr mutate(const Accumulate& n, const Expr&) override {
    return std::make_shared<Accumulate>(n.type, n.reduction, map(n.label), mutate(n.condition),
                                        mutate(n.body), n.id, n.loc);
  }
};

}  // namespace

Expr append_labels(const Expr& e, int base) { return Relabel(base).mutate(e); }

}  // namespace partc::ir
