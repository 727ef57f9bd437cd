// Expression printing with C++ precedence: parentheses only where needed,
// so generated code reads like the .part line it came from.
#include "codegen/expression.hpp"

#include <fmt/format.h>

#include <cmath>

#include "codegen/names.hpp"
#include "ir/constant.hpp"
#include "support/diagnostics.hpp"

namespace partc::codegen {

namespace {

using namespace ir;

// C++ precedence levels, higher binds tighter.
enum Precedence {
  kConditional = 2,
  kOr = 4,
  kAnd = 5,
  kEquality = 9,
  kRelational = 10,
  kAdditive = 12,
  kMultiplicative = 13,
  kUnary = 15,
  kPrimary = 16
};

struct Printed {
  std::string text;
  int precedence;
};

int precedence_of(BinaryOp op) {
  switch (op) {
    case BinaryOp::Add:
    case BinaryOp::Sub: return kAdditive;
    case BinaryOp::Mul:
    case BinaryOp::Div:
    case BinaryOp::FloorDiv: return kMultiplicative;
    case BinaryOp::Lt:
    case BinaryOp::Le:
    case BinaryOp::Gt:
    case BinaryOp::Ge: return kRelational;
    case BinaryOp::Eq:
    case BinaryOp::Ne: return kEquality;
    case BinaryOp::And: return kAnd;
    case BinaryOp::Or: return kOr;
  }
  return kPrimary;
}

const char* cpp_operator(BinaryOp op) {
  switch (op) {
    case BinaryOp::And: return "&&";
    case BinaryOp::Or: return "||";
    default: return binary_op_spelling(op);
  }
}

class Printer {
 public:
  Printer(const Model& model, const ExpressionNames& names) : model_(model), names_(names) {}

  std::string at_least(const Expr& e, int precedence) {
    Printed p = print(e);
    return p.precedence < precedence ? "(" + p.text + ")" : p.text;
  }

  Printed print(const Expr& e) {
    switch (e->kind) {
      case ExprKind::Literal: return {emit_literal(e->type, *as<Literal>(e)), kPrimary};
      case ExprKind::ParamRef: return {names_.params.at(as<ParamRef>(e)->param), kPrimary};
      case ExprKind::ConstRef: return {names_.consts[as<ConstRef>(e)->constant], kPrimary};
      case ExprKind::ObservableRef:
        return {names_.observables.at(as<ObservableRef>(e)->observable), kPrimary};
      case ExprKind::VarRef: {
        auto v = as<VarRef>(e);
        return {emit_load(model_, v->set, v->var,
                          names_.array(v->set, v->var) + "[" + names_.labels[v->label] + "]"),
                kPrimary};
      }
      case ExprKind::Dx: return {"dx", kPrimary};
      case ExprKind::Unary: return unary(*as<Unary>(e));
      case ExprKind::Binary: return binary(*as<Binary>(e));
      case ExprKind::Call: return call(*as<Call>(e));
      case ExprKind::MakeVec: return {make_vec(as<MakeVec>(e)->components), kPrimary};
      case ExprKind::Component: {
        auto c = as<Component>(e);
        return {at_least(c->vec, kPrimary) + "[" + std::to_string(c->index) + "]", kPrimary};
      }
      case ExprKind::Random: return {random(*as<Random>(e)), kPrimary};
      case ExprKind::Accumulate: return {names_.accumulators.at(as<Accumulate>(e)->id), kPrimary};
      case ExprKind::FnArg: return {cpp_name(as<FnArg>(e)->name), kPrimary};
      case ExprKind::Select: {
        auto c = as<Select>(e);
        return {at_least(c->condition, kOr) + " ? " + branch(c->then, c->type) + " : " +
                    branch(c->otherwise, c->type),
                kConditional};
      }
      case ExprKind::FnCall: {
        auto c = as<FnCall>(e);
        std::vector<std::string> args;  // an int passed for a real converts in the call
        for (const Expr& a : c->args) args.push_back(print(a).text);
        return {fmt::format("{}({})", names_.functions[c->fn], fmt::join(args, ", ")), kPrimary};
      }
    }
    internal_error("emit_expression: unknown expression kind");
  }

 private:
  Printed unary(const Unary& n) {
    std::string operand = at_least(n.operand, kUnary);
    if (n.op == UnaryOp::Not) return {"!" + operand, kUnary};
    if (operand[0] == '-') operand = "(" + operand + ")";  // never "--x"
    return {"-" + operand, kUnary};
  }

  // True when C++ types e as a 32-bit int: an int literal, or a conditional
  // of them. Everything else int in generated code is std::int64_t.
  static bool is_cpp_int(const Expr& e) {
    if (e->type != Type::Int) return false;
    if (as<Literal>(e)) return true;
    auto c = as<Select>(e);
    return c && is_cpp_int(c->then) && is_cpp_int(c->otherwise);
  }

  // A branch of c ? a : b, converted to the result's type: an int branch
  // beside a real one must not make C++ pick a type of its own.
  std::string branch(const Expr& e, Type type) {
    if (e->type == Type::Int && type == Type::Real) {
      if (auto lit = as<Literal>(e)) return emit_literal(Type::Real, lit->value);
      return "static_cast<double>(" + print(e).text + ")";
    }
    return at_least(e, kConditional);
  }

  Printed binary(const Binary& n) {
    if (n.op == BinaryOp::FloorDiv)
      return {fmt::format("partc::floor_div({}, {})", print(n.lhs).text, print(n.rhs).text),
              kPrimary};
    const int p = precedence_of(n.op);
    std::string lhs = at_least(n.lhs, p);
    // Sema folds literal op literal; a literal beside if(c, 100000, 3) would
    // still be C++ int arithmetic, which overflows: one side made 64-bit.
    if (n.type == Type::Int && is_cpp_int(n.lhs) && is_cpp_int(n.rhs))
      lhs = "std::int64_t{" + print(n.lhs).text + "}";
    // int / int is real division in .part.
    if (n.op == BinaryOp::Div && n.lhs->type == Type::Int && n.rhs->type == Type::Int)
      lhs = "static_cast<double>(" + print(n.lhs).text + ")";
    return {lhs + " " + cpp_operator(n.op) + " " + at_least(n.rhs, p + 1), p};
  }

  Printed call(const Call& n) {
    std::vector<std::string> args;
    for (const Expr& a : n.args) args.push_back(print(a).text);
    if (is_norm_of_dx(n) && !names_.dx_norm.empty())
      return {names_.dx_norm, kPrimary};
    // pow(x, k) for a small integer literal k: multiplications, as hand-written kernels do.
    if (n.fn == Function::Pow) {
      const std::optional<double> k = evaluate_constant(n.args[1], model_);
      if (k && *k == std::floor(*k) && std::abs(*k) <= 32)
        return {fmt::format("partc::ipow<{}>({})", static_cast<int>(*k), args[0]), kPrimary};
    }
    switch (n.fn) {
      case Function::Dot: return {fmt::format("partc::dot({}, {})", args[0], args[1]), kPrimary};
      case Function::Norm: return {fmt::format("partc::norm({})", args[0]), kPrimary};
      case Function::Min:
      case Function::Max:
        return {fmt::format("std::{}<{}>({}, {})", function_name(n.fn), cpp_type(n.type), args[0],
                            args[1]),
                kPrimary};
      // partc/math.hpp and partc/vec.hpp: the same for ints and reals, as .part means them.
      case Function::Sign:
      case Function::Mod:
      case Function::Cross:
        return {fmt::format("partc::{}({})", function_name(n.fn), fmt::join(args, ", ")), kPrimary};
      case Function::Clamp:
        return {fmt::format("partc::clamp<{}>({})", cpp_type(n.type), fmt::join(args, ", ")),
                kPrimary};
      default:
        return {fmt::format("std::{}({})", function_name(n.fn), fmt::join(args, ", ")), kPrimary};
    }
  }

  std::string make_vec(const std::vector<Expr>& components) {
    std::vector<std::string> parts;
    for (const Expr& c : components) {
      if (auto lit = as<Literal>(c)) {
        parts.push_back(emit_literal(Type::Real, lit->value));
      } else if (c->type == Type::Int) {
        parts.push_back("static_cast<double>(" + print(c).text + ")");  // no narrowing in {}
      } else {
        parts.push_back(print(c).text);
      }
    }
    return fmt::format("Vec{{{{{}}}}}", fmt::join(parts, ", "));
  }

  std::string random(const Random& n) {
    const char* draw = n.distribution == Distribution::Uniform ? "uniform" : "normal";
    const std::string id = names_.array(names_.home_set, kId) + "[" + names_.labels[0] + "]";
    // An effect's draws come from its own key (the instance name's hash).
    const std::string rng =
        n.owner.empty() ? "rng_"
                        : fmt::format("rng_.keyed(0x{:016x}ULL /* {} */)", fnv1a64(n.owner),
                                      n.owner);
    auto one = [&](int k) {
      return fmt::format("{}.{}({}, step_, {}, {})", rng, draw, id, n.stream, k);
    };
    if (n.type != Type::Vec) return one(0);
    std::vector<std::string> parts;
    for (int k = 0; k < model_.dim; ++k) parts.push_back(one(k));
    return fmt::format("Vec{{{{{}}}}}", fmt::join(parts, ", "));
  }

  const Model& model_;
  const ExpressionNames& names_;
};

}  // namespace

namespace {

// Beyond 32 bits, typed as the model's ints: an LL literal beside an
// std::int64_t (long) would make a call's template deduction ambiguous.
std::string emit_int(std::int64_t v) {
  if (v == std::numeric_limits<std::int64_t>::min()) return "std::numeric_limits<std::int64_t>::min()";
  const bool small = v >= std::numeric_limits<std::int32_t>::min() + 1 &&
                     v <= std::numeric_limits<std::int32_t>::max();
  return small ? std::to_string(v) : "std::int64_t{" + std::to_string(v) + "}";
}

}  // namespace

std::string emit_literal(Type type, const Literal& lit) {
  if (type != Type::Int || lit.type != Type::Int) return emit_literal(type, lit.value);
  return emit_int(lit.integer);
}

std::string emit_literal(Type type, double value) {
  switch (type) {
    case Type::Bool: return value != 0 ? "true" : "false";
    case Type::Int: return emit_int(static_cast<std::int64_t>(value));
    case Type::Real:
    case Type::Vec: {
      if (std::isinf(value))
        return value > 0 ? "std::numeric_limits<double>::infinity()"
                         : "-std::numeric_limits<double>::infinity()";
      std::string text = fmt::format("{}", value);  // shortest text that round-trips
      if (text.find_first_of(".en") == std::string::npos) text += ".0";
      return text;
    }
  }
  return "?";
}

std::string cpp_type(Type type) {
  switch (type) {
    case Type::Bool: return "bool";
    case Type::Int: return "std::int64_t";
    case Type::Real: return "double";
    case Type::Vec: return "Vec";
  }
  return "?";
}

std::string emit_load(const Model& model, int set, int var, const std::string& element) {
  if (model.sets[set].vars[var].storage == Precision::Double) return element;
  return "partc::widen(" + element + ")";
}

std::string emit_expression(const Expr& e, const Model& model, const ExpressionNames& names) {
  return Printer(model, names).print(e).text;
}

}  // namespace partc::codegen

namespace partc::codegen {

std::string emit_operand(const ir::Expr& e, ir::BinaryOp operand_of, const ir::Model& model,
                         const ExpressionNames& names) {
  return Printer(model, names).at_least(e, precedence_of(operand_of) + 1);
}

}  // namespace partc::codegen
