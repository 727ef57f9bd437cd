#include "sema/sema.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "ir/constant.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace {

using ir::Expr;
using ir::Type;

// One user error; caught per declaration and statement so that one bad
// line does not hide the next.
struct SemaError {
  Diagnostic diagnostic;
};

[[noreturn]] void fail(Location loc, std::string message, std::string note = {}) {
  throw SemaError{Diagnostic{loc, std::move(message), std::move(note)}};
}

std::string quoted(const std::string& name) { return "'" + name + "'"; }

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t k = 0; k <= b.size(); ++k) row[k] = k;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t k = 1; k <= b.size(); ++k) {
      const std::size_t next = std::min({row[k] + 1, row[k - 1] + 1,
                                         diagonal + (a[i - 1] == b[k - 1] ? 0 : 1)});
      diagonal = row[k];
      row[k] = next;
    }
  }
  return row[b.size()];
}

// "; did you mean 'rc'?" when a known name is close to the unknown one.
std::string suggestion(const std::string& name, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const std::string& k : known) {
    const std::size_t d = edit_distance(name, k);
    if (d < best_distance && d < name.size()) best_distance = d, best = k;
  }
  return best.empty() ? "" : "; did you mean " + quoted(best) + "?";
}

struct FunctionInfo {
  ir::Function fn;
  int arity;
};
const std::map<std::string, FunctionInfo> kFunctions = {
    {"exp", {ir::Function::Exp, 1}},   {"log", {ir::Function::Log, 1}},
    {"sqrt", {ir::Function::Sqrt, 1}}, {"pow", {ir::Function::Pow, 2}},
    {"abs", {ir::Function::Abs, 1}},   {"min", {ir::Function::Min, 2}},
    {"max", {ir::Function::Max, 2}},   {"dot", {ir::Function::Dot, 2}},
    {"norm", {ir::Function::Norm, 1}}, {"floor", {ir::Function::Floor, 1}},
    {"sin", {ir::Function::Sin, 1}},   {"cos", {ir::Function::Cos, 1}},
};

const std::map<std::string, ir::Reduction> kReductions = {
    {"sum", ir::Reduction::Sum},
    {"min", ir::Reduction::Min},
    {"max", ir::Reduction::Max},
    {"count", ir::Reduction::Count},
};

const std::map<std::string, Type> kTypeNames = {
    {"real", Type::Real}, {"int", Type::Int}, {"bool", Type::Bool}, {"vec", Type::Vec}};

const char* const kAxisNames[] = {"x", "y", "z", "w"};

// Where an expression appears decides what it may refer to.
struct Scope {
  enum class Where { Constant, Initialiser, Statement };
  Where where = Where::Constant;
  std::string context;  // "a param default", ... for messages
  std::vector<ir::Label>* labels = nullptr;
  std::vector<int> bound;  // labels visible here, innermost last
  bool in_accumulation = false;
  const ir::UserFn* function = nullptr;  // whose arguments are in scope
};

class Sema {
 public:
  explicit Sema(const SourceFile& file) : file_(file) {}

  ir::Model run(const ast::Program& program) {
    const ast::DomainDecl& domain = collect_header(program);
    for (const ast::Declaration& decl : program.declarations) guarded([&] { declare(decl); });
    // After the consts, which its bounds may name.
    guarded([&] { check_domain(domain); });
    if (model_.sets.empty() && errors_.empty())
      errors_.push_back({Location{}, "a model needs at least one particle set",
                         "declare one with: particles P(N) { v: vec = 0 }"});
    for (const ast::Declaration& decl : program.declarations)
      if (auto stage = boost::get<ast::StageBlock>(&decl)) check_stage(*stage);
    for (const ast::Declaration& decl : program.declarations)
      if (auto schedule = boost::get<ast::ScheduleBlock>(&decl))
        for (const ast::ScheduleItem& item : schedule->items) guarded([&] { check_schedule(item); });
    if (!errors_.empty()) throw CompileError(errors_);
    return std::move(model_);
  }

 private:
  template <class F>
  void guarded(F&& f) {
    try {
      f();
    } catch (const SemaError& e) {
      errors_.push_back(e.diagnostic);
    }
  }

  // ---- model and dim: needed before anything else has a type; domain ----

  // Returns the domain declaration, checked once the consts are declared.
  const ast::DomainDecl& collect_header(const ast::Program& program) {
    const ast::ModelDecl* model = nullptr;
    const ast::DimDecl* dim = nullptr;
    const ast::DomainDecl* domain = nullptr;
    auto once = [&](auto*& seen, const auto& decl, const char* what) {
      if (seen)
        errors_.push_back({decl.loc, std::string("a second ") + what + " declaration",
                           "the first is on line " +
                               std::to_string(file_.line_column(seen->loc.begin).line)});
      else
        seen = &decl;
    };
    for (const ast::Declaration& decl : program.declarations) {
      if (auto m = boost::get<ast::ModelDecl>(&decl)) once(model, *m, "model");
      if (auto d = boost::get<ast::DimDecl>(&decl)) once(dim, *d, "dim");
      if (auto d = boost::get<ast::DomainDecl>(&decl)) once(domain, *d, "domain");
    }
    const Location start{0, 1};
    if (!model) errors_.push_back({start, "missing 'model NAME' declaration"});
    if (!dim) errors_.push_back({start, "missing 'dim N' declaration"});
    if (!domain)
      errors_.push_back({start, "missing 'domain lo=(...) hi=(...)' declaration"});
    if (!errors_.empty()) throw CompileError(errors_);

    model_.name = model->name.name;
    model_.dim = static_cast<int>(dim->value.value);
    if (dim->value.value < 1 || dim->value.value > 4)
      throw CompileError(Diagnostic{dim->value.loc, "dim must be 1, 2, 3 or 4"});
    return *domain;
  }

  void check_domain(const ast::DomainDecl& decl) {
    auto bounds = [&](const std::vector<ast::Chain>& tuple, const char* which) {
      if (static_cast<int>(tuple.size()) != model_.dim)
        fail(tuple.front().loc, std::string(which) + " has " + std::to_string(tuple.size()) +
                                    " components but the model has dim " +
                                    std::to_string(model_.dim));
      std::vector<double> values;
      Scope scope;
      scope.context = "a domain bound";
      for (const ast::Chain& c : tuple) values.push_back(constant_number(check(c, scope), c.loc, scope));
      return values;
    };
    model_.domain.lo = bounds(decl.lo, "lo");
    model_.domain.hi = bounds(decl.hi, "hi");
    for (int k = 0; k < model_.dim; ++k)
      if (!(model_.domain.lo[k] < model_.domain.hi[k]))
        fail(decl.hi[k].loc, "the domain is empty along " + std::string(kAxisNames[k]) +
                                 ": hi must be greater than lo");
    model_.domain.periodic.assign(model_.dim, false);
    if (!decl.periodic) return;
    for (const ast::Identifier& axis : *decl.periodic) {
      const auto* it = std::find(std::begin(kAxisNames), std::begin(kAxisNames) + model_.dim,
                                 axis.name);
      if (it == std::begin(kAxisNames) + model_.dim)
        fail(axis.loc, "unknown axis " + quoted(axis.name) + " for a " +
                           std::to_string(model_.dim) + "-dimensional domain",
             "axes are named x, y, z, w");
      const auto k = it - std::begin(kAxisNames);
      if (model_.domain.periodic[k]) fail(axis.loc, "axis " + quoted(axis.name) + " listed twice");
      model_.domain.periodic[k] = true;
    }
  }

  // ---- declarations -----------------------------------------------------

  void declare_global(const ast::Identifier& name, const char* kind) {
    if (is_builtin_name(name.name))
      fail(name.loc, quoted(name.name) + " is a builtin name and cannot be redefined");
    auto [it, fresh] = globals_.emplace(name.name, name.loc);
    if (!fresh)
      fail(name.loc, std::string("redefinition of ") + quoted(name.name) + " as a " + kind,
           "first defined on line " + std::to_string(file_.line_column(it->second.begin).line));
  }

  Type type_named(const ast::Identifier& name, bool allow_vec) {
    auto it = kTypeNames.find(name.name);
    if (it == kTypeNames.end() || (!allow_vec && it->second == Type::Vec))
      fail(name.loc, "unknown type " + quoted(name.name),
           allow_vec ? "types are real, int, bool and vec" : "param types are real, int and bool");
    return it->second;
  }

  void declare(const ast::Declaration& decl) {
    if (auto p = boost::get<ast::ParamDecl>(&decl)) declare_param(*p);
    if (auto c = boost::get<ast::ConstDecl>(&decl)) declare_const(*c);
    if (auto f = boost::get<ast::FnDecl>(&decl)) declare_fn(*f);
    if (auto s = boost::get<ast::ParticlesDecl>(&decl)) declare_set(*s);
  }

  void declare_param(const ast::ParamDecl& decl) {
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
    model_.params.push_back({decl.name.name, type,
                             std::make_shared<ir::Literal>(type, value, decl.value.loc), decl.loc});
    names_.emplace(decl.name.name, Name{Name::Param, static_cast<int>(model_.params.size() - 1)});
  }

  void declare_const(const ast::ConstDecl& decl) {
    declare_global(decl.name, "const");
    Scope scope;
    scope.context = "a const";
    Expr value = check(decl.value, scope);
    model_.consts.push_back({decl.name.name, value->type, value, decl.loc});
    names_.emplace(decl.name.name, Name{Name::Const, static_cast<int>(model_.consts.size() - 1)});
  }

  void declare_fn(const ast::FnDecl& decl) {
    declare_global(decl.name, "function");
    ir::UserFn fn;
    fn.name = decl.name.name;
    fn.loc = decl.loc;
    for (const ast::FnParam& a : decl.params) {
      if (std::find(fn.arg_names.begin(), fn.arg_names.end(), a.name.name) != fn.arg_names.end())
        fail(a.name.loc, "argument " + quoted(a.name.name) + " listed twice");
      if (names_.count(a.name.name) || is_builtin_name(a.name.name))
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

  void declare_set(const ast::ParticlesDecl& decl) {
    declare_global(decl.name, "particle set");
    ir::ParticleSet set;
    set.name = decl.name.name;
    set.loc = decl.loc;
    Scope count_scope;
    count_scope.context = "a particle count";
    set.initial_count = convert(check(decl.count, count_scope), Type::Int, decl.count.loc,
                                "the particle count of " + set.name);
    set.vars.push_back({"p", Type::Vec, nullptr, true, decl.name.loc});
    set.vars.push_back({"id", Type::Int, nullptr, true, decl.name.loc});
    set.vars.push_back({"alive", Type::Bool, nullptr, true, decl.name.loc});
    const int set_index = static_cast<int>(model_.sets.size());
    for (const ast::VarDecl& var : decl.vars) {
      guarded([&] {
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
          initial = convert(check(*var.value, scope), type, var.value->loc,
                            "variable " + var.name.name);
        }
        set.vars.push_back({var.name.name, type, initial, false, var.loc});
      });
    }
    model_.sets.push_back(std::move(set));
    names_.emplace(decl.name.name, Name{Name::Set, set_index});
  }

  // ---- stages and statements --------------------------------------------

  void check_stage(const ast::StageBlock& block) {
    ir::Stage stage;
    stage.kind = block.kind == "init" ? ir::StageKind::Init : ir::StageKind::Step;
    stage.loc = block.loc;
    stage.set = -1;
    try {
      stage.set = resolve_stage_set(block);
    } catch (const SemaError& e) {
      errors_.push_back(e.diagnostic);
      return;
    }
    const int stage_index = static_cast<int>(model_.stages.size());
    for (const ast::Assignment& a : block.body)
      guarded([&] {
        stage.statements.push_back(check_statement(a, stage.set));
        if (!a.name) return;
        const auto [it, fresh] = statement_names_.emplace(
            a.name->name,
            StatementRef{stage_index, static_cast<int>(stage.statements.size() - 1), a.name->loc});
        if (!fresh)
          fail(a.name->loc, "a second statement named " + quoted(a.name->name),
               "the first is on line " + std::to_string(file_.line_column(it->second.loc.begin).line));
        stage.statements.back().name = a.name->name;
      });
    model_.stages.push_back(std::move(stage));
  }

  int resolve_stage_set(const ast::StageBlock& block) {
    if (block.set) return set_named(*block.set);
    if (model_.sets.size() != 1)
      fail(block.loc, "this model has several particle sets: name the one this " + block.kind +
                          " block updates, as in '" + block.kind + " " + model_.sets[0].name +
                          " { ... }'");
    return 0;
  }

  int set_named(const ast::Identifier& name) {
    auto it = names_.find(name.name);
    if (it == names_.end() || it->second.kind != Name::Set)
      fail(name.loc, "unknown particle set " + quoted(name.name) + suggestion(name.name, set_names()));
    return it->second.index;
  }

  std::vector<std::string> set_names() const {
    std::vector<std::string> out;
    for (const auto& s : model_.sets) out.push_back(s.name);
    return out;
  }

  ir::Statement check_statement(const ast::Assignment& a, int set_index) {
    const ir::ParticleSet& set = model_.sets[set_index];
    ir::Statement st;
    st.set = set_index;
    st.loc = a.loc;
    st.line = file_.line_column(a.loc.begin).line;
    st.var = set.find_var(a.target.var.name);
    if (st.var < 0)
      fail(a.target.var.loc, quoted(a.target.var.name) + " is not a variable of particle set " +
                                 set.name + suggestion(a.target.var.name, var_names(set)));
    const ir::Variable& var = set.vars[st.var];
    if (st.var == ir::kId) fail(a.target.var.loc, "'id' is read-only: particle ids never change");
    st.labels.push_back({a.target.label.name, set_index});
    statement_target_ = a.target.loc;
    for (const ir::ParticleSet& s : model_.sets)
      if (s.find_var(a.target.label.name) >= 0 || names_.count(a.target.label.name))
        fail(a.target.label.loc, "label " + quoted(a.target.label.name) +
                                     " has the name of a variable, param, const or set");
    static const std::map<std::string, ir::AssignOp> ops = {{"=", ir::AssignOp::Set},
                                                            {"+=", ir::AssignOp::Add},
                                                            {"-=", ir::AssignOp::Sub},
                                                            {"*=", ir::AssignOp::Mul},
                                                            {"/=", ir::AssignOp::Div}};
    st.op = ops.at(a.op);

    Scope scope;
    scope.where = Scope::Where::Statement;
    scope.context = "a statement";
    scope.labels = &st.labels;
    scope.bound = {0};
    Expr value = check(a.value, scope);
    const std::string what = "variable " + var.name;
    const Location at = a.value.loc;
    switch (st.op) {
      case ir::AssignOp::Set: value = convert(value, var.type, at, what); break;
      case ir::AssignOp::Add:
      case ir::AssignOp::Sub:
        if (var.type == Type::Bool)
          fail(a.loc, "bool variable " + quoted(var.name) + " can only be assigned with '='");
        value = convert(value, var.type, at, what);
        break;
      case ir::AssignOp::Mul:
      case ir::AssignOp::Div:
        if (var.type == Type::Bool)
          fail(a.loc, "bool variable " + quoted(var.name) + " can only be assigned with '='");
        if (var.type == Type::Int && st.op == ir::AssignOp::Div)
          fail(a.loc, "int variable " + quoted(var.name) + " cannot be divided in place",
               "'/' gives a real; assign to a real variable instead");
        value = convert(value, var.type == Type::Vec ? Type::Real : var.type, at,
                        var.type == Type::Vec ? "the scale factor of vec " + var.name : what);
        break;
    }
    st.value = value;
    return st;
  }

  // ---- schedule ---------------------------------------------------------

  void check_schedule(const ast::ScheduleItem& item) {
    auto named = statement_names_.find(item.statement.name);
    if (named == statement_names_.end()) {
      std::vector<std::string> known;
      for (const auto& [name, unused] : statement_names_) known.push_back(name);
      fail(item.statement.loc, "no statement named " + quoted(item.statement.name) +
                                   suggestion(item.statement.name, known),
           "name a statement where it is written: force: v[i] += sum(...)");
    }
    ir::Statement& st = model_.stages[named->second.stage].statements[named->second.statement];
    if (st.schedule.loc.end != 0)
      fail(item.statement.loc, "statement " + quoted(st.name) + " is scheduled twice");
    st.schedule.loc = item.loc;
    std::set<std::string> seen;
    for (const ast::ScheduleOption& option : item.options) {
      if (!seen.insert(option.key.name).second)
        fail(option.key.loc, "option " + quoted(option.key.name) + " given twice");
      if (option.key.name == "search") {
        st.schedule.search = search_choice(option.value);
      } else if (option.key.name == "skin") {
        Scope scope;
        scope.context = "a skin";
        Expr skin = check(option.value, scope);
        if (!ir::is_numeric_scalar(skin->type))
          fail(option.value.loc, "the skin must be a number, not a " + std::string(type_name(skin->type)));
        if (auto value = evaluate_constant(skin, model_); value && !(*value >= 0))
          fail(option.value.loc, "the skin must not be negative");
        st.schedule.skin = skin;
      } else {
        fail(option.key.loc, "unknown schedule option " + quoted(option.key.name) +
                                 suggestion(option.key.name, {"search", "skin"}),
             "options: search = auto | brute_force | cell_list | kd_tree; skin = LENGTH");
      }
    }
  }

  ir::SearchChoice search_choice(const ast::Chain& value) {
    const ast::Operand* sole = ast::sole_operand(value);
    const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
    for (ir::SearchChoice c : {ir::SearchChoice::Auto, ir::SearchChoice::BruteForce,
                               ir::SearchChoice::CellList, ir::SearchChoice::KdTree})
      if (id && id->name == ir::search_choice_name(c)) return c;
    fail(value.loc, "unknown search " + quoted(source_text(value.loc)),
         "searches: auto, brute_force, cell_list, kd_tree");
  }

  static std::vector<std::string> var_names(const ir::ParticleSet& set) {
    std::vector<std::string> out;
    for (const auto& v : set.vars) out.push_back(v.name);
    return out;
  }

  // ---- conversions ------------------------------------------------------

  // The value converted to `to` for storing in `what`, or an error.
  Expr convert(Expr value, Type to, Location at, const std::string& what) {
    const Type from = value->type;
    if (from == to) return value;
    if (from == Type::Int && to == Type::Real) return value;  // C++ promotes
    if (to == Type::Vec && ir::is_numeric_scalar(from)) {
      if (is_uniform(value)) {
        std::vector<Expr> components(model_.dim, value);
        return std::make_shared<ir::MakeVec>(std::move(components), value->loc);
      }
      fail(at, "cannot store a " + std::string(type_name(from)) + " in " + what +
                   ", which is a vec",
           "a vec needs " + std::to_string(model_.dim) +
               " components: write vec(...), or a vector expression");
    }
    if (from == Type::Real && to == Type::Int)
      fail(at, "cannot store a real in " + what + ", which is an int",
           "int values are exact; round explicitly, e.g. with floor(), into a real variable");
    fail(at, "cannot store a " + std::string(type_name(from)) + " in " + what + ", which is a " +
                 type_name(to));
  }

  double constant_number(const Expr& e, Location at, const Scope& scope) {
    if (!ir::is_numeric_scalar(e->type) && e->type != Type::Bool)
      fail(at, scope.context + " must be a number, not a " + type_name(e->type));
    auto value = evaluate_constant(e, model_);
    if (!value)
      fail(at, scope.context + " must be known when partc runs",
           "use literals and consts built from literals here, not params");
    if (!std::isfinite(*value))
      fail(at, scope.context + " evaluates to " + std::to_string(*value));
    return *value;
  }

  // ---- expressions ------------------------------------------------------

  Expr check(const ast::Chain& chain, Scope& scope) {
    Expr lhs = check(chain.first, scope);
    std::optional<ir::BinaryOp> previous_comparison;
    for (const ast::BinaryOp& step : chain.rest) {
      Expr rhs = check(step.rhs, scope);
      const Location loc{ast::location_of(chain.first).begin, step.loc.end};
      const ir::BinaryOp op = binary_op(step.op);
      const bool comparison = op >= ir::BinaryOp::Lt && op <= ir::BinaryOp::Ne;
      if (comparison && previous_comparison)
        fail(loc, "comparisons do not chain",
             "write 'a < b and b < c' instead of 'a < b < c'");
      if (comparison) previous_comparison = op;
      lhs = binary(op, lhs, rhs, loc, step.loc);
    }
    return lhs;
  }

  static ir::BinaryOp binary_op(const std::string& s) {
    static const std::map<std::string, ir::BinaryOp> ops = {
        {"+", ir::BinaryOp::Add}, {"-", ir::BinaryOp::Sub},  {"*", ir::BinaryOp::Mul},
        {"/", ir::BinaryOp::Div}, {"<", ir::BinaryOp::Lt},   {"<=", ir::BinaryOp::Le},
        {">", ir::BinaryOp::Gt},  {">=", ir::BinaryOp::Ge},  {"==", ir::BinaryOp::Eq},
        {"!=", ir::BinaryOp::Ne}, {"and", ir::BinaryOp::And}, {"or", ir::BinaryOp::Or}};
    return ops.at(s);
  }

  Expr binary(ir::BinaryOp op, Expr a, Expr b, Location loc, Location op_loc) {
    const Type ta = a->type, tb = b->type;
    const std::string spelled = binary_op_spelling(op);
    auto mismatch = [&](std::string note = {}) -> Expr {
      fail(op_loc, "'" + spelled + "' cannot combine a " + type_name(ta) + " and a " +
                       type_name(tb),
           std::move(note));
    };
    const bool scalars = ir::is_numeric_scalar(ta) && ir::is_numeric_scalar(tb);
    const Type numeric = ta == Type::Int && tb == Type::Int ? Type::Int : Type::Real;
    Type result = Type::Bool;
    switch (op) {
      case ir::BinaryOp::Add:
      case ir::BinaryOp::Sub:
        if (scalars) result = numeric;
        else if (ta == Type::Vec && tb == Type::Vec) result = Type::Vec;
        else return mismatch("vectors add only to vectors");
        break;
      case ir::BinaryOp::Mul:
        if (scalars) result = numeric;
        else if ((ta == Type::Vec && ir::is_numeric_scalar(tb)) ||
                 (tb == Type::Vec && ir::is_numeric_scalar(ta)))
          result = Type::Vec;
        else if (ta == Type::Vec && tb == Type::Vec)
          return mismatch("for the inner product write dot(a, b)");
        else return mismatch();
        break;
      case ir::BinaryOp::Div:
        // int / int is real division: 3 / N must not silently truncate to 0.
        if (scalars) result = Type::Real;
        else if (ta == Type::Vec && ir::is_numeric_scalar(tb)) result = Type::Vec;
        else return mismatch();
        break;
      case ir::BinaryOp::Lt:
      case ir::BinaryOp::Le:
      case ir::BinaryOp::Gt:
      case ir::BinaryOp::Ge:
        if (!scalars) return mismatch(ta == Type::Vec || tb == Type::Vec
                                          ? "compare lengths instead, e.g. |dx| < rc"
                                          : "");
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
    return std::make_shared<ir::Binary>(result, op, a, b, loc);
  }

  struct CheckOperand {
    Sema& sema;
    Scope& scope;
    Expr operator()(const ast::IntLiteral& n) const {
      return std::make_shared<ir::Literal>(Type::Int, static_cast<double>(n.value), n.loc);
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
        return std::make_shared<ir::Call>(inner->type, ir::Function::Abs,
                                          std::vector<Expr>{inner}, n.loc);
      fail(n.loc, "|...| needs a number or a vec, not a bool");
    }
    Expr operator()(const ast::Unary& n) const {
      Expr a = sema.check(n.operand, scope);
      if (n.op == "not") {
        if (a->type != Type::Bool) fail(n.loc, "'not' needs a bool, not a " + std::string(type_name(a->type)));
        return std::make_shared<ir::Unary>(Type::Bool, ir::UnaryOp::Not, a, n.loc);
      }
      if (a->type == Type::Bool)
        fail(n.loc, "'" + n.op + "' needs a number or a vec, not a bool");
      if (n.op == "+") return a;
      return std::make_shared<ir::Unary>(a->type, ir::UnaryOp::Neg, a, n.loc);
    }
    Expr operator()(const ast::Postfix& n) const {
      Expr e = sema.check(n.base, scope);
      for (const ast::Identifier& c : n.components) {
        if (e->type != Type::Vec)
          fail(c.loc, "." + c.name + " needs a vec, not a " + type_name(e->type));
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

  Expr check(const ast::Operand& operand, Scope& scope) {
    return boost::apply_visitor(CheckOperand{*this, scope}, operand);
  }

  Expr check_name(const ast::Identifier& n, Scope& scope) {
    if (n.name == "dx") {
      if (!scope.in_accumulation)
        fail(n.loc, "dx is only defined inside an accumulation",
             "dx is the shortest vector from particle i to particle j, as in sum(j, |dx| < rc, ...)");
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
        case Name::Set:
          fail(n.loc, quoted(n.name) + " is a particle set, not a value");
        case Name::Fn:
          fail(n.loc, quoted(n.name) + " is a function; call it, as in " + n.name + "(...)");
      }
    }
    if (kFunctions.count(n.name) || kReductions.count(n.name) || is_random_function(n.name))
      fail(n.loc, quoted(n.name) + " is a function; call it, as in " + n.name + "(...)");
    if (scope.labels) {
      for (const ir::Label& l : *scope.labels)
        if (l.name == n.name)
          fail(n.loc, quoted(n.name) + " is a label; index a variable with it, as in v[" + n.name + "]");
      for (const ir::ParticleSet& s : model_.sets)
        if (s.find_var(n.name) >= 0)
          fail(n.loc, quoted(n.name) + " is a particle variable; index it with a label, as in " +
                          n.name + "[" + scope.labels->front().name + "]");
    }
    std::vector<std::string> known;
    for (const auto& [name, unused] : names_) known.push_back(name);
    fail(n.loc, "unknown name " + quoted(n.name) + suggestion(n.name, known));
  }

  Expr check_indexed(const ast::Indexed& n, Scope& scope) {
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
          fail(n.label.loc, "label " + quoted(n.label.name) + " is only bound inside its accumulation");
      fail(n.label.loc, "label " + quoted(n.label.name) + " is not bound here",
           "a statement names its own particle by the label of its target (" +
               scope.labels->front().name + "); other particles are named by an accumulation, as in sum(" +
               n.label.name + ", ...)");
    }
    const int set_index = (*scope.labels)[label].set;
    const ir::ParticleSet& set = model_.sets[set_index];
    const int var = set.find_var(n.var.name);
    if (var < 0)
      fail(n.var.loc, quoted(n.var.name) + " is not a variable of particle set " + set.name +
                          suggestion(n.var.name, var_names(set)));
    return std::make_shared<ir::VarRef>(set.vars[var].type, set_index, var, label, n.loc);
  }

  static bool is_builtin_name(const std::string& name) {
    return kFunctions.count(name) || kReductions.count(name) || name == "dx" || name == "vec" ||
           is_random_function(name);
  }

  static bool is_random_function(const std::string& name) {
    return name == "uniform" || name == "normal" || name == "uniform_vec" || name == "normal_vec";
  }

  Expr check_call(const ast::Call& n, Scope& scope) {
    const std::string& name = n.callee.name;
    const bool binding = !n.args.empty() && boost::get<ast::LabelBinding>(&n.args.front());
    const auto reduction = kReductions.find(name);
    if (reduction != kReductions.end() &&
        (name == "sum" || name == "count" || binding || n.args.size() == 3))
      return check_accumulation(n, reduction->second, scope);
    if (binding)
      fail(ast::location_of(n.args.front()),
           "'in' binds a label only as the first argument of sum, count, min or max");
    if (is_random_function(name)) return check_random(n, scope);
    std::vector<Expr> args;
    for (const ast::Argument& a : n.args) args.push_back(check(boost::get<ast::Chain>(a), scope));
    if (name == "vec") {
      if (static_cast<int>(args.size()) != model_.dim)
        fail(n.loc, "vec(...) needs " + std::to_string(model_.dim) + " components in a " +
                        std::to_string(model_.dim) + "-dimensional model, not " +
                        std::to_string(args.size()));
      for (std::size_t k = 0; k < args.size(); ++k)
        if (!ir::is_numeric_scalar(args[k]->type))
          fail(args[k]->loc, "a vec component must be a number, not a " +
                                 std::string(type_name(args[k]->type)));
      return std::make_shared<ir::MakeVec>(std::move(args), n.loc);
    }
    if (scope.function && name == scope.function->name)
      fail(n.callee.loc, "function " + quoted(name) + " calls itself",
           "functions are not recursive; write the repetition out");
    if (auto user = names_.find(name); user != names_.end() && user->second.kind == Name::Fn)
      return check_user_call(n, user->second.index, std::move(args));
    auto fn = kFunctions.find(name);
    if (fn == kFunctions.end()) {
      std::vector<std::string> known = {"vec", "sum", "count", "uniform", "normal", "uniform_vec",
                                        "normal_vec"};
      for (const auto& [k, unused] : kFunctions) known.push_back(k);
      for (const auto& f : model_.functions) known.push_back(f.name);
      fail(n.callee.loc, "unknown function " + quoted(name) + suggestion(name, known));
    }
    if (static_cast<int>(args.size()) != fn->second.arity)
      fail(n.loc, name + "() takes " + std::to_string(fn->second.arity) + " argument" +
                      (fn->second.arity == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
    return std::make_shared<ir::Call>(call_type(fn->second.fn, name, args), fn->second.fn,
                                      std::move(args), n.loc);
  }

  Expr check_user_call(const ast::Call& n, int index, std::vector<Expr> args) {
    const ir::UserFn& fn = model_.functions[index];
    if (args.size() != fn.arg_names.size())
      fail(n.loc, fn.name + "() takes " + std::to_string(fn.arg_names.size()) + " argument" +
                      (fn.arg_names.size() == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
    for (std::size_t k = 0; k < args.size(); ++k)
      args[k] = convert(args[k], fn.arg_types[k], args[k]->loc,
                        "argument " + fn.arg_names[k] + " of " + fn.name);
    return std::make_shared<ir::FnCall>(fn.body->type, index, std::move(args), n.loc);
  }

  Type call_type(ir::Function fn, const std::string& name, const std::vector<Expr>& args) {
    auto need = [&](std::size_t k, bool ok, const char* what) {
      if (!ok)
        fail(args[k]->loc, name + "() needs " + what + ", not a " + type_name(args[k]->type));
    };
    switch (fn) {
      case ir::Function::Dot:
        need(0, args[0]->type == Type::Vec, "vecs");
        need(1, args[1]->type == Type::Vec, "vecs");
        return Type::Real;
      case ir::Function::Norm:
        need(0, args[0]->type == Type::Vec, "a vec");
        return Type::Real;
      case ir::Function::Abs:
        need(0, ir::is_numeric_scalar(args[0]->type), "a number (for a vec's length use |v|)");
        return args[0]->type;
      case ir::Function::Min:
      case ir::Function::Max:
        need(0, ir::is_numeric_scalar(args[0]->type), "numbers");
        need(1, ir::is_numeric_scalar(args[1]->type), "numbers");
        return args[0]->type == Type::Int && args[1]->type == Type::Int ? Type::Int : Type::Real;
      default:
        for (std::size_t k = 0; k < args.size(); ++k)
          need(k, ir::is_numeric_scalar(args[k]->type), "a number");
        return Type::Real;
    }
  }

  Expr check_random(const ast::Call& n, Scope& scope) {
    if (!n.args.empty()) fail(n.loc, n.callee.name + "() takes no arguments");
    if (scope.where == Scope::Where::Constant)
      fail(n.loc, scope.context + " cannot be random",
           "random numbers are drawn per particle, in initial values and statements");
    if (scope.in_accumulation)
      fail(n.loc, "random numbers inside an accumulation are not supported",
           "a draw is keyed by one particle's id; draw per particle outside the sum");
    const std::string& name = n.callee.name;
    const bool vec = name.size() > 4 && name.compare(name.size() - 4, 4, "_vec") == 0;
    const auto dist = name.rfind("uniform", 0) == 0 ? ir::Distribution::Uniform
                                                    : ir::Distribution::Normal;
    return std::make_shared<ir::Random>(vec ? Type::Vec : Type::Real, dist,
                                        model_.random_streams++, n.loc);
  }

  Expr check_accumulation(const ast::Call& n, ir::Reduction reduction, Scope& scope) {
    const std::string& name = n.callee.name;
    const std::size_t expected_min = reduction == ir::Reduction::Count ? 1 : 2;
    const std::size_t expected_max = reduction == ir::Reduction::Count ? 2 : 3;
    if (n.args.size() < expected_min || n.args.size() > expected_max)
      fail(n.loc, reduction == ir::Reduction::Count
                      ? "count takes a label and an optional condition: count(j, condition)"
                      : name + " takes a label, an optional condition and a value: " + name +
                            "(j, condition, value)");
    if (scope.where != Scope::Where::Statement)
      fail(n.loc, "an accumulation over particles cannot appear in " + scope.context);
    if (scope.in_accumulation)
      fail(n.loc, "nested accumulations are not supported",
           "compute the inner one into a variable in an earlier statement");

    // The label: `j` (over the statement's set) or `j in Q`.
    ir::Label label;
    Location label_loc;
    if (auto b = boost::get<ast::LabelBinding>(&n.args.front())) {
      label = {b->label.name, set_named(b->set)};
      label_loc = b->label.loc;
    } else {
      const ast::Chain& c = boost::get<ast::Chain>(n.args.front());
      const ast::Operand* sole = ast::sole_operand(c);
      const ast::Identifier* id = sole ? boost::get<ast::Identifier>(sole) : nullptr;
      if (!id)
        fail(c.loc, "the first argument of " + name + " must be a new label, as in " + name +
                        "(j, ...)");
      label = {id->name, scope.labels->front().set};
      label_loc = id->loc;
    }
    if (label.name == scope.labels->front().name)
      fail(statement_target_, "cannot write " + source_text(statement_target_) + ": " +
                                  quoted(label.name) + " is the label of this " + name +
                                  ", which runs over other particles",
           "a statement writes only its own particle, as in v[i] += " + name + "(j, ...)");
    for (int b : scope.bound)
      if ((*scope.labels)[b].name == label.name)
        fail(label_loc, "label " + quoted(label.name) + " is already bound");
    for (const ir::ParticleSet& s : model_.sets)
      if (s.find_var(label.name) >= 0)
        fail(label_loc, "label " + quoted(label.name) + " has the name of a particle variable");
    if (names_.count(label.name) || label.name == "dx")
      fail(label_loc, "label " + quoted(label.name) + " has the name of a param, const or set");

    scope.labels->push_back(label);
    const int label_index = static_cast<int>(scope.labels->size() - 1);
    Scope inner = scope;
    inner.bound.push_back(label_index);
    inner.in_accumulation = true;

    const bool has_condition = n.args.size() == expected_max;
    Expr condition, body;
    if (has_condition) {
      condition = check(argument_chain(n.args[1], name), inner);
      if (condition->type != Type::Bool)
        fail(condition->loc, "the condition of " + name + " must be a bool, not a " +
                                 type_name(condition->type));
    }
    if (reduction != ir::Reduction::Count) {
      body = check(argument_chain(n.args.back(), name), inner);
      if (body->type == Type::Bool ||
          (body->type == Type::Vec && reduction != ir::Reduction::Sum))
        fail(body->loc, name + " cannot accumulate a " + std::string(type_name(body->type)));
    }
    const Type type = reduction == ir::Reduction::Count ? Type::Int : body->type;
    return std::make_shared<ir::Accumulate>(type, reduction, label_index, condition, body,
                                            model_.accumulations++, n.loc);
  }

  static const ast::Chain& argument_chain(const ast::Argument& a, const std::string& name) {
    if (auto c = boost::get<ast::Chain>(&a)) return *c;
    fail(ast::location_of(a), "'in' binds a label only in the first argument of " + name);
  }

  struct StatementRef {
    int stage, statement;
    Location loc;
  };

  struct Name {
    enum Kind { Param, Const, Set, Fn } kind;
    int index;
  };

  std::string source_text(Location loc) const { return std::string(file_.slice(loc)); }

  const SourceFile& file_;
  Location statement_target_;  // of the statement being checked
  ir::Model model_;
  std::vector<Diagnostic> errors_;
  std::map<std::string, Location> globals_;
  std::map<std::string, Name> names_;
  std::map<std::string, StatementRef> statement_names_;
};

}  // namespace

ir::Model build_ir(const ast::Program& program, const SourceFile& file) {
  return Sema(file).run(program);
}

}  // namespace partc
