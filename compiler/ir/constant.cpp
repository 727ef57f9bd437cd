#include "ir/constant.hpp"

#include <algorithm>
#include <cmath>

#include "ir/visitor.hpp"

namespace partc {

using namespace ir;

namespace {

std::optional<double> apply_function(Function fn, const std::vector<double>& a) {
  switch (fn) {
    case Function::Exp: return std::exp(a[0]);
    case Function::Log: return std::log(a[0]);
    case Function::Sqrt: return std::sqrt(a[0]);
    case Function::Pow: return std::pow(a[0], a[1]);
    case Function::Abs: return std::abs(a[0]);
    case Function::Min: return std::min(a[0], a[1]);
    case Function::Max: return std::max(a[0], a[1]);
    case Function::Floor: return std::floor(a[0]);
    case Function::Sin: return std::sin(a[0]);
    case Function::Cos: return std::cos(a[0]);
    case Function::Dot:
    case Function::Norm: return std::nullopt;  // vector arguments
  }
  return std::nullopt;
}

std::optional<double> apply_binary(BinaryOp op, double a, double b) {
  switch (op) {
    case BinaryOp::Add: return a + b;
    case BinaryOp::Sub: return a - b;
    case BinaryOp::Mul: return a * b;
    case BinaryOp::Div: return a / b;
    case BinaryOp::Lt: return a < b;
    case BinaryOp::Le: return a <= b;
    case BinaryOp::Gt: return a > b;
    case BinaryOp::Ge: return a >= b;
    case BinaryOp::Eq: return a == b;
    case BinaryOp::Ne: return a != b;
    case BinaryOp::And: return a != 0 && b != 0;
    case BinaryOp::Or: return a != 0 || b != 0;
  }
  return std::nullopt;
}

class FindsNonUniform : public Visitor {
 public:
  bool found = false;

 public:
  using Visitor::visit;

 protected:
  void visit(const VarRef&) override { found = true; }
  void visit(const Dx&) override { found = true; }
  void visit(const Random&) override { found = true; }
  void visit(const Accumulate&) override { found = true; }
};

}  // namespace

std::optional<double> evaluate_constant(const Expr& e, const Model& model) {
  if (e->type == Type::Vec) return std::nullopt;
  if (auto lit = as<Literal>(e)) return lit->value;
  if (auto ref = as<ConstRef>(e)) return evaluate_constant(model.consts[ref->constant].value, model);
  if (auto u = as<Unary>(e)) {
    auto a = evaluate_constant(u->operand, model);
    if (!a) return std::nullopt;
    return u->op == UnaryOp::Neg ? -*a : double(*a == 0);
  }
  if (auto b = as<Binary>(e)) {
    if (b->lhs->type == Type::Vec || b->rhs->type == Type::Vec) return std::nullopt;
    auto l = evaluate_constant(b->lhs, model);
    auto r = evaluate_constant(b->rhs, model);
    if (!l || !r) return std::nullopt;
    return apply_binary(b->op, *l, *r);
  }
  if (auto c = as<Call>(e)) {
    std::vector<double> args;
    for (const Expr& a : c->args) {
      auto v = evaluate_constant(a, model);
      if (!v) return std::nullopt;
      args.push_back(*v);
    }
    return apply_function(c->fn, args);
  }
  return std::nullopt;
}

bool is_uniform(const Expr& e) {
  FindsNonUniform finder;
  finder.visit(e);
  return !finder.found;
}

}  // namespace partc
