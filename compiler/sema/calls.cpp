// Sema: calls of built-in and user functions, random draws, accumulations.
#include <algorithm>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ir/constant.hpp"
#include "sema/checker.hpp"

namespace partc::sema {

namespace {

struct FunctionInfo {
  ir::Function fn;
  int arity;
};
const std::map<std::string, FunctionInfo> kFunctions = {
    {"exp", {ir::Function::Exp, 1}},     {"log", {ir::Function::Log, 1}},
    {"sqrt", {ir::Function::Sqrt, 1}},   {"pow", {ir::Function::Pow, 2}},
    {"abs", {ir::Function::Abs, 1}},     {"min", {ir::Function::Min, 2}},
    {"max", {ir::Function::Max, 2}},     {"dot", {ir::Function::Dot, 2}},
    {"norm", {ir::Function::Norm, 1}},   {"floor", {ir::Function::Floor, 1}},
    {"ceil", {ir::Function::Ceil, 1}},   {"round", {ir::Function::Round, 1}},
    {"sin", {ir::Function::Sin, 1}},     {"cos", {ir::Function::Cos, 1}},
    {"tan", {ir::Function::Tan, 1}},     {"asin", {ir::Function::Asin, 1}},
    {"acos", {ir::Function::Acos, 1}},   {"atan", {ir::Function::Atan, 1}},
    {"atan2", {ir::Function::Atan2, 2}}, {"tanh", {ir::Function::Tanh, 1}},
    {"sign", {ir::Function::Sign, 1}},   {"clamp", {ir::Function::Clamp, 3}},
    {"mod", {ir::Function::Mod, 2}},     {"cross", {ir::Function::Cross, 2}},
};

const std::map<std::string, ir::Reduction> kReductions = {
    {"sum", ir::Reduction::Sum},
    {"min", ir::Reduction::Min},
    {"max", ir::Reduction::Max},
    {"count", ir::Reduction::Count},
};

}  // namespace

bool Sema::is_builtin_name(const std::string& name) {
  return kFunctions.count(name) || kReductions.count(name) || name == "dx" || name == "vec" ||
         name == "if" || name == "pi" || name == "lo" || name == "hi" ||
         is_random_function(name);
}

bool Sema::is_random_function(const std::string& name) {
  return name == "uniform" || name == "normal" || name == "uniform_vec" || name == "normal_vec";
}

Expr Sema::check_call(const ast::Call& n, Scope& scope) {
  const std::string& name = n.callee.name;
  const bool binding = !n.args.empty() && boost::get<ast::LabelBinding>(&n.args.front());
  const auto reduction = kReductions.find(name);
  if (reduction != kReductions.end() &&
      (name == "sum" || name == "count" || binding || n.args.size() >= 3))
    return check_accumulation(n, reduction->second, scope);
  if (binding)
    fail(ast::location_of(n.args.front()),
         "'in' binds a label only as the first argument of sum, count, min or max");
  if (is_random_function(name)) return check_random(n, scope);
  // The callee first: a misspelt function must not be reported as its
  // arguments' unknown label (summ(j, ...)).
  const auto user = names_.find(name);
  const bool user_fn = user != names_.end() && user->second.kind == Name::Fn;
  const auto fn = kFunctions.find(name);
  if (!user_fn && fn == kFunctions.end() && name != "vec" && name != "if") {
    if (scope.function && name == scope.function->name)
      fail(n.callee.loc, "function " + quoted(name) + " calls itself",
           "functions are not recursive; write the repetition out");
    follow_on_if_failed(name);
    fail_if_declared_below(n.callee);
    std::vector<std::string> known = {"vec",     "if",     "sum",         "count",
                                      "uniform", "normal", "uniform_vec", "normal_vec"};
    for (const auto& [k, unused] : kFunctions) known.push_back(k);
    for (const auto& f : model_.functions) known.push_back(f.name);
    fail(n.callee.loc, "unknown function " + quoted(name) + suggestion(name, known));
  }
  std::vector<Expr> args;
  for (const ast::Argument& a : n.args) args.push_back(check(boost::get<ast::Chain>(a), scope));
  if (name == "vec") {
    if (static_cast<int>(args.size()) != model_.dim)
      fail(n.loc, "vec(...) needs " + std::to_string(model_.dim) + " components in a " +
                      std::to_string(model_.dim) + "-dimensional model, not " +
                      std::to_string(args.size()));
    for (std::size_t k = 0; k < args.size(); ++k)
      if (!ir::is_numeric_scalar(args[k]->type))
        fail(args[k]->loc, "a vec component must be a number, not " + a_type(args[k]->type));
    return std::make_shared<ir::MakeVec>(std::move(args), n.loc);
  }
  if (name == "if") return check_select(n, std::move(args));
  if (user_fn) return check_user_call(n, user->second.index, std::move(args));
  if (static_cast<int>(args.size()) != fn->second.arity)
    fail(n.loc, name + "() takes " + std::to_string(fn->second.arity) + " argument" +
                    (fn->second.arity == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
  return std::make_shared<ir::Call>(call_type(fn->second.fn, name, args), fn->second.fn,
                                    std::move(args), n.loc);
}

Expr Sema::check_user_call(const ast::Call& n, int index, std::vector<Expr> args) {
  const ir::UserFn& fn = model_.functions[index];
  if (args.size() != fn.arg_names.size())
    fail(n.loc, fn.name + "() takes " + std::to_string(fn.arg_names.size()) + " argument" +
                    (fn.arg_names.size() == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
  for (std::size_t k = 0; k < args.size(); ++k)
    args[k] = convert(args[k], fn.arg_types[k], args[k]->loc,
                      "argument " + fn.arg_names[k] + " of " + fn.name);
  return std::make_shared<ir::FnCall>(fn.body->type, index, std::move(args), n.loc);
}

Type Sema::call_type(ir::Function fn, const std::string& name, const std::vector<Expr>& args) {
  auto need = [&](std::size_t k, bool ok, const char* what) {
    if (!ok) fail(args[k]->loc, name + "() needs " + what + ", not " + a_type(args[k]->type));
  };
  switch (fn) {
    case ir::Function::Dot:
      need(0, args[0]->type == Type::Vec, "vecs");
      need(1, args[1]->type == Type::Vec, "vecs");
      return Type::Real;
    case ir::Function::Norm: need(0, args[0]->type == Type::Vec, "a vec"); return Type::Real;
    case ir::Function::Abs:
      need(0, ir::is_numeric_scalar(args[0]->type), "a number (for a vec's length use |v|)");
      return args[0]->type;
    case ir::Function::Cross:
      need(0, args[0]->type == Type::Vec, "vecs");
      need(1, args[1]->type == Type::Vec, "vecs");
      if (model_.dim != 2 && model_.dim != 3)
        fail(args[0]->loc,
             "cross() is defined in 2 and 3 dimensions, not in " + std::to_string(model_.dim));
      return model_.dim == 3 ? Type::Vec : Type::Real;
    // Ints stay ints; one real argument makes the result real.
    case ir::Function::Min:
    case ir::Function::Max:
    case ir::Function::Clamp:
    case ir::Function::Mod:
    case ir::Function::Sign: {
      bool ints = true;
      for (std::size_t k = 0; k < args.size(); ++k) {
        need(k, ir::is_numeric_scalar(args[k]->type), "numbers");
        ints = ints && args[k]->type == Type::Int;
      }
      if (fn == ir::Function::Mod) no_zero_divisor(args[1], "mod()");
      return ints ? Type::Int : Type::Real;
    }
    default:
      for (std::size_t k = 0; k < args.size(); ++k)
        need(k, ir::is_numeric_scalar(args[k]->type), "a number");
      return Type::Real;
  }
}

// if(c, a, b): branches of one type, or an int and a real (then real).
Expr Sema::check_select(const ast::Call& n, std::vector<Expr> args) {
  if (args.size() != 3)
    fail(n.loc, "if() takes a condition and two values: if(condition, then, otherwise), not " +
                    std::to_string(args.size()) + " argument" + (args.size() == 1 ? "" : "s"));
  if (args[0]->type != Type::Bool)
    fail(args[0]->loc, "the condition of if() must be a bool, not " + a_type(args[0]->type));
  const Type a = args[1]->type, b = args[2]->type;
  Type type = a;
  if (a != b) {
    if (!ir::is_numeric_scalar(a) || !ir::is_numeric_scalar(b)) {
      auto zero = [](const Expr& e) {
        auto lit = ir::as<ir::Literal>(e);
        return lit && lit->type != Type::Bool && lit->value == 0;
      };
      std::string zero_vec = "vec(0";
      for (int k = 1; k < model_.dim; ++k) zero_vec += ", 0";
      fail(n.loc, "the branches of if() must have one type, not " + a_type(a) + " and " + a_type(b),
           (a == Type::Vec && zero(args[2])) || (b == Type::Vec && zero(args[1]))
               ? "for the zero vector write " + zero_vec + ")"
               : "");
    }
    type = Type::Real;
  }
  return std::make_shared<ir::Select>(type, args[0], args[1], args[2], n.loc);
}

// Integer // and mod by a divisor known to be 0 are mistakes, not the 0
// they give at run time.
void Sema::no_zero_divisor(const Expr& divisor, const std::string& what) {
  if (divisor->type != Type::Int) return;
  if (auto value = evaluate_constant(divisor, model_); value && *value == 0)
    fail(divisor->loc, what + " by an int that is always 0");
}

Expr Sema::check_random(const ast::Call& n, Scope& scope) {
  if (!n.args.empty()) fail(n.loc, n.callee.name + "() takes no arguments");
  if (scope.where == Scope::Where::Constant)
    fail(n.loc, scope.context + " cannot be random",
         "random numbers are drawn per particle, in initial values and statements");
  if (!scope.home)
    fail(n.loc, "an observable's statement cannot draw random numbers",
         "draws are keyed by a particle's id; draw per particle, in a statement like x[i] = ...");
  if (scope.in_accumulation)
    fail(n.loc, "random numbers inside an accumulation are not supported",
         "a draw is keyed by one particle's id; draw per particle outside the sum");
  const std::string& name = n.callee.name;
  const bool vec = name.size() > 4 && name.compare(name.size() - 4, 4, "_vec") == 0;
  const auto dist =
      name.rfind("uniform", 0) == 0 ? ir::Distribution::Uniform : ir::Distribution::Normal;
  const int stream = n.random_key.empty() ? model_.random_streams++
                                          : model_.effect_random_streams[n.random_key]++;
  return std::make_shared<ir::Random>(vec ? Type::Vec : Type::Real, dist, stream, n.random_key,
                                      n.loc);
}

// min(j, cond, e, none): `none` where no particle satisfies cond, instead of
// +-inf (which the finite check would take for a blow-up). The count and the
// min run over the same particles (a condition cannot draw random numbers);
// codegen fuses their loops.
Expr Sema::check_extremum_or_none(const ast::Call& n, ir::Reduction reduction, Scope& scope) {
  const std::string& name = n.callee.name;
  ast::Call reduced = n, counted = n;
  reduced.args.pop_back();
  counted.callee.name = "count";
  counted.args.resize(2);
  const Expr value = check_accumulation(reduced, reduction, scope);
  const Expr found = check_accumulation(counted, ir::Reduction::Count, scope);
  Expr none = check(argument_chain(n.args.back(), name), scope);
  none = convert(none, value->type, none->loc, "the value of " + name + " over no particles");
  const Expr any = std::make_shared<ir::Binary>(
      Type::Bool, ir::BinaryOp::Gt, found, std::make_shared<ir::Literal>(std::int64_t{0}, n.loc),
      n.loc);
  return std::make_shared<ir::Select>(value->type, any, value, none, n.loc);
}

Expr Sema::check_accumulation(const ast::Call& n, ir::Reduction reduction, Scope& scope) {
  const std::string& name = n.callee.name;
  if ((reduction == ir::Reduction::Min || reduction == ir::Reduction::Max) && n.args.size() == 4)
    return check_extremum_or_none(n, reduction, scope);
  const std::size_t expected_min = reduction == ir::Reduction::Count ? 1 : 2;
  const std::size_t expected_max = reduction == ir::Reduction::Count ? 2 : 3;
  if (n.args.size() < expected_min || n.args.size() > expected_max)
    fail(n.loc, reduction == ir::Reduction::Count
                    ? "count takes a label and an optional condition: count(j, condition)"
                    : name + " takes a label, an optional condition and a value: " + name +
                          "(j, condition, value)" +
                          (reduction == ir::Reduction::Sum
                               ? std::string()
                               : ", and a value for no particles: " + name +
                                     "(j, condition, value, none)"));
  if (scope.where != Scope::Where::Statement)
    fail(n.loc, "an accumulation over particles cannot appear in " + scope.context);
  if (scope.in_accumulation)
    fail(n.loc, "nested accumulations are not supported",
         "compute the inner one into a variable in an earlier statement");

  // The label: `j` (over the statement's set), `j in Q`, or `j in (Q, R)`.
  std::string label_name;
  Location label_loc;
  std::vector<int> sets;
  if (auto b = boost::get<ast::LabelBinding>(&n.args.front())) {
    label_name = b->label.name;
    label_loc = b->label.loc;
    for (const ast::Identifier& set : b->sets) {
      const int s = set_named(set);
      if (std::find(sets.begin(), sets.end(), s) != sets.end())
        fail(set.loc, "set " + quoted(set.name) + " is listed twice in this " + name);
      sets.push_back(s);
    }
  } else {
    const ast::Chain& c = boost::get<ast::Chain>(n.args.front());
    const ast::Operand* sole = ast::sole_operand(c);
    const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
    if (!id)
      fail(c.loc,
           "the first argument of " + name + " must be a new label, as in " + name + "(j, ...)");
    label_name = id->name;
    label_loc = id->loc;
    sets.push_back(scope.labels->front().set);
    if (sets.front() < 0)
      fail(id->loc,
           "this block updates no particle set: say which set " + quoted(id->name) + " runs over",
           "as in " + name + "(" + id->name + " in " + model_.sets[0].name + ", ...)");
  }
  if (label_name == scope.labels->front().name)
    fail(statement_target_,
         "cannot write " + source_text(statement_target_) + ": " + quoted(label_name) +
             " is the label of this " + name + ", which runs over other particles",
         "a statement writes only its own particle, as in v[i] += " + name + "(j, ...)");
  for (int b : scope.bound)
    if ((*scope.labels)[b].name == label_name)
      fail(label_loc, "label " + quoted(label_name) + " is already bound");
  for (const ir::ParticleSet& s : model_.sets)
    if (s.find_var(label_name) >= 0)
      fail(label_loc, "label " + quoted(label_name) + " has the name of a particle variable");
  if (names_.count(label_name) || label_name == "dx")
    fail(label_loc, "label " + quoted(label_name) + " has the name of a param, const or set");

  // Over several sets, the accumulation is one per set, combined: each set has
  // its own search and its own label, so the analyses see ordinary sums.
  Expr combined;
  for (int set : sets) {
    scope.labels->push_back({label_name, set});
    const int label_index = static_cast<int>(scope.labels->size() - 1);
    Scope inner = scope;
    inner.bound.push_back(label_index);
    inner.in_accumulation = true;
    if (sets.size() > 1) {
      std::vector<std::string> names;
      for (int t : sets) names.push_back(model_.sets[t].name);
      inner.several_sets = fmt::format("{} and {}", fmt::join(names.begin(), names.end() - 1, ", "),
                                       names.back());
    }
    const Expr part = check_accumulation_over(n, reduction, label_index, inner);
    if (!combined) {
      combined = part;
    } else if (reduction == ir::Reduction::Min || reduction == ir::Reduction::Max) {
      const ir::Function f = reduction == ir::Reduction::Min ? ir::Function::Min : ir::Function::Max;
      combined = std::make_shared<ir::Call>(part->type, f, std::vector<Expr>{combined, part}, n.loc);
    } else {
      combined = std::make_shared<ir::Binary>(part->type, ir::BinaryOp::Add, combined, part, n.loc);
    }
  }
  return combined;
}

// One set's accumulation: its condition and value checked with the label bound.
Expr Sema::check_accumulation_over(const ast::Call& n, ir::Reduction reduction, int label_index,
                                   Scope& inner) {
  const std::string& name = n.callee.name;
  const bool has_condition = n.args.size() == (reduction == ir::Reduction::Count ? 2u : 3u);
  Expr condition, body;
  if (has_condition) {
    condition = check(argument_chain(n.args[1], name), inner);
    if (condition->type != Type::Bool)
      fail(condition->loc,
           "the condition of " + name + " must be a bool, not " + a_type(condition->type));
  }
  if (reduction != ir::Reduction::Count) {
    body = check(argument_chain(n.args.back(), name), inner);
    if (body->type == Type::Bool || (body->type == Type::Vec && reduction != ir::Reduction::Sum))
      fail(body->loc, name + " cannot accumulate " + a_type(body->type));
  }
  const Type type = reduction == ir::Reduction::Count ? Type::Int : body->type;
  return std::make_shared<ir::Accumulate>(type, reduction, label_index, condition, body,
                                          model_.accumulations++, n.loc);
}

const ast::Chain& Sema::argument_chain(const ast::Argument& a, const std::string& name) {
  if (auto c = boost::get<ast::Chain>(&a)) return *c;
  fail(ast::location_of(a), "'in' binds a label only in the first argument of " + name);
}

}  // namespace partc::sema
