// Dispatch for Visitor and Mutator, and the default rebuilding mutations.
#include "ir/mutator.hpp"
#include "ir/visitor.hpp"
#include "support/diagnostics.hpp"

namespace partc::ir {

void Visitor::visit(const Expr& e) {
  if (!e) return;
  switch (e->kind) {
    case ExprKind::Literal: return visit(*as<Literal>(e));
    case ExprKind::ParamRef: return visit(*as<ParamRef>(e));
    case ExprKind::ConstRef: return visit(*as<ConstRef>(e));
    case ExprKind::ObservableRef: return visit(*as<ObservableRef>(e));
    case ExprKind::VarRef: return visit(*as<VarRef>(e));
    case ExprKind::Dx: return visit(*as<Dx>(e));
    case ExprKind::Unary: return visit(*as<Unary>(e));
    case ExprKind::Binary: return visit(*as<Binary>(e));
    case ExprKind::Call: return visit(*as<Call>(e));
    case ExprKind::MakeVec: return visit(*as<MakeVec>(e));
    case ExprKind::Component: return visit(*as<Component>(e));
    case ExprKind::Random: return visit(*as<Random>(e));
    case ExprKind::Accumulate: return visit(*as<Accumulate>(e));
    case ExprKind::FnArg: return visit(*as<FnArg>(e));
    case ExprKind::FnCall: return visit(*as<FnCall>(e));
    case ExprKind::Select: return visit(*as<Select>(e));
  }
  internal_error("Visitor: unknown expression kind");
}

Expr Mutator::mutate(const Expr& e) {
  if (!e) return e;
  switch (e->kind) {
    case ExprKind::Literal: return mutate(*as<Literal>(e), e);
    case ExprKind::ParamRef: return mutate(*as<ParamRef>(e), e);
    case ExprKind::ConstRef: return mutate(*as<ConstRef>(e), e);
    case ExprKind::ObservableRef: return mutate(*as<ObservableRef>(e), e);
    case ExprKind::VarRef: return mutate(*as<VarRef>(e), e);
    case ExprKind::Dx: return mutate(*as<Dx>(e), e);
    case ExprKind::Unary: return mutate(*as<Unary>(e), e);
    case ExprKind::Binary: return mutate(*as<Binary>(e), e);
    case ExprKind::Call: return mutate(*as<Call>(e), e);
    case ExprKind::MakeVec: return mutate(*as<MakeVec>(e), e);
    case ExprKind::Component: return mutate(*as<Component>(e), e);
    case ExprKind::Random: return mutate(*as<Random>(e), e);
    case ExprKind::Accumulate: return mutate(*as<Accumulate>(e), e);
    case ExprKind::FnArg: return mutate(*as<FnArg>(e), e);
    case ExprKind::FnCall: return mutate(*as<FnCall>(e), e);
    case ExprKind::Select: return mutate(*as<Select>(e), e);
  }
  internal_error("Mutator: unknown expression kind");
}

namespace {
// Mutates every element; reports whether any changed.
bool mutate_all(Mutator& m, const std::vector<Expr>& in, std::vector<Expr>& out) {
  bool changed = false;
  out.reserve(in.size());
  for (const Expr& a : in) {
    out.push_back(m.mutate(a));
    changed |= out.back() != a;
  }
  return changed;
}
}  // namespace

Expr Mutator::mutate(const Unary& n, const Expr& self) {
  Expr a = mutate(n.operand);
  if (a == n.operand) return self;
  return std::make_shared<Unary>(n.type, n.op, a, n.loc);
}

Expr Mutator::mutate(const Binary& n, const Expr& self) {
  Expr a = mutate(n.lhs), b = mutate(n.rhs);
  if (a == n.lhs && b == n.rhs) return self;
  return std::make_shared<Binary>(n.type, n.op, a, b, n.loc);
}

Expr Mutator::mutate(const Call& n, const Expr& self) {
  std::vector<Expr> args;
  if (!mutate_all(*this, n.args, args)) return self;
  return std::make_shared<Call>(n.type, n.fn, std::move(args), n.loc);
}

Expr Mutator::mutate(const FnCall& n, const Expr& self) {
  std::vector<Expr> args;
  if (!mutate_all(*this, n.args, args)) return self;
  return std::make_shared<FnCall>(n.type, n.fn, std::move(args), n.loc);
}

Expr Mutator::mutate(const MakeVec& n, const Expr& self) {
  std::vector<Expr> components;
  if (!mutate_all(*this, n.components, components)) return self;
  return std::make_shared<MakeVec>(std::move(components), n.loc);
}

Expr Mutator::mutate(const Component& n, const Expr& self) {
  Expr v = mutate(n.vec);
  if (v == n.vec) return self;
  return std::make_shared<Component>(v, n.index, n.loc);
}

Expr Mutator::mutate(const Select& n, const Expr& self) {
  Expr c = mutate(n.condition), a = mutate(n.then), b = mutate(n.otherwise);
  if (c == n.condition && a == n.then && b == n.otherwise) return self;
  return std::make_shared<Select>(n.type, c, a, b, n.loc);
}

Expr Mutator::mutate(const Accumulate& n, const Expr& self) {
  Expr c = mutate(n.condition), b = mutate(n.body);
  if (c == n.condition && b == n.body) return self;
  return std::make_shared<Accumulate>(n.type, n.reduction, n.label, c, b, n.id, n.loc);
}

std::vector<const Accumulate*> accumulations_in(const Expr& e) {
  class Finder : public Visitor {
   public:
    std::vector<const Accumulate*> found;
    using Visitor::visit;

   protected:
    void visit(const Accumulate& n) override {
      found.push_back(&n);
      Visitor::visit(n);
    }
  } finder;
  finder.visit(e);
  return finder.found;
}

std::vector<const Accumulate*> accumulations_in(const Statement& st) {
  std::vector<const Accumulate*> all = accumulations_in(st.value);
  for (const Accumulate* acc : accumulations_in(st.solve_operator)) all.push_back(acc);
  return all;
}

std::set<std::pair<int, int>> variables_read(const Expr& e) {
  class Reads : public Visitor {
   public:
    std::set<std::pair<int, int>> found;
    using Visitor::visit;

   protected:
    void visit(const VarRef& n) override { found.insert({n.set, n.var}); }
  } reads;
  reads.visit(e);
  return reads.found;
}

}  // namespace partc::ir
