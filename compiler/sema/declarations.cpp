// Sema: the model's header (model, dim, domain) and its declarations.
#include <algorithm>
#include <cmath>

#include "ir/constant.hpp"
#include "sema/checker.hpp"

namespace partc::sema {

ir::Model Sema::run(const ast::Program& program) {
  const ast::DomainDecl& domain = collect_header(program);
  declare_builtin_observables();
  for (const ast::Declaration& decl : program.declarations)
    if (const ast::Identifier* name = ast::global_name(decl))
      declarations_.emplace(name->name, name->loc);
  // A set is declared even when its count or a variable is wrong (see
  // declare_set); with none at all, stage blocks have nothing to update.
  for (const ast::Declaration& decl : program.declarations) guarded([&] { declare(decl); });
  // After the consts, which its bounds may name.
  guarded([&] { check_domain(domain); });
  // After the consts too: an instance's const parameters are consts.
  for (const ast::Requirement& r : program.requirements) guarded([&] { check_requirement(r); });
  if (model_.sets.empty() && !has_errors())
    diagnostics_.push_back({Location{}, "a model needs at least one particle set",
                            "declare one with: particles P(N) { v: vec = 0 }"});
  // After every observable, which they may name.
  for (const ast::Declaration& decl : program.declarations) {
    if (auto t = boost::get<ast::TimestepDecl>(&decl)) guarded([&] { check_timestep(*t); });
    if (auto o = boost::get<ast::OutputDecl>(&decl)) guarded([&] { check_output(*o); });
  }
  for (const ast::Declaration& decl : program.declarations)
    if (auto stage = boost::get<ast::StageBlock>(&decl)) check_stage(*stage);
  if (time_read_ && !model_.timestep)
    diagnostics_.push_back({*time_read_, "t is the time, which needs a timestep",
                            "say how far a step advances time, as in: timestep = dt"});
  for (const ast::Declaration& decl : program.declarations)
    if (auto schedule = boost::get<ast::ScheduleBlock>(&decl))
      for (const ast::ScheduleItem& item : schedule->items) guarded([&] { check_schedule(item); });
  decide_storage();
  decide_arithmetic();
  if (has_errors()) throw CompileError(diagnostics_);
  return std::move(model_);
}

// Returns the domain declaration, checked once the consts are declared.
const ast::DomainDecl& Sema::collect_header(const ast::Program& program) {
  const ast::ModelDecl* model = nullptr;
  const ast::DimDecl* dim = nullptr;
  const ast::DomainDecl* domain = nullptr;
  auto once = [&](auto*& seen, const auto& decl, const char* what) {
    if (seen)
      diagnostics_.push_back(
          {decl.loc, std::string("a second ") + what + " declaration",
           "the first is on line " + std::to_string(file_.line_column(seen->loc.begin).line)});
    else
      seen = &decl;
  };
  for (const ast::Declaration& decl : program.declarations) {
    if (auto m = boost::get<ast::ModelDecl>(&decl)) once(model, *m, "model");
    if (auto d = boost::get<ast::DimDecl>(&decl)) once(dim, *d, "dim");
    if (auto d = boost::get<ast::DomainDecl>(&decl)) once(domain, *d, "domain");
  }
  const Location start{0, 1};
  if (!model) diagnostics_.push_back({start, "missing 'model NAME' declaration"});
  if (!dim) diagnostics_.push_back({start, "missing 'dim N' declaration"});
  if (!domain) diagnostics_.push_back({start, "missing 'domain lo=(...) hi=(...)' declaration"});
  if (has_errors()) throw CompileError(diagnostics_);

  model_.name = model->name.name;
  model_.dim = static_cast<int>(dim->value.value);
  if (dim->value.value < 1 || dim->value.value > 4)
    throw CompileError(Diagnostic{dim->value.loc, "dim must be 1, 2, 3 or 4"});
  return *domain;
}

void Sema::check_domain(const ast::DomainDecl& decl) {
  auto bounds = [&](const std::vector<ast::Chain>& tuple, const char* which) {
    if (static_cast<int>(tuple.size()) != model_.dim)
      fail(tuple.front().loc, std::string(which) + " has " + std::to_string(tuple.size()) +
                                  " components but the model has dim " +
                                  std::to_string(model_.dim));
    std::vector<double> values;
    Scope scope;
    scope.context = "a domain bound";
    for (const ast::Chain& c : tuple)
      values.push_back(constant_number(check(c, scope), c.loc, scope));
    return values;
  };
  model_.domain.lo = bounds(decl.lo, "lo");
  model_.domain.hi = bounds(decl.hi, "hi");
  for (int k = 0; k < model_.dim; ++k)
    if (!(model_.domain.lo[k] < model_.domain.hi[k]))
      fail(decl.hi[k].loc, "the domain is empty along " + std::string(kAxisNames[k]) +
                               ": hi must be greater than lo");
  ir::Domain& d = model_.domain;
  d.periodic.assign(model_.dim, false);
  d.reflect.assign(model_.dim, false);
  d.open.assign(model_.dim, false);
  std::vector<std::string> kind_of(model_.dim);
  for (const ast::BoundaryClause& clause : decl.boundaries) {
    const std::string& kind = clause.kind.name;
    std::vector<bool>* axes = kind == "periodic"  ? &d.periodic
                              : kind == "reflect" ? &d.reflect
                              : kind == "open"    ? &d.open
                                                  : nullptr;
    if (!axes)
      fail(clause.kind.loc,
           "unknown boundary " + quoted(kind) + suggestion(kind, {"periodic", "reflect", "open"}),
           "a domain's faces are periodic=(...), reflect=(...) or open=(...); an axis in none "
           "of them is unbounded");
    for (const ast::Identifier& axis : clause.axes) {
      const auto* it =
          std::find(std::begin(kAxisNames), std::begin(kAxisNames) + model_.dim, axis.name);
      if (it == std::begin(kAxisNames) + model_.dim)
        fail(axis.loc,
             "unknown axis " + quoted(axis.name) + " for a " + std::to_string(model_.dim) +
                 "-dimensional domain",
             "axes are named x, y, z, w");
      const auto k = it - std::begin(kAxisNames);
      if (kind_of[k] == kind) fail(axis.loc, "axis " + quoted(axis.name) + " listed twice");
      if (!kind_of[k].empty())
        fail(axis.loc, "axis " + quoted(axis.name) + " is already " + kind_of[k],
             "each axis has one kind of boundary");
      kind_of[k] = kind;
      (*axes)[k] = true;
    }
  }
  if (ir::Domain::any(d.reflect)) return;
  for (const ir::ParticleSet& set : model_.sets)
    for (const ir::Variable& var : set.vars)
      if (var.mirrored)
        fail(var.loc, "variable " + quoted(var.name) + " is mirrored, but no face reflects",
             "mirrored variables turn at reflecting faces: declare them in the domain, as in "
             "reflect=(y)");
}

void Sema::declare_global(const ast::Identifier& name, const char* kind) {
  if (is_builtin_name(name.name))
    fail(name.loc, quoted(name.name) + " is a builtin name and cannot be redefined");
  auto [it, fresh] = globals_.emplace(name.name, name.loc);
  if (!fresh)
    fail(name.loc, std::string("redefinition of ") + quoted(name.name) + " as a " + kind,
         "first defined on line " + std::to_string(file_.line_column(it->second.begin).line));
}

Type Sema::type_named(const ast::Identifier& name, bool allow_vec) {
  auto it = kTypeNames.find(name.name);
  if (it == kTypeNames.end() || (!allow_vec && it->second == Type::Vec))
    fail(name.loc, "unknown type " + quoted(name.name),
         allow_vec ? "types are real, int, bool and vec" : "param types are real, int and bool");
  return it->second;
}

void Sema::fail_if_declared_below(const ast::Identifier& name) const {
  const auto it = declarations_.find(name.name);
  if (it != declarations_.end() && !names_.count(name.name))
    fail(name.loc,
         quoted(name.name) + " is declared below, at " + file_.line_reference(it->second.begin),
         "declarations are read in order: move it above this line");
}

void Sema::declare(const ast::Declaration& decl) {
  if (auto p = boost::get<ast::ParamDecl>(&decl)) poisoned(p->name, [&] { declare_param(*p); });
  if (auto c = boost::get<ast::ConstDecl>(&decl)) poisoned(c->name, [&] { declare_const(*c); });
  if (auto f = boost::get<ast::FnDecl>(&decl)) poisoned(f->name, [&] { declare_fn(*f); });
  if (auto o = boost::get<ast::ObservableDecl>(&decl))
    poisoned(o->name, [&] { declare_observable(*o); });
  if (auto s = boost::get<ast::ParticlesDecl>(&decl)) declare_set(*s);
}

void Sema::declare_param(const ast::ParamDecl& decl) {
  declare_global(decl.name, "param");
  const Type type = type_named(decl.type, false);
  Scope scope;
  scope.context = "a param default";
  Expr def = check(decl.value, scope);
  const double value = constant_number(def, decl.value.loc, scope);
  convert(def, type, decl.value.loc, "param " + decl.name.name);
  if (type == Type::Int && value != std::floor(value))
    fail(decl.value.loc, "param " + quoted(decl.name.name) + " is an int but its default is " +
                             std::to_string(value));
  model_.params.push_back(
      {decl.name.name, type, std::make_shared<ir::Literal>(type, value, decl.value.loc), decl.loc});
  names_.emplace(decl.name.name, Name{Name::Param, static_cast<int>(model_.params.size() - 1)});
}

void Sema::declare_const(const ast::ConstDecl& decl) {
  declare_global(decl.name, "const");
  Scope scope;
  scope.context = "a const";
  Expr value = check(decl.value, scope);
  // A const folded at compile time is emitted as a C++ literal: it must be one.
  if (auto folded = evaluate_constant(value, model_)) {
    if ((value->type == Type::Real || value->type == Type::Vec) && !std::isfinite(*folded))
      fail(
          decl.value.loc,
          "const " + quoted(decl.name.name) + " is " +
              (std::isnan(*folded) ? "NaN"
               : *folded > 0       ? "+inf"
                                   : "-inf"),
          "a const must be a finite number: check its arguments' ranges (sqrt(-1), log(0), 1 / 0)");
    if (value->type == Type::Int && !ir::as<ir::Literal>(value) && std::abs(*folded) > 0x1p53)
      fail(decl.value.loc,
           "const " + quoted(decl.name.name) +
               " is an int beyond 2^53 computed from "
               "other consts, which partc cannot fold exactly",
           "write its value as one literal, or make it a real");
  }
  model_.consts.push_back({decl.name.name, value->type, value, decl.loc});
  names_.emplace(decl.name.name, Name{Name::Const, static_cast<int>(model_.consts.size() - 1)});
}

void Sema::check_requirement(const ast::Requirement& r) {
  Scope scope;
  scope.context = "a requirement";
  const Expr condition = check(r.condition, scope);
  const std::string text(file_.slice(r.condition.loc));
  if (condition->type != Type::Bool)
    fail(r.condition.loc,
         "a requirement is a condition, true or false, not " + a_type(condition->type));
  const std::optional<double> holds = evaluate_constant(condition, model_);
  if (!holds)
    fail(r.condition.loc, "requires " + text + " reads what is set at run time",
         "a requirement reads only the effect's const parameters and consts, which partc knows");
  if (*holds == 0)
    fail(r.use, "this " + r.instance + " breaks its effect's requirement: " + text,
         "required at " + file_.line_reference(r.item.begin) +
             "; give the parameters it names values that meet it");
}

void Sema::declare_fn(const ast::FnDecl& decl) {
  declare_global(decl.name, "function");
  ir::UserFn fn;
  fn.name = decl.name.name;
  fn.loc = decl.loc;
  for (const ast::FnParam& a : decl.params) {
    if (std::find(fn.arg_names.begin(), fn.arg_names.end(), a.name.name) != fn.arg_names.end())
      fail(a.name.loc, "argument " + quoted(a.name.name) + " listed twice");
    if ((!decl.from_module && names_.count(a.name.name)) || is_builtin_name(a.name.name))
      fail(a.name.loc, "argument " + quoted(a.name.name) +
                           " has the name of a param, const, set, function or builtin");
    fn.arg_names.push_back(a.name.name);
    fn.arg_types.push_back(type_named(a.type, true));
  }
  Scope scope;
  scope.context = "a function body";
  scope.function = &fn;
  fn.body = check(decl.value, scope);
  model_.functions.push_back(std::move(fn));
  names_.emplace(decl.name.name, Name{Name::Fn, static_cast<int>(model_.functions.size() - 1)});
}

void Sema::declare_set(const ast::ParticlesDecl& decl) {
  try {
    declare_global(decl.name, "particle set");
  } catch (const SemaError&) {
    failed_sets_.insert(decl.name.name);
    throw;
  }
  ir::ParticleSet set;
  set.name = decl.name.name;
  set.loc = decl.loc;
  // A wrong count is reported, and the set still declared, so that its
  // statements are checked too.
  set.initial_count = std::make_shared<ir::Literal>(Type::Int, 0, decl.count.loc);
  guarded([&] {
    Scope count_scope;
    count_scope.context = "a particle count";
    Expr count = convert(check(decl.count, count_scope), Type::Int, decl.count.loc,
                         "the particle count of " + set.name);
    if (auto value = evaluate_constant(count, model_); value && *value < 0)
      fail(decl.count.loc, "particle set " + quoted(set.name) + " would have " +
                               std::to_string(static_cast<long long>(*value)) + " particles");
    set.initial_count = count;
  });
  const auto builtin = [&](const char* name, Type type) {
    return ir::Variable{name, type, nullptr, true, decl.name.loc, false, ir::Precision::Double, {}};
  };
  set.vars.push_back(builtin("p", Type::Vec));
  set.vars.push_back(builtin("id", Type::Int));
  set.vars.push_back(builtin("alive", Type::Bool));
  const int set_index = static_cast<int>(model_.sets.size());
  for (const ast::VarDecl& var : decl.vars) {
    guarded([&] {
      poisoned(var.name, [&] {
        if (set.find_var(var.name.name) >= 0)
          fail(var.name.loc, set.find_var(var.name.name) < ir::kFirstUserVar
                                 ? quoted(var.name.name) + " is a builtin variable of every set"
                                 : "variable " + quoted(var.name.name) + " declared twice");
        if (names_.count(var.name.name) || is_builtin_name(var.name.name))
          fail(var.name.loc, "variable " + quoted(var.name.name) +
                                 " has the name of a param, const, set or builtin");
        const Type type = type_named(var.type, true);
        Expr initial;
        if (var.value) {
          Scope scope;
          scope.where = Scope::Where::Initialiser;
          scope.context = "an initial value";
          initial =
              convert(check(*var.value, scope), type, var.value->loc, "variable " + var.name.name);
        }
        if (var.mirrored && type != Type::Vec)
          fail(var.name.loc,
               "only a vec can be mirrored: " + quoted(var.name.name) + " is " + a_type(type));
        set.vars.push_back({var.name.name,
                            type,
                            initial,
                            false,
                            var.loc,
                            var.mirrored,
                            ir::Precision::Double,
                            {},
                            var.effect_owned});
      });
    });
  }
  model_.sets.push_back(std::move(set));
  names_.emplace(decl.name.name, Name{Name::Set, set_index});
}

// step (the steps taken) and t (the time, when the model has a timestep).
void Sema::declare_builtin_observables() {
  auto builtin = [&](const char* name, Type type) {
    model_.observables.push_back(
        {name, type, std::make_shared<ir::Literal>(type, 0, Location{}), true, Location{}});
    names_.emplace(name, Name{Name::Observable, static_cast<int>(model_.observables.size() - 1)});
  };
  builtin("step", Type::Int);
  builtin("t", Type::Real);
}

void Sema::declare_observable(const ast::ObservableDecl& decl) {
  declare_global(decl.name, "observable");
  const Type type = type_named(decl.type, true);
  Scope scope;
  scope.context = "the initial value of an observable";
  Expr initial =
      convert(check(decl.value, scope), type, decl.value.loc, "observable " + decl.name.name);
  model_.observables.push_back({decl.name.name, type, initial, false, decl.loc});
  names_.emplace(decl.name.name,
                 Name{Name::Observable, static_cast<int>(model_.observables.size() - 1)});
}

void Sema::check_timestep(const ast::TimestepDecl& decl) {
  if (model_.timestep)
    fail(decl.loc, "a second timestep declaration",
         "the first is on line " +
             std::to_string(file_.line_column(model_.timestep->loc.begin).line));
  Scope scope;
  scope.context = "the timestep";
  scope.observables = true;  // an adaptive step reads what the last one measured
  Expr dt = check(decl.value, scope);
  if (!ir::is_numeric_scalar(dt->type))
    fail(decl.value.loc, "the timestep must be a number, not " + a_type(dt->type));
  if (auto value = evaluate_constant(dt, model_); value && !(*value > 0))
    fail(decl.value.loc, "the timestep must be positive");
  model_.timestep = dt;
}

// Which observables the run logs: step always, t when there is a timestep.
// The output interval: an int of params and consts, at least 1.
Expr Sema::check_output_interval(const ast::Chain& every) {
  Scope scope;
  scope.context = "the output interval";
  Expr e = convert(check(every, scope), Type::Int, every.loc, "the output interval");
  if (auto value = evaluate_constant(e, model_); value && !(*value >= 1))
    fail(every.loc, "the output interval must be at least 1 step");
  return e;
}

void Sema::check_frames(const ast::OutputDecl& decl) {
  const int set = set_named(*decl.set);
  for (const ir::Frames& f : model_.frames)
    if (f.set == set)
      fail(decl.set->loc, "a second output declaration for set " + quoted(decl.set->name),
           "the first is on line " + std::to_string(file_.line_column(f.loc.begin).line));
  const ir::ParticleSet& s = model_.sets[set];
  ir::Frames frames{set, {}, nullptr, decl.loc};
  for (const ast::Identifier& name : decl.names) {
    const int var = s.find_var(name.name);
    follow_on_if_failed(name.name);
    if (var < 0) {
      std::vector<std::string> known;
      for (const ir::Variable& v : s.vars) known.push_back(v.name);
      fail(name.loc, quoted(name.name) + " is not a variable of particle set " + s.name +
                         suggestion(name.name, known));
    }
    if (var == ir::kPosition || var == ir::kId)
      fail(name.loc, quoted(name.name) + " is always written", "list only the other variables");
    if (std::find(frames.vars.begin(), frames.vars.end(), var) != frames.vars.end())
      fail(name.loc, quoted(name.name) + " listed twice");
    frames.vars.push_back(var);
  }
  if (decl.every) frames.every = check_output_interval(*decl.every);
  model_.frames.push_back(std::move(frames));
}

void Sema::check_output(const ast::OutputDecl& decl) {
  if (decl.set) return check_frames(decl);
  if (model_.log.loc.end != 0)
    fail(decl.loc, "a second output declaration",
         "the first is on line " + std::to_string(file_.line_column(model_.log.loc.begin).line));
  std::vector<int> chosen;
  for (const ast::Identifier& name : decl.names) {
    const auto it = names_.find(name.name);
    follow_on_if_failed(name.name);
    if (it == names_.end() || it->second.kind != Name::Observable) {
      for (const ir::ParticleSet& s : model_.sets)
        if (s.find_var(name.name) >= 0)
          fail(name.loc, quoted(name.name) + " is a particle variable, not an observable",
               "output lists observables; choose the variables VTK frames hold with output " +
                   s.name + ": " + name.name + ", ... (or sum them into an observable)");
      std::vector<std::string> known;
      for (const ir::Observable& o : model_.observables) known.push_back(o.name);
      fail(name.loc, "unknown observable " + quoted(name.name) + suggestion(name.name, known),
           "declare it with: observable " + name.name + ": real = 0");
    }
    if (std::find(chosen.begin(), chosen.end(), it->second.index) != chosen.end())
      fail(name.loc, quoted(name.name) + " listed twice");
    chosen.push_back(it->second.index);
  }
  if (decl.every) model_.log.every = check_output_interval(*decl.every);
  model_.log.observables = std::move(chosen);
  model_.log.loc = decl.loc;
}

}  // namespace partc::sema
