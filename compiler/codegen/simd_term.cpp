// Each node becomes one named vector (or a mask, for a condition), declared
// once: a node printed the same twice (|dx| in the condition and the term)
// reuses the first. A vec is a vector per component, with an optional
// common factor: s * dx / r is kept as (s / r) times dx's components, one
// division for the pair instead of one per component (in the seed's term
// that was a third of the time), and applied only when a component is
// needed. Results differ from the scalar walk's by a few roundings: Highway's
// exp and log are within a few ulp, and the factor changes the order.
//
// On float lanes (arithmetic = float) the same nodes are emitted over a tag
// of floats: the walk's dx and |dx|^2 are loaded rounded to float, variables
// gathered in their storage and converted (partc/simd/float_lanes.hpp), and
// numbers broadcast as floats; each condition is decided on double lanes
// (see emit_simd_terms), and a term's |dx| is then the condition's, rounded.
#include "codegen/simd_term.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <map>
#include <optional>

#include "codegen/names.hpp"
#include "ir/constant.hpp"
#include "ir/inline_calls.hpp"
#include "support/diagnostics.hpp"

namespace partc::codegen {

namespace {

using namespace ir;

// A vec: components, times factor when there is one.
struct VecValue {
  std::string factor;
  std::vector<std::string> components;
};

class Emitter {
 public:
  // The emitters of one loop share `locals`, so their temporaries' names differ.
  Emitter(const Model& model, const ExpressionNames& names, NameTable& locals, std::string batch,
          std::string k, std::string tag, bool floats)
      : model_(model),
        names_(names),
        locals_(locals),
        batch_(std::move(batch)),
        k_(std::move(k)),
        d_(std::move(tag)),
        floats_(floats) {}

  // Later loads from pair k on (the second half of a float vector's pairs).
  Emitter& at(const std::string& k) {
    k_ = k;
    return *this;
  }
  // The local holding |dx| from pair k on, if computed already; else "".
  std::string computed_norm_of_dx() const {
    const auto r2 = declared_.find(walk_column("r2()"));
    if (r2 == declared_.end()) return "";
    const auto norm = declared_.find(fmt::format("hn::Sqrt({})", r2->second));
    return norm == declared_.end() ? "" : norm->second;
  }
  // |dx| as this value, when a term needs it (on float lanes: the double
  // condition's, rounded once, rather than a square root of r2 rounded).
  void give_norm_of_dx(const std::string& value) { given_norm_of_dx_ = value; }

  std::vector<std::string> setup;  // before the loop: the broadcasts
  std::vector<std::string> lines;  // in it

  std::string real(const Expr& e) {
    switch (e->kind) {
      case ExprKind::Literal: return broadcast(literal(as<Literal>(e)->value));
      case ExprKind::ParamRef:
        return broadcast(as_lane(names_.params.at(as<ParamRef>(e)->param), e->type));
      case ExprKind::ConstRef:
        return broadcast(as_lane(names_.consts[as<ConstRef>(e)->constant], e->type));
      case ExprKind::ObservableRef:
        return broadcast(as_lane(names_.observables.at(as<ObservableRef>(e)->observable), e->type));
      case ExprKind::VarRef: return variable(*as<VarRef>(e)).components[0];
      case ExprKind::Unary: return declare(fmt::format("hn::Neg({})", real(as<Unary>(e)->operand)));
      case ExprKind::Binary: return real_binary(*as<Binary>(e));
      case ExprKind::Call: return real_call(*as<Call>(e));
      case ExprKind::Component: {
        auto c = as<Component>(e);
        return component(vec(c->vec), c->index);
      }
      case ExprKind::Select: {
        auto s = as<Select>(e);
        return declare(fmt::format("hn::IfThenElse({}, {}, {})", mask(s->condition), real(s->then),
                                   real(s->otherwise)));
      }
      default: internal_error("simd_term: no vector form for a real node");
    }
  }

  VecValue vec(const Expr& e) {
    switch (e->kind) {
      case ExprKind::Dx: return dx();
      case ExprKind::VarRef: return variable(*as<VarRef>(e));
      case ExprKind::MakeVec: {
        VecValue v;
        for (const Expr& c : as<MakeVec>(e)->components) v.components.push_back(real(c));
        return v;
      }
      case ExprKind::Unary: {
        VecValue v = vec(as<Unary>(e)->operand);
        if (!v.factor.empty())
          v.factor = declare(fmt::format("hn::Neg({})", v.factor));
        else
          for (auto& c : v.components) c = declare(fmt::format("hn::Neg({})", c));
        return v;
      }
      case ExprKind::Binary: return vec_binary(*as<Binary>(e));
      case ExprKind::Select: {
        auto s = as<Select>(e);
        const std::string when = mask(s->condition);
        const VecValue a = vec(s->then), b = vec(s->otherwise);
        VecValue v;
        for (int c = 0; c < model_.dim; ++c)
          v.components.push_back(declare(
              fmt::format("hn::IfThenElse({}, {}, {})", when, component(a, c), component(b, c))));
        return v;
      }
      default: internal_error("simd_term: no vector form for a vec node");
    }
  }

  std::string mask(const Expr& e) {
    if (auto lit = as<Literal>(e))
      return declare(lit->value != 0 ? fmt::format("hn::Eq(hn::Zero({0}), hn::Zero({0}))", d_)
                                     : fmt::format("hn::Lt(hn::Zero({0}), hn::Zero({0}))", d_));
    if (e->kind == ExprKind::ParamRef || e->kind == ExprKind::ConstRef ||
        e->kind == ExprKind::ObservableRef)
      return declare(fmt::format("hn::Ne({}, hn::Zero({}))", real(e), d_));
    if (auto u = as<Unary>(e)) return declare(fmt::format("hn::Not({})", mask(u->operand)));
    if (auto s = as<Select>(e))  // if(c, a, b) of conditions: (c and a) or (not c and b)
      return declare(fmt::format("hn::Or(hn::And({0}, {1}), hn::AndNot({0}, {2}))",
                                 mask(s->condition), mask(s->then), mask(s->otherwise)));
    auto b = as<Binary>(e);
    if (!b) internal_error("simd_term: no vector form for a condition");
    if (b->op == BinaryOp::And || b->op == BinaryOp::Or)
      return declare(fmt::format("hn::{}({}, {})", b->op == BinaryOp::And ? "And" : "Or",
                                 mask(b->lhs), mask(b->rhs)));
    static const std::map<BinaryOp, const char*> compare = {
        {BinaryOp::Lt, "Lt"}, {BinaryOp::Le, "Le"}, {BinaryOp::Gt, "Gt"},
        {BinaryOp::Ge, "Ge"}, {BinaryOp::Eq, "Eq"}, {BinaryOp::Ne, "Ne"}};
    return declare(fmt::format("hn::{}({}, {})", compare.at(b->op), real(b->lhs), real(b->rhs)));
  }

  // c of v, its factor applied.
  std::string component(const VecValue& v, int c) {
    if (v.factor.empty()) return v.components[c];
    return declare(fmt::format("hn::Mul({}, {})", v.factor, v.components[c]));
  }

  std::string declare(const std::string& value) {
    auto [it, fresh] = declared_.emplace(value, "");
    if (fresh) {
      it->second = locals_.fresh(temporary_name(value));
      lines.push_back(fmt::format("const auto {} = {};", it->second, value));
    }
    return it->second;
  }

 private:
  // What a temporary holds, from the operation computing it (quotient,
  // masked, below; variable() names its gathers, rho_j); NameTable::fresh
  // numbers repeats.
  static std::string temporary_name(const std::string& value) {
    static const std::map<std::string, const char*> nouns = {
        {"Neg", "minus"},        {"Add", "sum"},         {"Sub", "difference"},
        {"Mul", "product"},      {"MulAdd", "dot"},      {"Div", "quotient"},
        {"Exp", "exponential"},  {"Log", "logarithm"},   {"Sqrt", "root"},
        {"Abs", "magnitude"},    {"Min", "least"},       {"Max", "greatest"},
        {"Tanh", "tanh_value"},  {"Sin", "sine"},        {"Cos", "cosine"},
        {"Lt", "below"},         {"Le", "at_most"},      {"Gt", "above"},
        {"Ge", "at_least"},      {"Eq", "equal"},        {"Ne", "unequal"},
        {"And", "both"},         {"Or", "either"},       {"Not", "negation"},
        {"IfThenElse", "chosen"}, {"IfThenElseZero", "masked"}};
    const std::string hn = "hn::";
    if (value.rfind(hn, 0) == 0) {
      const auto noun = nouns.find(value.substr(hn.size(), value.find('(') - hn.size()));
      if (noun != nouns.end()) return noun->second;
    }
    if (value.rfind("partc::simd::demote_mask(", 0) == 0) return "condition";
    return "value";
  }

  // A named vector loaded or computed once per vector of pairs (dx_0, r2, ...).
  std::string named(const std::string& name, const std::string& value) {
    auto [it, fresh] = declared_.emplace(value, "");
    if (fresh) {
      it->second = locals_.fresh(name);
      lines.push_back(fmt::format("const auto {} = {};", it->second, value));
    }
    return it->second;
  }
  // A number the same for every pair, in every lane: set once, before the
  // loop, named after the scalar when it has a name (rc: rc_lanes).
  std::string broadcast(const std::string& scalar) {
    const std::string value = fmt::format("hn::Set({}, {})", d_, scalar);
    auto [it, fresh] = declared_.emplace(value, "");
    if (fresh) {
      const std::string name = named_scalar(scalar);
      it->second = locals_.fresh(!name.empty() ? name + "_lanes" : "constant");
      setup.push_back(fmt::format("const auto {} = {};", it->second, value));
    }
    return it->second;
  }
  // The name a broadcast value is of (rc, or rc in static_cast<float>(rc)); "" for a number.
  static std::string named_scalar(const std::string& scalar) {
    const std::string cast = "static_cast<float>(";
    const std::string name = scalar.rfind(cast, 0) == 0
                                 ? scalar.substr(cast.size(), scalar.size() - cast.size() - 1)
                                 : scalar;
    const bool is_name = !name.empty() &&
                         (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
                         name.find_first_of("(<:.") == std::string::npos;
    return is_name ? name : "";
  }
  // A scalar of the model as a lane's value: a double, or a float on float lanes.
  std::string as_lane(const std::string& name, Type type) const {
    if (floats_) return "static_cast<float>(" + name + ")";
    return type == Type::Real ? name : "static_cast<double>(" + name + ")";
  }
  // A literal in the lanes' type: on float lanes the float nearest to it.
  std::string literal(double value) const {
    if (!floats_ || !std::isfinite(value))
      return as_lane(emit_literal(Type::Real, value), Type::Real);
    std::string text = fmt::format("{}", static_cast<float>(value));  // shortest round trip
    if (text.find_first_of(".e") == std::string::npos) text += ".0";
    return text + "f";
  }
  // A column of the walk's (dx, r2) from k, in the lanes' type.
  std::string walk_column(const std::string& column) const {
    return floats_ ? fmt::format("partc::simd::load_demoted({}.{} + {})", batch_, column, k_)
                   : fmt::format("hn::LoadU({}, {}.{} + {})", d_, batch_, column, k_);
  }

  VecValue dx() {
    VecValue v;
    for (int c = 0; c < model_.dim; ++c)
      v.components.push_back(
          named("dx_" + std::to_string(c), walk_column(fmt::format("dx({})", c))));
    return v;
  }
  std::string squared_norm_of_dx() { return named("r2", walk_column("r2()")); }
  std::string norm_of_dx() {
    return named("dx_norm", given_norm_of_dx_.empty()
                                ? fmt::format("hn::Sqrt({})", squared_norm_of_dx())
                                : given_norm_of_dx_);
  }

  // The particle's index per lane, as signed integers for gathers (as wide
  // as the lanes); times the dimension for a vec's components (repeated adds:
  // no 64-bit multiply everywhere).
  std::string index(int label, int scale) {
    const std::string of = label == 0 ? "i" : "j";
    std::string lanes =
        named(of + "_lanes",
              fmt::format("partc::simd::index_lanes({}, {}.{}() + {})", d_, batch_, of, k_));
    if (scale == 1) return lanes;
    std::string scaled = lanes;
    for (int s = 1; s < scale; ++s)
      scaled = named(of + "_lanes_x" + std::to_string(s + 1),
                     fmt::format("hn::Add({}, {})", scaled, lanes));
    return scaled;
  }

  // Gathered from its storage (float or double) into the lanes' type.
  VecValue variable(const VarRef& v) {
    const Variable& var = model_.sets[v.set].vars[v.var];
    const std::string array = names_.array(v.set, v.var);
    const std::string of = v.label == 0 ? "i" : "j";  // rho_j, v_i_0
    VecValue value;
    if (var.type == Type::Real) {
      value.components.push_back(named(
          array + "_" + of, fmt::format("partc::simd::gather({}, {}.data(), {})", d_, array,
                                        index(v.label, 1))));
      return value;
    }
    const std::string at = index(v.label, model_.dim);
    for (int c = 0; c < model_.dim; ++c) {
      const std::string offset =
          c == 0 ? at
                 : named(at + "_" + std::to_string(c),
                         fmt::format("hn::Add({}, hn::Set(hn::RebindToSigned<decltype({})>(), {}))",
                                     at, d_, c));
      value.components.push_back(named(
          array + "_" + of + "_" + std::to_string(c),
          fmt::format("partc::simd::gather({}, reinterpret_cast<const {}*>({}.data()), {})", d_,
                      precision_name(var.storage), array, offset)));
    }
    return value;
  }

  std::string real_binary(const Binary& b) {
    static const std::map<BinaryOp, const char*> ops = {{BinaryOp::Add, "Add"},
                                                        {BinaryOp::Sub, "Sub"},
                                                        {BinaryOp::Mul, "Mul"},
                                                        {BinaryOp::Div, "Div"}};
    return declare(fmt::format("hn::{}({}, {})", ops.at(b.op), real(b.lhs), real(b.rhs)));
  }

  VecValue vec_binary(const Binary& b) {
    const bool lhs_vec = b.lhs->type == Type::Vec, rhs_vec = b.rhs->type == Type::Vec;
    if (lhs_vec && rhs_vec) {  // + or -: componentwise
      const VecValue a = vec(b.lhs), c = vec(b.rhs);
      VecValue v;
      for (int k = 0; k < model_.dim; ++k)
        v.components.push_back(
            declare(fmt::format("hn::{}({}, {})", b.op == BinaryOp::Add ? "Add" : "Sub",
                                component(a, k), component(c, k))));
      return v;
    }
    // A scalar times or over a vec: into the factor.
    VecValue v = vec(lhs_vec ? b.lhs : b.rhs);
    const std::string s = real(lhs_vec ? b.rhs : b.lhs);
    if (b.op == BinaryOp::Mul)
      v.factor = v.factor.empty() ? s : declare(fmt::format("hn::Mul({}, {})", s, v.factor));
    else  // vec / scalar
      v.factor = declare(
          fmt::format("hn::Div({}, {})", v.factor.empty() ? broadcast("1.0") : v.factor, s));
    return v;
  }

  std::string dot(const VecValue& a, const VecValue& b) {
    std::string sum = declare(fmt::format("hn::Mul({}, {})", a.components[0], b.components[0]));
    for (int c = 1; c < model_.dim; ++c)
      sum = declare(fmt::format("hn::MulAdd({}, {}, {})", a.components[c], b.components[c], sum));
    if (!a.factor.empty()) sum = declare(fmt::format("hn::Mul({}, {})", a.factor, sum));
    if (!b.factor.empty()) sum = declare(fmt::format("hn::Mul({}, {})", b.factor, sum));
    return sum;
  }

  // x^k by repeated squaring, as partc::ipow does.
  std::string power(const std::string& x, int k) {
    if (k == 0) return broadcast("1.0");
    std::string result, square = x;
    for (int n = std::abs(k); n > 0; n >>= 1) {
      if (n & 1)
        result = result.empty() ? square : declare(fmt::format("hn::Mul({}, {})", result, square));
      if (n > 1) square = declare(fmt::format("hn::Mul({0}, {0})", square));
    }
    return k < 0 ? declare(fmt::format("hn::Div({}, {})", broadcast("1.0"), result)) : result;
  }

  std::string real_call(const Call& n) {
    if (is_norm_of_dx(n)) return norm_of_dx();
    if (is_squared_norm_of_dx(n)) return squared_norm_of_dx();
    switch (n.fn) {
      case Function::Exp:
      case Function::Log:
      case Function::Tanh:
      case Function::Sin:
      case Function::Cos: {
        static const std::map<Function, const char*> math = {{Function::Exp, "Exp"},
                                                             {Function::Log, "Log"},
                                                             {Function::Tanh, "Tanh"},
                                                             {Function::Sin, "Sin"},
                                                             {Function::Cos, "Cos"}};
        return declare(fmt::format("hn::{}({}, {})", math.at(n.fn), d_, real(n.args[0])));
      }
      case Function::Sqrt: return declare(fmt::format("hn::Sqrt({})", real(n.args[0])));
      case Function::Abs: return declare(fmt::format("hn::Abs({})", real(n.args[0])));
      case Function::Min:
      case Function::Max:
        return declare(fmt::format("hn::{}({}, {})", n.fn == Function::Min ? "Min" : "Max",
                                   real(n.args[0]), real(n.args[1])));
      case Function::Pow:
        return power(real(n.args[0]), static_cast<int>(*evaluate_constant(n.args[1], model_)));
      case Function::Dot: return dot(vec(n.args[0]), vec(n.args[1]));
      case Function::Norm: {
        const VecValue v = vec(n.args[0]);
        return declare(fmt::format("hn::Sqrt({})", dot(v, v)));
      }
      default: internal_error("simd_term: no vector form for a call");
    }
  }

  const Model& model_;
  const ExpressionNames& names_;
  NameTable& locals_;
  const std::string batch_;
  std::string k_;
  const std::string d_;
  const bool floats_;                            // float lanes (arithmetic = float), else double
  std::map<std::string, std::string> declared_;  // value -> its local
  std::string given_norm_of_dx_;
};

}  // namespace

SimdTermCode emit_simd_terms(const std::vector<const Accumulate*>& accs, const Model& model,
                             const ExpressionNames& names, NameTable& locals,
                             const std::string& batch, const std::string& k, const std::string& tag,
                             Precision arithmetic) {
  const bool floats = arithmetic == Precision::Float;
  Emitter emit(model, names, locals, batch, k, tag, floats);
  // On float lanes each condition is still decided on double lanes, for the
  // two vectors of doubles a vector of floats covers, so that the pairs that
  // count are the ones double arithmetic counts: a float comparison moves a
  // cutoff by up to an ulp of float (on the seed at N = 10^6, ten draws of the
  // points: one pair counted otherwise, a whole term wrong).
  const std::string wide = floats ? locals.fresh("wide") : "";
  const std::string k_high = floats ? locals.fresh(k + "_high") : "";
  Emitter decide(model, names, locals, batch, k, wide, false);
  SimdTermCode code;
  if (floats) {
    code.setup.push_back(fmt::format("const partc::simd::Real {};", wide));
    code.lines.push_back(
        fmt::format("const std::size_t {} = {} + hn::Lanes({});", k_high, k, wide));
  }
  for (const Accumulate* acc : accs) {
    // User functions as their bodies (analysis/vector_terms.cpp judged these).
    const Expr condition = acc->condition ? inline_calls(acc->condition, model) : nullptr;
    const Expr body = inline_calls(acc->body, model);
    if ((acc->condition && !condition) || !body) internal_error("simd_term: a call not inlined");
    std::string when;
    if (condition && floats) {
      const std::string low = decide.at(k).mask(condition);
      const std::string low_norm = decide.computed_norm_of_dx();
      const std::string high = decide.at(k_high).mask(condition);
      const std::string high_norm = decide.computed_norm_of_dx();
      when = emit.declare(fmt::format("partc::simd::demote_mask({}, {})", low, high));
      if (!low_norm.empty() && !high_norm.empty())
        emit.give_norm_of_dx(fmt::format("partc::simd::demote({}, {})", low_norm, high_norm));
    } else if (condition) {
      when = emit.mask(condition);
    }
    std::vector<std::string> parts;
    if (acc->type == Type::Real) {
      parts.push_back(emit.real(body));
    } else {
      const VecValue v = emit.vec(body);
      for (int c = 0; c < model.dim; ++c) parts.push_back(emit.component(v, c));
    }
    // Masked after the arithmetic: a NaN where the condition fails (0 / 0 at i's own pair) is
    // dropped.
    if (!when.empty())
      for (std::string& part : parts)
        part = emit.declare(fmt::format("hn::IfThenElseZero({}, {})", when, part));
    code.terms.push_back(parts);
  }
  for (const auto* lines : {&decide.setup, &emit.setup})
    code.setup.insert(code.setup.end(), lines->begin(), lines->end());
  for (const auto* lines : {&decide.lines, &emit.lines})
    code.lines.insert(code.lines.end(), lines->begin(), lines->end());
  return code;
}

}  // namespace partc::codegen
