// Sema: stage blocks, their statements, and the schedule.
#include <algorithm>
#include <functional>
#include <map>
#include <set>

#include "ir/constant.hpp"
#include "sema/checker.hpp"

namespace partc::sema {

void Sema::check_stage(const ast::StageBlock& block) {
  ir::Stage stage;
  stage.kind = block.kind == "init"   ? ir::StageKind::Init
               : block.kind == "step" ? ir::StageKind::Step
                                      : ir::StageKind::Named;
  stage.loc = block.loc;
  stage.set = -1;
  stage.also_after_load = block.also_after_load;
  try {
    const ast::Identifier* set = stage_words(block, stage);
    stage.set = resolve_stage_set(block, set);
  } catch (const SemaError& e) {
    if (!e.follow_on) diagnostics_.push_back(e.diagnostic);
    return;
  }
  check_block(block.body, stage, false);
  model_.stages.push_back(std::move(stage));
}

// The words after init/step (the set) or stage (the name, then the set);
// returns the set's, if given.
const ast::Identifier* Sema::stage_words(const ast::StageBlock& block, ir::Stage& stage) {
  const std::size_t named = stage.kind == ir::StageKind::Named;
  if (named && block.words.empty())
    fail(block.loc, "a stage needs a name, as in 'stage settle { ... }'");
  if (block.words.size() > 1 + named)
    fail(block.words.back().loc,
         "one word too many: " + block.kind + (named ? " NAME [SET] { ... }" : " [SET] { ... }"));
  if (named) {
    const ast::Identifier& name = block.words.front();
    if (is_builtin_name(name.name) || names_.count(name.name) || name.name == "init")
      fail(name.loc, "stage " + quoted(name.name) +
                         " has the name of a param, const, set, "
                         "function, observable or builtin");
    for (const ir::Stage& other : model_.stages)
      if (other.kind == ir::StageKind::Named && other.name == name.name)
        fail(name.loc, "a second stage named " + quoted(name.name),
             "the first is on line " + std::to_string(file_.line_column(other.loc.begin).line));
    stage.name = name.name;
  }
  return block.words.size() > named ? &block.words.back() : nullptr;
}

// The statements of a block, in order; those of an iterate block (not
// nested) become one of the stage's loops.
void Sema::check_block(const std::vector<ast::BlockStatement>& body, ir::Stage& stage,
                       bool in_loop) {
  const int stage_index = static_cast<int>(model_.stages.size());
  for (const ast::BlockStatement& s : body)
    guarded([&] {
      if (auto loop = boost::get<ast::x3::forward_ast<ast::IterateBlock>>(&s)) {
        if (in_loop) fail(loop->get().loc, "iterate blocks do not nest");
        check_iterate(loop->get(), stage);
        return;
      }
      const auto* a = boost::get<ast::Assignment>(&s);
      const auto* solve = boost::get<ast::SolveStatement>(&s);
      stage.statements.push_back(a ? check_statement(*a, stage.set)
                                   : check_solve(*solve, stage.set));
      if (a)
        for (const ast::Origin& o : a->origins)
          stage.statements.back().origins.push_back({o.effect, o.loc});
      if (a && a->origins.size() > 1) stage.statements.back().terms_by_origin = true;
      const boost::optional<ast::Identifier>& name = a ? a->name : solve->name;
      if (!name) return;
      const auto [it, fresh] = statement_names_.emplace(
          name->name,
          StatementRef{stage_index, static_cast<int>(stage.statements.size() - 1), name->loc});
      if (!fresh)
        fail(
            name->loc, "a second statement named " + quoted(name->name),
            "the first is on line " + std::to_string(file_.line_column(it->second.loc.begin).line));
      stage.statements.back().name = name->name;
    });
}

void Sema::check_iterate(const ast::IterateBlock& loop, ir::Stage& stage) {
  ir::Iterate it;
  it.loc = loop.loc;
  it.first = static_cast<int>(stage.statements.size());
  Scope scope;
  scope.context = "the condition of an iterate block";
  scope.observables = true;
  it.until = check(loop.until, scope);
  if (it.until->type != Type::Bool)
    fail(loop.until.loc,
         "the condition of an iterate block must be a bool, not " + a_type(it.until->type),
         "it decides on observables, as in: iterate until residual < 1e-8 limit 1000 { ... }");
  scope.context = "the limit of an iterate block";
  it.limit =
      convert(check(loop.limit, scope), Type::Int, loop.limit.loc, "the limit of an iterate block");
  if (auto value = evaluate_constant(it.limit, model_); value && !(*value >= 1))
    fail(loop.limit.loc, "an iterate block's limit must be at least 1 pass");
  if (loop.body.empty()) fail(loop.loc, "an iterate block needs statements to repeat");
  check_block(loop.body, stage, true);
  it.last = static_cast<int>(stage.statements.size());
  stage.loops.push_back(std::move(it));
}

int Sema::resolve_stage_set(const ast::StageBlock& block, const ast::Identifier* set) {
  if (set) return set_named(*set);
  if (model_.sets.empty()) throw SemaError{{}, true};  // "a model needs a set" says it
  // A block that assigns only observables needs no set.
  std::function<bool(const std::vector<ast::BlockStatement>&)> observables_only =
      [&](const std::vector<ast::BlockStatement>& body) {
        return std::all_of(body.begin(), body.end(), [&](const ast::BlockStatement& s) {
          if (auto loop = boost::get<ast::x3::forward_ast<ast::IterateBlock>>(&s))
            return observables_only(loop->get().body);
          const auto* a = boost::get<ast::Assignment>(&s);
          return a && !a->target.label;
        });
      };
  if (model_.sets.size() != 1 && observables_only(block.body)) return -1;
  const std::string example =
      block.kind == "stage" ? "stage " + block.words.front().name : block.kind;
  if (model_.sets.size() != 1)
    fail(block.loc, "this model has several particle sets: name the one this " + block.kind +
                        " block updates, as in '" + example + " " + model_.sets[0].name +
                        " { ... }'");
  return 0;
}

int Sema::set_named(const ast::Identifier& name) {
  auto it = names_.find(name.name);
  if ((it == names_.end() || it->second.kind != Name::Set) && failed_sets_.count(name.name))
    throw SemaError{{}, true};
  if (it == names_.end() || it->second.kind != Name::Set)
    fail(name.loc,
         "unknown particle set " + quoted(name.name) + suggestion(name.name, set_names()));
  return it->second.index;
}

std::vector<std::string> Sema::set_names() const {
  std::vector<std::string> out;
  for (const auto& s : model_.sets) out.push_back(s.name);
  return out;
}

// Why a statement cannot assign `name` when it is not a variable of `set`,
// if the name means something else; returns when it means nothing.
void Sema::not_assignable(const ast::Identifier& name, const ir::ParticleSet& set) {
  follow_on_if_failed(name.name);
  const auto it = names_.find(name.name);
  const std::string kept_per_particle =
      "a value that changes during a run is a particle variable: declare it in particles " +
      set.name + " { " + name.name + ": real = ... }";
  if (it != names_.end() && it->second.kind == Name::Param)
    fail(name.loc,
         quoted(name.name) + " is a param: it is set before the run (--set " + name.name +
             "=...), not by statements",
         kept_per_particle);
  if (it != names_.end() && it->second.kind == Name::Const)
    fail(name.loc, quoted(name.name) + " is a const and cannot be assigned", kept_per_particle);
  for (const ir::ParticleSet& other : model_.sets)
    if (&other != &set && other.find_var(name.name) >= 0)
      fail(name.loc,
           quoted(name.name) + " is a variable of particle set " + other.name + ", not " + set.name,
           "a block updates one set: write this in a block of its own, as in 'step " + other.name +
               " { ... }'");
}

namespace {

ir::AssignOp assign_op(const std::string& spelled) {
  static const std::map<std::string, ir::AssignOp> ops = {{"=", ir::AssignOp::Set},
                                                          {"+=", ir::AssignOp::Add},
                                                          {"-=", ir::AssignOp::Sub},
                                                          {"*=", ir::AssignOp::Mul},
                                                          {"/=", ir::AssignOp::Div}};
  return ops.at(spelled);
}

}  // namespace

// A statement that updates target.var[target.label] of every particle of the
// block's set: its set, variable and label, or why there is none.
ir::Statement Sema::particle_statement(const ast::Target& target, Location loc, int set_index) {
  if (set_index < 0)
    fail(target.loc, "this model has several particle sets: name the one this block updates",
         "as in 'step " + model_.sets[0].name + " { ... }'");
  const ir::ParticleSet& set = model_.sets[set_index];
  ir::Statement st;
  st.set = set_index;
  st.loc = loc;
  st.line = file_.output_line(loc.begin);
  st.var = set.find_var(target.var.name);
  if (st.var < 0) not_assignable(target.var, set);
  if (st.var < 0)
    fail(target.var.loc, quoted(target.var.name) + " is not a variable of particle set " +
                             set.name + suggestion(target.var.name, var_names(set)));
  const ast::Identifier& label = *target.label;
  st.labels.push_back({label.name, set_index});
  statement_target_ = target.loc;
  for (const ir::ParticleSet& s : model_.sets)
    if (s.find_var(label.name) >= 0 || names_.count(label.name))
      fail(label.loc, "label " + quoted(label.name) +
                          " has the name of a variable, param, const, observable or set");
  return st;
}

ir::Statement Sema::check_statement(const ast::Assignment& a, int set_index) {
  if (!a.target.label) return check_observable_statement(a, set_index);
  const ast::Identifier& label = *a.target.label;
  if (auto it = names_.find(a.target.var.name);
      it != names_.end() && it->second.kind == Name::Observable)
    fail(a.target.loc,
         quoted(a.target.var.name) +
             " is an observable, one value for the model: assign it "
             "without a label",
         "as in " + a.target.var.name + " = sum(" + label.name + " in P, ...)");
  ir::Statement st = particle_statement(a.target, a.loc, set_index);
  const ir::Variable& var = model_.sets[set_index].vars[st.var];
  if (st.var == ir::kId) fail(a.target.var.loc, "'id' is read-only: particle ids never change");
  st.op = assign_op(a.op);

  Scope scope = statement_scope(st, "a statement");
  st.value = check_assigned_value(a, st.op, var.type, "variable " + var.name, scope);
  return st;
}

// e_kin = sum(i in P, ...): run once, not per particle. labels[0] is a
// placeholder for the particle there is not, over the block's set (if it
// has one), so that sum(i, ...) runs over that set.
ir::Statement Sema::check_observable_statement(const ast::Assignment& a, int set_index) {
  const std::string& name = a.target.var.name;
  const auto it = names_.find(name);
  if (it == names_.end() || it->second.kind != Name::Observable) {
    for (const ir::ParticleSet& s : model_.sets)
      if (s.find_var(name) >= 0)
        fail(a.target.loc, quoted(name) + " is a particle variable: write " + name + "[i] " + a.op +
                               " ... to update every particle");
    if (set_index >= 0) not_assignable(a.target.var, model_.sets[set_index]);
    follow_on_if_failed(name);
    std::vector<std::string> known;
    for (const ir::Observable& o : model_.observables)
      if (!o.builtin) known.push_back(o.name);
    fail(a.target.loc, "unknown observable " + quoted(name) + suggestion(name, known),
         "declare it with: observable " + name + ": real = 0");
  }
  const ir::Observable& observable = model_.observables[it->second.index];
  if (observable.builtin)
    fail(
        a.target.loc, quoted(name) + " is kept by the run and cannot be assigned",
        name == "t" ? "t advances by the timestep after each step" : "step counts the steps taken");
  ir::Statement st;
  st.set = set_index;
  st.var = -1;
  st.observable = it->second.index;
  st.loc = a.loc;
  st.line = file_.output_line(a.loc.begin);
  st.labels.push_back({"", set_index});
  statement_target_ = a.target.loc;
  st.op = assign_op(a.op);
  Scope scope = statement_scope(st, "an observable's statement");
  st.value = check_assigned_value(a, st.op, observable.type, "observable " + name, scope);
  return st;
}

// solve w[i]: operator = rhs. The operator's linearity in w is decided by
// analysis/linear_operator.cpp; here, names and types.
ir::Statement Sema::check_solve(const ast::SolveStatement& s, int set_index) {
  if (!s.unknown.label)
    fail(s.unknown.loc,
         "a solve is for a particle variable: write solve " + s.unknown.var.name + "[i]: ...");
  ir::Statement st = particle_statement(s.unknown, s.loc, set_index);
  const ir::ParticleSet& set = model_.sets[set_index];
  if (st.var < ir::kFirstUserVar)
    fail(s.unknown.var.loc, "cannot solve for the builtin variable " + quoted(s.unknown.var.name));
  if (set.vars[st.var].type != Type::Real)
    fail(s.unknown.var.loc, "a solve is for a real variable, not " + a_type(set.vars[st.var].type),
         "solve each component of a vec as a real variable of its own");
  st.op = ir::AssignOp::Set;
  Scope scope = statement_scope(st, "a solve");
  st.solve_operator = check(s.lhs, scope);
  if (!ir::is_numeric_scalar(st.solve_operator->type))
    fail(s.lhs.loc,
         "the left side of a solve must be a number, not " + a_type(st.solve_operator->type));
  st.value = convert(check(s.rhs, scope), Type::Real, s.rhs.loc, "the right side of a solve");
  return st;
}

// Where a statement's expressions are checked: its labels; its own particle
// (label 0) bound, unless its target is an observable, which has none.
Scope Sema::statement_scope(ir::Statement& st, std::string context) {
  Scope scope;
  scope.where = Scope::Where::Statement;
  scope.context = std::move(context);
  scope.labels = &st.labels;
  scope.home = st.observable < 0;
  if (scope.home) scope.bound = {0};
  scope.observables = true;
  return scope;
}

// The value of `target op= value`, checked against the target's type.
ir::Expr Sema::check_assigned_value(const ast::Assignment& a, ir::AssignOp op, Type type,
                                    const std::string& what, Scope& scope) {
  Expr value = check(a.value, scope);
  const Location at = a.value.loc;
  if (type == Type::Bool && op != ir::AssignOp::Set)
    fail(a.loc, "bool " + what + " can only be assigned with '='");
  switch (op) {
    case ir::AssignOp::Set:
    case ir::AssignOp::Add:
    case ir::AssignOp::Sub: return convert(value, type, at, what);
    case ir::AssignOp::Mul:
    case ir::AssignOp::Div:
      if (type == Type::Int && op == ir::AssignOp::Div)
        fail(a.loc, "int " + what + " cannot be divided in place",
             "'/' gives a real; assign to a real variable instead");
      return convert(value, type == Type::Vec ? Type::Real : type, at,
                     type == Type::Vec ? "the scale factor of vec " + what : what);
  }
  internal_error("check_assigned_value: unknown operator");
}

void Sema::check_schedule(const ast::ScheduleItem& item) {
  if (!item.subject || item.subject->member) return check_precision_request(item);
  const ast::Identifier& statement = item.subject->name;
  auto named = statement_names_.find(statement.name);
  if (named == statement_names_.end()) {
    const auto it = names_.find(statement.name);
    if (it != names_.end() && it->second.kind == Name::Set)
      fail(statement.loc, quoted(statement.name) + " is a particle set, not a statement",
           "a set's variables are scheduled one by one, as in " + statement.name +
               ".v: precision = float; precision = float alone is for the whole model");
    std::vector<std::string> known;
    for (const auto& [name, unused] : statement_names_) known.push_back(name);
    fail(statement.loc,
         "no statement named " + quoted(statement.name) + suggestion(statement.name, known),
         "name a statement where it is written: force: v[i] += sum(...)");
  }
  ir::Statement& st = model_.stages[named->second.stage].statements[named->second.statement];
  if (st.schedule.loc.end != 0)
    fail(statement.loc, "statement " + quoted(st.name) + " is scheduled twice");
  st.schedule.loc = item.loc;
  std::set<std::string> seen;
  for (const ast::ScheduleOption& option : item.options) {
    if (!seen.insert(option.key.name).second)
      fail(option.key.loc, "option " + quoted(option.key.name) + " given twice");
    if (option.key.name == "search") {
      st.schedule.search = search_choice(option.value);
    } else if (option.key.name == "sharing") {
      st.schedule.sharing = sharing_choice(option.value);
    } else if (option.key.name == "skin") {
      Scope scope;
      scope.context = "a skin";
      Expr skin = check(option.value, scope);
      if (!ir::is_numeric_scalar(skin->type))
        fail(option.value.loc, "the skin must be a number, not " + a_type(skin->type));
      if (auto value = evaluate_constant(skin, model_); value && !(*value >= 0))
        fail(option.value.loc, "the skin must not be negative");
      st.schedule.skin = skin;
    } else if (option.key.name == "summation") {
      const ast::Operand* sole = ast::sole_operand(option.value);
      const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
      if (!id || (id->name != "plain" && id->name != "compensated"))
        fail(option.value.loc, "summation is plain or compensated",
             "compensated: Neumaier's summation, for terms of wildly different sizes");
      st.schedule.compensated = id->name == "compensated";
    } else if (option.key.name == "arithmetic") {
      st.schedule.arithmetic = precision_named(option.value, "arithmetic");
      st.schedule.arithmetic_loc = option.loc;
      st.schedule.arithmetic_reason =
          scheduled_reason(st.schedule.arithmetic, "this statement", option.loc);
    } else if (option.key.name == "solver" || option.key.name == "max_iterations") {
      if (!st.solve_operator)
        fail(option.key.loc, quoted(option.key.name) + " schedules a solve, and " +
                                 quoted(st.name) + " is not one");
      if (option.key.name == "solver")
        st.schedule.solver = solver_choice(option.value);
      else
        st.schedule.max_iterations = positive_schedule_value(option, Type::Int);
    } else if (option.key.name == "tol") {
      st.schedule.tolerance = positive_schedule_value(option, Type::Real);
    } else if (option.key.name == "dense") {
      st.schedule.dense = dense_method(option.value);
    } else if (option.key.name == "order") {
      st.schedule.order = positive_schedule_value(option, Type::Int);
    } else if (option.key.name == "precision") {
      fail(option.key.loc, "precision is chosen per variable, not per statement",
           "write P.v: precision = float for one variable, or precision = float alone for the "
           "whole model");
    } else {
      fail(option.key.loc,
           "unknown schedule option " + quoted(option.key.name) +
               suggestion(option.key.name, {"search", "sharing", "skin", "summation", "arithmetic",
                                            "solver", "tol", "max_iterations", "dense", "order"}),
           "options: search = auto | brute_force | cell_list | kd_tree; "
           "sharing = auto | shared | separate; skin = LENGTH; "
           "summation = plain | compensated; arithmetic = double | float; "
           "dense = direct | fmm, with tol = 1e-6 or "
           "order = K; for a solve: solver = auto | lu | cg | bicgstab | gmres, tol = 1e-10, "
           "max_iterations = K");
    }
  }
  check_fast_sum_options(st, item);
}

// tol belongs to a solve or to a fast sum, order to a fast sum only; a fast
// sum takes one of them (the other follows from it).
void Sema::check_fast_sum_options(const ir::Statement& st, const ast::ScheduleItem& item) {
  auto option_loc = [&](const std::string& key) {
    for (const ast::ScheduleOption& option : item.options)
      if (option.key.name == key) return option.key.loc;
    return item.loc;
  };
  const bool fmm = st.schedule.dense == ir::DenseMethod::Fmm;
  if (fmm && st.solve_operator && st.schedule.solver != ir::SolverChoice::Auto &&
      st.schedule.solver != ir::SolverChoice::Gmres)
    fail(option_loc("solver"),
         "a solve with dense = fmm is matrix-free, and " +
             std::string(ir::solver_choice_name(st.schedule.solver)) + " needs its matrix",
         "dense = fmm solves by GMRES, whose products are the fast sum; drop the solver, or "
         "drop dense = fmm to assemble the matrix");
  if (st.schedule.tolerance && !fmm && !st.solve_operator)
    fail(option_loc("tol"),
         "'tol' schedules a solve or a fast sum, and " + quoted(st.name) + " is neither",
         "for a fast dense sum: dense = fmm, tol = 1e-6");
  if (st.schedule.order && !fmm)
    fail(option_loc("order"),
         "'order' schedules a fast sum, and " + quoted(st.name) + " has no dense = fmm",
         "dense = fmm, order = 8: Chebyshev nodes per axis of the fast multipole method");
  // A solve's tol is its solver's: the fast sum's follows from it, or from an order.
  if (st.schedule.order && st.schedule.tolerance && !st.solve_operator)
    fail(option_loc("order"), "a fast sum takes a tolerance or an order, not both",
         "tol = 1e-6 lets the cost model choose the order; order = K fixes it");
}

// A schedule value that must be a positive number of the given type.
ir::Expr Sema::positive_schedule_value(const ast::ScheduleOption& option, Type type) {
  Scope scope;
  scope.context = "a schedule's " + option.key.name;
  Expr value = convert(check(option.value, scope), type, option.value.loc,
                       "the schedule's " + option.key.name);
  if (auto v = evaluate_constant(value, model_); v && !(*v > 0))
    fail(option.value.loc, "the schedule's " + option.key.name + " must be positive");
  return value;
}

// precision = float | double for the whole model (no subject) or for one
// variable (P.v), the only option a variable takes; the whole model also
// takes arithmetic = float | double. decide_storage and decide_arithmetic
// apply them.
void Sema::check_precision_request(const ast::ScheduleItem& item) {
  std::pair<int, int> variable{-1, -1};
  std::string whose = "the whole model";
  if (item.subject) {
    const ast::Identifier& member = *item.subject->member;
    const int set = set_named(item.subject->name);
    const ir::ParticleSet& s = model_.sets[set];
    const int var = s.find_var(member.name);
    if (var < 0)
      fail(member.loc, "particle set " + quoted(s.name) + " has no variable " +
                           quoted(member.name) + suggestion(member.name, var_names(s)));
    whose = s.name + "." + member.name;
    const Type type = s.vars[var].type;
    if (type != Type::Real && type != Type::Vec)
      fail(member.loc, whose + " is " + a_type(type) + ", which has no precision to choose",
           "only real and vec variables (and p) can be stored as float; ints and bools are "
           "stored exactly");
    variable = {set, var};
  }
  for (const ast::ScheduleOption& option : item.options) {
    if (option.key.name == "arithmetic" && !item.subject) {
      if (model_arithmetic_)
        fail(option.key.loc, "the arithmetic of the whole model is chosen twice",
             "first on line " +
                 std::to_string(file_.line_column(model_arithmetic_->loc.begin).line));
      model_arithmetic_ = PrecisionRequest{precision_named(option.value, "arithmetic"), option.loc};
      continue;
    }
    if (option.key.name != "precision") {
      static const std::vector<std::string> statement_options = {
          "search",     "sharing", "skin", "summation",
          "arithmetic", "solver",  "tol",  "max_iterations"};
      const bool of_statements = std::find(statement_options.begin(), statement_options.end(),
                                           option.key.name) != statement_options.end();
      const std::vector<std::string> own =
          item.subject ? std::vector<std::string>{"precision"}
                       : std::vector<std::string>{"precision", "arithmetic"};
      if (!of_statements)
        fail(
            option.key.loc,
            "unknown schedule option " + quoted(option.key.name) + suggestion(option.key.name, own),
            whose + (item.subject ? " takes precision = float | double"
                                  : " takes precision = float | double and arithmetic = "
                                    "float | double"));
      fail(option.key.loc, quoted(option.key.name) + " schedules a statement, not " + whose,
           "name the statement, as in force: " + option.key.name + " = ...");
    }
    const PrecisionRequest request{precision_named(option.value, "precision"), option.loc};
    const PrecisionRequest* earlier = nullptr;
    if (!item.subject) {
      if (model_precision_)
        earlier = &*model_precision_;
      else
        model_precision_ = request;
    } else if (const auto [it, fresh] = variable_precision_.emplace(variable, request); !fresh) {
      earlier = &it->second;
    }
    if (earlier)
      fail(option.key.loc, "the precision of " + whose + " is chosen twice",
           "first on line " + std::to_string(file_.line_column(earlier->loc.begin).line));
  }
}

// The value of precision (storage) or arithmetic (pair terms).
ir::Precision Sema::precision_named(const ast::Chain& value, const std::string& option) {
  const ast::Operand* sole = ast::sole_operand(value);
  const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
  if (id && id->name == "float") return ir::Precision::Float;
  if (id && id->name == "double") return ir::Precision::Double;
  fail(value.loc, option + " is float or double, not " + quoted(source_text(value.loc)),
       option == "precision"
           ? "float stores each number in 32 bits, double in 64; both compute in double"
           : "float computes vector pair terms on float lanes, twice as many, and adds them "
             "into double sums; double computes them in double");
}

// "float, as the schedule says for this variable (md.part:20)".
std::string Sema::scheduled_reason(ir::Precision chosen, const std::string& whose,
                                   Location at) const {
  return std::string(ir::precision_name(chosen)) + ", as the schedule says for " + whose + " (" +
         file_.line_reference(at.begin) + ")";
}

// The storage of every real and vec variable, p included: its own schedule
// entry, else the whole model's, else double; with the reason, for --explain.
void Sema::decide_storage() {
  for (std::size_t s = 0; s < model_.sets.size(); ++s)
    for (std::size_t v = 0; v < model_.sets[s].vars.size(); ++v) {
      ir::Variable& var = model_.sets[s].vars[v];
      if (var.type != Type::Real && var.type != Type::Vec) continue;
      const auto own = variable_precision_.find({static_cast<int>(s), static_cast<int>(v)});
      const PrecisionRequest* chosen = own != variable_precision_.end() ? &own->second
                                       : model_precision_               ? &*model_precision_
                                                                        : nullptr;
      if (!chosen) {
        var.storage_reason = "double, the default";
        continue;
      }
      var.storage = chosen->precision;
      var.storage_reason = scheduled_reason(
          var.storage, own != variable_precision_.end() ? "this variable" : "the whole model",
          chosen->loc);
    }
}

void Sema::decide_arithmetic() {
  for (ir::Stage& stage : model_.stages)
    for (ir::Statement& st : stage.statements) {
      if (st.schedule.arithmetic_loc.end != 0) continue;  // its own entry
      if (!model_arithmetic_) {
        st.schedule.arithmetic_reason = "double, the default";
        continue;
      }
      st.schedule.arithmetic = model_arithmetic_->precision;
      st.schedule.arithmetic_reason =
          scheduled_reason(st.schedule.arithmetic, "the whole model", model_arithmetic_->loc);
    }
}

ir::SolverChoice Sema::solver_choice(const ast::Chain& value) {
  const ast::Operand* sole = ast::sole_operand(value);
  const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
  for (ir::SolverChoice c : {ir::SolverChoice::Auto, ir::SolverChoice::Lu, ir::SolverChoice::Cg,
                             ir::SolverChoice::Bicgstab, ir::SolverChoice::Gmres})
    if (id && id->name == ir::solver_choice_name(c)) return c;
  fail(value.loc, "unknown solver " + quoted(source_text(value.loc)),
       "solvers: auto, lu (dense), cg (symmetric positive definite), bicgstab, gmres");
}

ir::DenseMethod Sema::dense_method(const ast::Chain& value) {
  const ast::Operand* sole = ast::sole_operand(value);
  const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
  for (ir::DenseMethod d : {ir::DenseMethod::Direct, ir::DenseMethod::Fmm})
    if (id && id->name == ir::dense_method_name(d)) return d;
  fail(value.loc, "dense sums run direct or fmm, not " + quoted(source_text(value.loc)),
       "fmm: a black-box fast multipole method with an accuracy knob (tol or order)");
}

ir::SearchChoice Sema::search_choice(const ast::Chain& value) {
  const ast::Operand* sole = ast::sole_operand(value);
  const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
  for (ir::SearchChoice c : {ir::SearchChoice::Auto, ir::SearchChoice::BruteForce,
                             ir::SearchChoice::CellList, ir::SearchChoice::KdTree})
    if (id && id->name == ir::search_choice_name(c)) return c;
  fail(value.loc, "unknown search " + quoted(source_text(value.loc)),
       "searches: auto, brute_force, cell_list, kd_tree");
}

ir::Sharing Sema::sharing_choice(const ast::Chain& value) {
  const ast::Operand* sole = ast::sole_operand(value);
  const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
  for (ir::Sharing s : {ir::Sharing::Auto, ir::Sharing::Shared, ir::Sharing::Separate})
    if (id && id->name == ir::sharing_name(s)) return s;
  fail(value.loc, "sharing is auto, shared or separate, not " + quoted(source_text(value.loc)),
       "shared: one search with other statements' sums over the set, at the largest radius; "
       "separate: a search of this statement's own");
}

std::vector<std::string> Sema::var_names(const ir::ParticleSet& set) {
  std::vector<std::string> out;
  for (const auto& v : set.vars) out.push_back(v.name);
  return out;
}

}  // namespace partc::sema
