// Sema: stage blocks, their statements, and the schedule.
#include <set>

#include "ir/constant.hpp"
#include "sema/checker.hpp"

namespace partc::sema {

void Sema::check_stage(const ast::StageBlock& block) {
  ir::Stage stage;
  stage.kind = block.kind == "init" ? ir::StageKind::Init : ir::StageKind::Step;
  stage.loc = block.loc;
  stage.set = -1;
  try {
    stage.set = resolve_stage_set(block);
  } catch (const SemaError& e) {
    if (!e.follow_on) diagnostics_.push_back(e.diagnostic);
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
        fail(
            a.name->loc, "a second statement named " + quoted(a.name->name),
            "the first is on line " + std::to_string(file_.line_column(it->second.loc.begin).line));
      stage.statements.back().name = a.name->name;
    });
  model_.stages.push_back(std::move(stage));
}

int Sema::resolve_stage_set(const ast::StageBlock& block) {
  if (block.set) return set_named(*block.set);
  if (model_.sets.empty()) throw SemaError{{}, true};  // "a model needs a set" says it
  if (model_.sets.size() != 1)
    fail(block.loc, "this model has several particle sets: name the one this " + block.kind +
                        " block updates, as in '" + block.kind + " " + model_.sets[0].name +
                        " { ... }'");
  return 0;
}

int Sema::set_named(const ast::Identifier& name) {
  auto it = names_.find(name.name);
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

ir::Statement Sema::check_statement(const ast::Assignment& a, int set_index) {
  const ir::ParticleSet& set = model_.sets[set_index];
  ir::Statement st;
  st.set = set_index;
  st.loc = a.loc;
  st.line = file_.line_column(a.loc.begin).line;
  st.var = set.find_var(a.target.var.name);
  if (st.var < 0) not_assignable(a.target.var, set);
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

void Sema::check_schedule(const ast::ScheduleItem& item) {
  auto named = statement_names_.find(item.statement.name);
  if (named == statement_names_.end()) {
    std::vector<std::string> known;
    for (const auto& [name, unused] : statement_names_) known.push_back(name);
    fail(item.statement.loc,
         "no statement named " + quoted(item.statement.name) +
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
        fail(option.value.loc, "the skin must be a number, not " + a_type(skin->type));
      if (auto value = evaluate_constant(skin, model_); value && !(*value >= 0))
        fail(option.value.loc, "the skin must not be negative");
      st.schedule.skin = skin;
    } else {
      fail(option.key.loc,
           "unknown schedule option " + quoted(option.key.name) +
               suggestion(option.key.name, {"search", "skin"}),
           "options: search = auto | brute_force | cell_list | kd_tree; skin = LENGTH");
    }
  }
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

std::vector<std::string> Sema::var_names(const ir::ParticleSet& set) {
  std::vector<std::string> out;
  for (const auto& v : set.vars) out.push_back(v.name);
  return out;
}

}  // namespace partc::sema
