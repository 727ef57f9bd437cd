// Sema: names, operators, conversions between types.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "ir/constant.hpp"
#include "sema/checker.hpp"

namespace partc::sema {

// The value converted to `to` for storing in `what`, or an error.
Expr Sema::convert(Expr value, Type to, Location at, const std::string& what) {
  const Type from = value->type;
  if (from == to) return value;
  if (from == Type::Int && to == Type::Real) return value;  // C++ promotes
  if (to == Type::Vec && ir::is_numeric_scalar(from)) {
    // Only 0 means the same in every dimension; `v[i] -= dt * g` must not
    // become gravity along the diagonal.
    if (auto lit = ir::as<ir::Literal>(value); lit && lit->value == 0) {
      std::vector<Expr> components(model_.dim, value);
      return std::make_shared<ir::MakeVec>(std::move(components), value->loc);
    }
    const std::string text = source_text(value->loc);
    const std::string factor = ir::as<ir::Binary>(value) ? "(" + text + ")" : text;
    auto components = [&](const std::string& first, const std::string& last) {
      std::string out = "vec(";
      for (int k = 0; k + 1 < model_.dim; ++k) out += first + ", ";
      return out + last + ")";
    };
    fail(at, "cannot store " + a_type(from) + " in " + what + ", which is a vec",
         "a scalar is not spread over the components: write " + components("0", text) +
             " for a vector along one axis, or " + factor + " * " + components("1", "1") +
             " for the same value in each");
  }
  if (from == Type::Real && to == Type::Int)
    fail(at, "cannot store a real in " + what + ", which is an int",
         ir::as<ir::Binary>(value) && ir::as<ir::Binary>(value)->op == ir::BinaryOp::Div
             ? "'/' always gives a real; a // b divides ints, rounding down"
             : "int values are exact: write an int, or divide ints with // (rounding down)");
  fail(at, "cannot store " + a_type(from) + " in " + what + ", which is " + a_type(to));
}

double Sema::constant_number(const Expr& e, Location at, const Scope& scope) {
  if (!ir::is_numeric_scalar(e->type) && e->type != Type::Bool)
    fail(at, scope.context + " must be a number, not " + a_type(e->type));
  auto value = evaluate_constant(e, model_);
  if (!value)
    fail(at, scope.context + " must be known when partc runs",
         "use literals and consts built from literals here, not params");
  if (!std::isfinite(*value)) fail(at, scope.context + " evaluates to " + std::to_string(*value));
  return *value;
}

Expr Sema::check(const ast::Chain& chain, Scope& scope) {
  // The IR is as deep as operators chain and nest; every pass after sema
  // recurses over it, so its depth is bounded here (a 10 MB sum would not be).
  struct Nesting {
    int& depth;
    const int added;
    ~Nesting() { depth -= added; }
  } nesting{expression_depth_, 1 + static_cast<int>(chain.rest.size())};
  expression_depth_ += nesting.added;
  if (expression_depth_ > kMaxExpressionDepth)
    fail(chain.loc, "expression too deep: more than " + std::to_string(kMaxExpressionDepth) +
                        " operators, calls and parentheses nested or in a row",
         "split it with intermediate variables or functions");
  Expr lhs = check(chain.first, scope);
  std::optional<ir::BinaryOp> previous_comparison;
  for (const ast::BinaryOp& step : chain.rest) {
    Expr rhs = check(step.rhs, scope);
    const Location loc{ast::location_of(chain.first).begin, step.loc.end};
    const ir::BinaryOp op = binary_op(step.op);
    const bool comparison = op >= ir::BinaryOp::Lt && op <= ir::BinaryOp::Ne;
    if (comparison && previous_comparison)
      fail(loc, "comparisons do not chain", "write 'a < b and b < c' instead of 'a < b < c'");
    if (comparison) previous_comparison = op;
    lhs = binary(op, lhs, rhs, loc, step.loc);
  }
  return lhs;
}

ir::BinaryOp Sema::binary_op(const std::string& s) {
  static const std::map<std::string, ir::BinaryOp> ops = {
      {"+", ir::BinaryOp::Add}, {"-", ir::BinaryOp::Sub},       {"*", ir::BinaryOp::Mul},
      {"/", ir::BinaryOp::Div}, {"//", ir::BinaryOp::FloorDiv}, {"<", ir::BinaryOp::Lt},
      {"<=", ir::BinaryOp::Le}, {">", ir::BinaryOp::Gt},        {">=", ir::BinaryOp::Ge},
      {"==", ir::BinaryOp::Eq}, {"!=", ir::BinaryOp::Ne},       {"and", ir::BinaryOp::And},
      {"or", ir::BinaryOp::Or}};
  return ops.at(s);
}

// p[j] - p[i] in a periodic domain is not the shortest vector between the
// two particles, and a condition on it bounds no neighbourhood: partc then
// loops over every particle. dx is what the author almost surely meant.
void Sema::warn_if_raw_displacement(const ir::ExprNode& a, const ir::ExprNode& b, Location loc) {
  auto position = [](const ir::ExprNode& e) {
    return e.kind == ir::ExprKind::VarRef && static_cast<const ir::VarRef&>(e).var == ir::kPosition
               ? &static_cast<const ir::VarRef&>(e)
               : nullptr;
  };
  const ir::VarRef *pa = position(a), *pb = position(b);
  if (!pa || !pb || pa->label == pb->label) return;
  const auto& periodic = model_.domain.periodic;
  if (std::find(periodic.begin(), periodic.end(), true) == periodic.end()) return;
  warn(loc, source_text(loc) + " ignores the periodic boundaries",
       "dx is the shortest vector from i to j, across periodic boundaries; a condition on |dx| "
       "also lets partc search only nearby particles");
}

Expr Sema::binary(ir::BinaryOp op, Expr a, Expr b, Location loc, Location op_loc) {
  const Type ta = a->type, tb = b->type;
  const std::string spelled = binary_op_spelling(op);
  auto mismatch = [&](std::string note = {}) -> Expr {
    fail(op_loc, "'" + spelled + "' cannot combine " + a_type(ta) + " and " + a_type(tb),
         std::move(note));
  };
  if (op == ir::BinaryOp::Sub) warn_if_raw_displacement(*a, *b, loc);
  const bool scalars = ir::is_numeric_scalar(ta) && ir::is_numeric_scalar(tb);
  const Type numeric = ta == Type::Int && tb == Type::Int ? Type::Int : Type::Real;
  Type result = Type::Bool;
  switch (op) {
    case ir::BinaryOp::Add:
    case ir::BinaryOp::Sub:
      if (scalars)
        result = numeric;
      else if (ta == Type::Vec && tb == Type::Vec)
        result = Type::Vec;
      else
        return mismatch("vectors add only to vectors");
      break;
    case ir::BinaryOp::Mul:
      if (scalars)
        result = numeric;
      else if ((ta == Type::Vec && ir::is_numeric_scalar(tb)) ||
               (tb == Type::Vec && ir::is_numeric_scalar(ta)))
        result = Type::Vec;
      else if (ta == Type::Vec && tb == Type::Vec)
        return mismatch("for the inner product write dot(a, b)");
      else
        return mismatch();
      break;
    case ir::BinaryOp::FloorDiv:
      if (ta != Type::Int || tb != Type::Int)
        return mismatch("'//' divides ints, rounding down; for reals write floor(a / b)");
      no_zero_divisor(b, "'//'");
      result = Type::Int;
      break;
    case ir::BinaryOp::Div:
      // int / int is real division: 3 / N must not silently truncate to 0.
      if (scalars)
        result = Type::Real;
      else if (ta == Type::Vec && ir::is_numeric_scalar(tb))
        result = Type::Vec;
      else
        return mismatch();
      break;
    case ir::BinaryOp::Lt:
    case ir::BinaryOp::Le:
    case ir::BinaryOp::Gt:
    case ir::BinaryOp::Ge:
      if (!scalars)
        return mismatch(
            ta == Type::Vec || tb == Type::Vec ? "compare lengths instead, e.g. |dx| < rc" : "");
      result = Type::Bool;
      break;
    case ir::BinaryOp::Eq:
    case ir::BinaryOp::Ne:
      if (!scalars && !(ta == Type::Bool && tb == Type::Bool)) return mismatch();
      result = Type::Bool;
      break;
    case ir::BinaryOp::And:
    case ir::BinaryOp::Or:
      if (ta != Type::Bool || tb != Type::Bool) return mismatch("'and' and 'or' take bools");
      result = Type::Bool;
      break;
  }
  if (result == Type::Int)
    if (Expr folded = fold_int_literals(op, a, b, loc, op_loc)) return folded;
  return std::make_shared<ir::Binary>(result, op, a, b, loc);
}

// Int arithmetic on two literals is done here, exactly in 64 bits, so that
// the C++ compiler never computes it in 32-bit `int` (100000 * 100000), and
// an overflow is an error at its place rather than wrong code.
Expr Sema::fold_int_literals(ir::BinaryOp op, const Expr& a, const Expr& b, Location loc,
                             Location op_loc) {
  const auto *x = ir::as<ir::Literal>(a), *y = ir::as<ir::Literal>(b);
  if (!x || !y) return nullptr;
  const std::int64_t p = x->integer, q = y->integer;
  std::int64_t r = 0;
  bool overflow = false;
  switch (op) {
    case ir::BinaryOp::Add: overflow = __builtin_add_overflow(p, q, &r); break;
    case ir::BinaryOp::Sub: overflow = __builtin_sub_overflow(p, q, &r); break;
    case ir::BinaryOp::Mul: overflow = __builtin_mul_overflow(p, q, &r); break;
    case ir::BinaryOp::FloorDiv:
      if (q == -1 && p == std::numeric_limits<std::int64_t>::min()) {
        overflow = true;
      } else {
        r = p / q;  // q != 0: no_zero_divisor refused a literal 0
        if ((p % q != 0) && ((p < 0) != (q < 0))) --r;
      }
      break;
    default: return nullptr;
  }
  if (overflow)
    fail(op_loc, "integer overflow: " + std::to_string(p) + " " + binary_op_spelling(op) + " " +
                     std::to_string(q) + " does not fit in 64 bits",
         "ints are 64-bit; for larger numbers write a real, as in 1e20");
  return std::make_shared<ir::Literal>(r, loc);
}

struct Sema::CheckOperand {
  Sema& sema;
  Scope& scope;
  Expr operator()(const ast::IntLiteral& n) const {
    return std::make_shared<ir::Literal>(n.value, n.loc);
  }
  Expr operator()(const ast::RealLiteral& n) const {
    return std::make_shared<ir::Literal>(Type::Real, n.value, n.loc);
  }
  Expr operator()(const ast::BoolLiteral& n) const {
    return std::make_shared<ir::Literal>(Type::Bool, n.value ? 1.0 : 0.0, n.loc);
  }
  Expr operator()(const ast::Identifier& n) const { return sema.check_name(n, scope); }
  Expr operator()(const ast::Indexed& n) const { return sema.check_indexed(n, scope); }
  Expr operator()(const ast::Call& n) const { return sema.check_call(n, scope); }
  Expr operator()(const ast::Norm& n) const {
    Expr inner = sema.check(n.inner, scope);
    if (inner->type == Type::Vec)
      return std::make_shared<ir::Call>(Type::Real, ir::Function::Norm, std::vector<Expr>{inner},
                                        n.loc);
    if (ir::is_numeric_scalar(inner->type))
      return std::make_shared<ir::Call>(inner->type, ir::Function::Abs, std::vector<Expr>{inner},
                                        n.loc);
    fail(n.loc, "|...| needs a number or a vec, not a bool");
  }
  Expr operator()(const ast::Unary& n) const {
    Expr a = sema.check(n.operand, scope);
    if (n.op == "not") {
      if (a->type != Type::Bool) fail(n.loc, "'not' needs a bool, not " + a_type(a->type));
      return std::make_shared<ir::Unary>(Type::Bool, ir::UnaryOp::Not, a, n.loc);
    }
    if (a->type == Type::Bool) fail(n.loc, "'" + n.op + "' needs a number or a vec, not a bool");
    if (n.op == "+") return a;
    if (auto lit = ir::as<ir::Literal>(a); lit && a->type == Type::Int) {
      if (lit->integer == std::numeric_limits<std::int64_t>::min())
        fail(n.loc, "integer overflow: -(" + std::to_string(lit->integer) +
                        ") does not fit in 64 bits");
      return std::make_shared<ir::Literal>(-lit->integer, n.loc);
    }
    return std::make_shared<ir::Unary>(a->type, ir::UnaryOp::Neg, a, n.loc);
  }
  Expr operator()(const ast::Postfix& n) const {
    Expr e = sema.check(n.base, scope);
    for (const ast::Identifier& c : n.components) {
      if (e->type != Type::Vec) fail(c.loc, "." + c.name + " needs a vec, not " + a_type(e->type));
      const auto* it =
          std::find(std::begin(kAxisNames), std::begin(kAxisNames) + sema.model_.dim, c.name);
      if (it == std::begin(kAxisNames) + sema.model_.dim)
        fail(c.loc, "no component ." + c.name + " in a " + std::to_string(sema.model_.dim) +
                        "-dimensional vec");
      e = std::make_shared<ir::Component>(e, static_cast<int>(it - std::begin(kAxisNames)),
                                          Location{e->loc.begin, c.loc.end});
    }
    return e;
  }
  Expr operator()(const ast::Chain& n) const { return sema.check(n, scope); }
  template <class Node>
  Expr operator()(const ast::x3::forward_ast<Node>& n) const {
    return (*this)(n.get());
  }
};

Expr Sema::check(const ast::Operand& operand, Scope& scope) {
  return boost::apply_visitor(CheckOperand{*this, scope}, operand);
}

Expr Sema::check_name(const ast::Identifier& n, Scope& scope) {
  if (n.name == "pi") return std::make_shared<ir::Literal>(Type::Real, M_PI, n.loc);
  if (n.name == "dim") return std::make_shared<ir::Literal>(Type::Int, model_.dim, n.loc);
  if (n.name == "lo" || n.name == "hi") {
    // The domain's corners, for walls: p[i].y - lo.y is the distance to the floor.
    const std::vector<double>& corner = n.name == "lo" ? model_.domain.lo : model_.domain.hi;
    if (corner.empty())
      fail(n.loc, quoted(n.name) + ", a corner of the domain, is known in statements only",
           "declarations are checked before the domain, whose bounds may name them");
    std::vector<Expr> components;
    for (double c : corner) components.push_back(std::make_shared<ir::Literal>(Type::Real, c, n.loc));
    return std::make_shared<ir::MakeVec>(components, n.loc);
  }
  if (n.name == "dx") {
    if (!scope.in_accumulation)
      fail(n.loc, "dx is only defined inside an accumulation",
           "dx is the shortest vector from particle i to particle j, as in sum(j, |dx| < rc, ...)");
    if (!scope.home)
      fail(n.loc, "dx needs two particles, and an observable's sum runs over one",
           "compute per-particle values in a statement first, as in e[i] = sum(j, |dx| < rc, ...), "
           "then sum them: total = sum(i in P, e[i])");
    return std::make_shared<ir::Dx>(scope.bound.front(), scope.bound.back(), n.loc);
  }
  if (scope.function) {
    const auto& args = scope.function->arg_names;
    const auto arg = std::find(args.begin(), args.end(), n.name);
    if (arg != args.end()) {
      const int index = static_cast<int>(arg - args.begin());
      return std::make_shared<ir::FnArg>(scope.function->arg_types[index], index, n.name, n.loc);
    }
  }
  auto it = names_.find(n.name);
  if (it != names_.end()) {
    switch (it->second.kind) {
      case Name::Param:
        return std::make_shared<ir::ParamRef>(model_.params[it->second.index].type,
                                              it->second.index, n.loc);
      case Name::Const:
        return std::make_shared<ir::ConstRef>(model_.consts[it->second.index].type,
                                              it->second.index, n.loc);
      case Name::Set: fail(n.loc, quoted(n.name) + " is a particle set, not a value");
      case Name::Fn:
        fail(n.loc, quoted(n.name) + " is a function; call it, as in " + n.name + "(...)");
      case Name::Observable: {
        const ir::Observable& o = model_.observables[it->second.index];
        if (scope.where == Scope::Where::Constant && !scope.observables)
          fail(n.loc,
               scope.context + " cannot read " + quoted(n.name) + ", which changes during a run",
               scope.function ? "pass it as an argument" : "");
        if (it->second.index == ir::kTime && !time_read_) time_read_ = n.loc;
        return std::make_shared<ir::ObservableRef>(o.type, it->second.index, n.loc);
      }
    }
  }
  if (is_builtin_name(n.name))
    fail(n.loc, quoted(n.name) + " is a function; call it, as in " + n.name + "(...)");
  if (scope.labels) {
    for (const ir::Label& l : *scope.labels)
      if (l.name == n.name)
        fail(n.loc,
             quoted(n.name) + " is a label; index a variable with it, as in v[" + n.name + "]");
    for (const ir::ParticleSet& s : model_.sets)
      if (s.find_var(n.name) >= 0)
        fail(n.loc, quoted(n.name) + " is a particle variable; index it with a label, as in " +
                        n.name + "[" + (scope.home ? scope.labels->front().name : "i") + "]");
  }
  follow_on_if_failed(n.name);
  fail_if_declared_below(n);
  std::vector<std::string> known;
  for (const auto& [name, unused] : names_) known.push_back(name);
  fail(n.loc, "unknown name " + quoted(n.name) + suggestion(n.name, known));
}

Expr Sema::check_indexed(const ast::Indexed& n, Scope& scope) {
  if (scope.where != Scope::Where::Statement)
    fail(n.loc, scope.context + " cannot read particle variables",
         scope.where == Scope::Where::Initialiser
             ? "initial values may use params, consts and random numbers; set values "
               "that depend on other variables in the init block"
         : scope.function ? "pass the value as an argument, e.g. fn " + scope.function->name +
                                "(..., " + n.var.name + ": " + "real)"
                          : "");
  int label = -1;
  for (int b : scope.bound)
    if ((*scope.labels)[b].name == n.label.name) label = b;
  if (label < 0) {
    for (const ir::Label& l : *scope.labels)
      if (l.name == n.label.name)
        fail(n.label.loc,
             "label " + quoted(n.label.name) + " is only bound inside its accumulation");
    if (!scope.home)
      fail(n.label.loc, "label " + quoted(n.label.name) + " is not bound here",
           "an observable is one value for the model: read particle variables inside a "
           "reduction, as in sum(" +
               n.label.name + " in " + model_.sets[0].name + ", " + n.var.name + "[" +
               n.label.name + "])");
    fail(n.label.loc, "label " + quoted(n.label.name) + " is not bound here",
         "a statement names its own particle by the label of its target (" +
             scope.labels->front().name +
             "); other particles are named by an accumulation, as in sum(" + n.label.name +
             ", ...)");
  }
  const int set_index = (*scope.labels)[label].set;
  const ir::ParticleSet& set = model_.sets[set_index];
  const int var = set.find_var(n.var.name);
  if (var < 0) follow_on_if_failed(n.var.name);
  if (var < 0)
    fail(n.var.loc,
         quoted(n.var.name) + " is not a variable of particle set " + set.name +
             suggestion(n.var.name, var_names(set)),
         !scope.several_sets.empty() && scope.bound.back() == label
             ? quoted(n.label.name) + " runs over " + scope.several_sets +
                   ": what it reads must be a variable of each (declare " + n.var.name +
                   " in " + set.name + " too)"
             : std::string());
  return std::make_shared<ir::VarRef>(set.vars[var].type, set_index, var, label, n.loc);
}

}  // namespace partc::sema
