#include "ir/constant.hpp"

#include <algorithm>
#include <cmath>

#include "ir/visitor.hpp"

namespace partc {

using namespace ir;

namespace {

// As partc/math.hpp computes them at run time; `type` is the call's.
std::optional<double> apply_function(Function fn, const std::vector<double>& a, Type type) {
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
    case Function::Ceil: return std::ceil(a[0]);
    case Function::Round: return std::round(a[0]);
    case Function::Tan: return std::tan(a[0]);
    case Function::Asin: return std::asin(a[0]);
    case Function::Acos: return std::acos(a[0]);
    case Function::Atan: return std::atan(a[0]);
    case Function::Atan2: return std::atan2(a[0], a[1]);
    case Function::Tanh: return std::tanh(a[0]);
    case Function::Sign: return double((a[0] > 0) - (a[0] < 0));
    case Function::Clamp: return a[0] < a[1] ? a[1] : a[0] > a[2] ? a[2] : a[0];
    case Function::Mod:
      if (type == Type::Int && a[1] == 0) return 0.0;
      return a[0] - a[1] * std::floor(a[0] / a[1]);
    case Function::Dot:
    case Function::Norm:
    case Function::Cross: return std::nullopt;  // vector arguments
  }
  return std::nullopt;
}

std::optional<double> apply_binary(BinaryOp op, double a, double b) {
  switch (op) {
    case BinaryOp::Add: return a + b;
    case BinaryOp::Sub: return a - b;
    case BinaryOp::Mul: return a * b;
    case BinaryOp::Div: return a / b;
    case BinaryOp::FloorDiv: return b == 0 ? 0.0 : std::floor(a / b);
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
  if (auto s = as<Select>(e)) {
    auto c = evaluate_constant(s->condition, model);
    if (!c) return std::nullopt;
    return evaluate_constant(*c != 0 ? s->then : s->otherwise, model);
  }
  if (auto c = as<Call>(e)) {
    std::vector<double> args;
    for (const Expr& a : c->args) {
      auto v = evaluate_constant(a, model);
      if (!v) return std::nullopt;
      args.push_back(*v);
    }
    return apply_function(c->fn, args, c->type);
  }
  return std::nullopt;
}

bool is_uniform(const Expr& e) {
  FindsNonUniform finder;
  finder.visit(e);
  return !finder.found;
}

}  // namespace partc
