// The semantic checker's class, shared by the files that implement it.
//
// Sema is split by concern, one file each: declarations.cpp (the model's
// header, params, consts, functions, particle sets), statements.cpp (stages,
// statements, the schedule), expressions.cpp (names, operators, conversions)
// and calls.cpp (built-in functions, user functions, random draws,
// accumulations). Internal to sema/; the entry point is sema.hpp.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ast/ast.hpp"
#include "ir/ir.hpp"
#include "support/diagnostics.hpp"
#include "support/source.hpp"

namespace partc::sema {

using ir::Expr;
using ir::Type;

// One user error; caught per declaration and statement so that one bad
// line does not hide the next.
// A follow-on error (a use of a name whose declaration failed) is silent:
// the first error says what is wrong.
struct SemaError {
  Diagnostic diagnostic;
  bool follow_on = false;
};

[[noreturn]] inline void fail(Location loc, std::string message, std::string note = {}) {
  throw SemaError{Diagnostic{loc, std::move(message), std::move(note)}};
}

inline std::string quoted(const std::string& name) { return "'" + name + "'"; }

// "an int", "a real", ...: a type as messages name it.
inline std::string a_type(ir::Type t) {
  return std::string(t == ir::Type::Int ? "an " : "a ") + ir::type_name(t);
}

// "; did you mean 'rc'?" when a known name is close to the unknown one.
std::string suggestion(const std::string& name, const std::vector<std::string>& known);

inline const std::map<std::string, Type> kTypeNames = {
    {"real", Type::Real}, {"int", Type::Int}, {"bool", Type::Bool}, {"vec", Type::Vec}};

inline const char* const kAxisNames[] = {"x", "y", "z", "w"};

// Where an expression appears decides what it may refer to.
struct Scope {
  enum class Where { Constant, Initialiser, Statement };
  Where where = Where::Constant;
  std::string context;  // "a param default", ... for messages
  std::vector<ir::Label>* labels = nullptr;
  std::vector<int> bound;  // labels visible here, innermost last
  bool in_accumulation = false;
  std::string several_sets;  // "F and W" when the innermost label runs over several sets
  bool home = true;          // there is a particle i (not in an observable's statement)
  bool observables = false;  // may read observables, which change during a run
  const ir::UserFn* function = nullptr;  // whose arguments are in scope
};

class Sema {
 public:
  explicit Sema(const SourceFile& file) : file_(file) {}
  ir::Model run(const ast::Program& program);
  // After a run that succeeded: the warnings, in the order found.
  const std::vector<Diagnostic>& warnings() const { return diagnostics_; }

 private:
  template <class F>
  void guarded(F&& f) {
    try {
      f();
    } catch (const SemaError& e) {
      if (!e.follow_on) diagnostics_.push_back(e.diagnostic);
    }
  }
  // A param, const, function or variable whose declaration fails is
  // remembered, so that its uses are not reported again as unknown names.
  template <class F>
  void poisoned(const ast::Identifier& name, F&& declare_it) {
    try {
      declare_it();
    } catch (const SemaError&) {
      if (!names_.count(name.name)) failed_names_.insert(name.name);
      throw;
    }
  }
  // Stops checking what uses a name whose declaration failed.
  void follow_on_if_failed(const std::string& name) const {
    if (failed_names_.count(name)) throw SemaError{{}, true};
  }
  void warn(Location loc, std::string message, std::string note = {}) {
    diagnostics_.push_back({loc, std::move(message), std::move(note), true});
  }

  // ---- declarations.cpp: model and dim, needed before anything else has a
  // type; the domain; params, consts, functions and sets -----------------
  // Returns the domain declaration, checked once the consts are declared.
  const ast::DomainDecl& collect_header(const ast::Program& program);
  void check_domain(const ast::DomainDecl& decl);

  void declare_global(const ast::Identifier& name, const char* kind);
  Type type_named(const ast::Identifier& name, bool allow_vec);
  void declare(const ast::Declaration& decl);
  void declare_param(const ast::ParamDecl& decl);
  void declare_const(const ast::ConstDecl& decl);
  void declare_fn(const ast::FnDecl& decl);
  void declare_set(const ast::ParticlesDecl& decl);
  void declare_builtin_observables();
  void declare_observable(const ast::ObservableDecl& decl);
  void check_timestep(const ast::TimestepDecl& decl);
  // An instance's requires item, on the values its use line gave.
  void check_requirement(const ast::Requirement& r);
  void check_output(const ast::OutputDecl& decl);
  void check_frames(const ast::OutputDecl& decl);
  Expr check_output_interval(const ast::Chain& every);

  // ---- statements.cpp: stages, statements and the schedule ----------------
  void check_stage(const ast::StageBlock& block);
  const ast::Identifier* stage_words(const ast::StageBlock& block, ir::Stage& stage);
  void check_block(const std::vector<ast::BlockStatement>& body, ir::Stage& stage, bool in_loop);
  void check_iterate(const ast::IterateBlock& loop, ir::Stage& stage);
  int resolve_stage_set(const ast::StageBlock& block, const ast::Identifier* set);
  int set_named(const ast::Identifier& name);
  std::vector<std::string> set_names() const;
  ir::Statement particle_statement(const ast::Target& target, Location loc, int set_index);
  ir::Statement check_statement(const ast::Assignment& a, int set_index);
  ir::Statement check_observable_statement(const ast::Assignment& a, int set_index);
  ir::Statement check_solve(const ast::SolveStatement& s, int set_index);
  Scope statement_scope(ir::Statement& st, std::string context);
  ir::Expr check_assigned_value(const ast::Assignment& a, ir::AssignOp op, Type type,
                                const std::string& what, Scope& scope);
  void not_assignable(const ast::Identifier& name, const ir::ParticleSet& set);

  void check_schedule(const ast::ScheduleItem& item);
  // Storage precision: requests for the whole model and per variable, then
  // the decision for every variable once all are known (per variable wins).
  struct PrecisionRequest {
    ir::Precision precision;
    Location loc;
  };
  void check_precision_request(const ast::ScheduleItem& item);
  ir::Precision precision_named(const ast::Chain& value, const std::string& option);
  std::string scheduled_reason(ir::Precision chosen, const std::string& whose, Location at) const;
  void decide_storage();
  // Pair-term arithmetic: a statement's own entry, else the whole model's.
  void decide_arithmetic();
  std::optional<PrecisionRequest> model_precision_;
  std::optional<PrecisionRequest> model_arithmetic_;
  std::map<std::pair<int, int>, PrecisionRequest> variable_precision_;  // (set, var) ->
  ir::SearchChoice search_choice(const ast::Chain& value);
  ir::Sharing sharing_choice(const ast::Chain& value);
  ir::SolverChoice solver_choice(const ast::Chain& value);
  ir::DenseMethod dense_method(const ast::Chain& value);
  void check_fast_sum_options(const ir::Statement& st, const ast::ScheduleItem& item);
  ir::Expr positive_schedule_value(const ast::ScheduleOption& option, Type type);
  static std::vector<std::string> var_names(const ir::ParticleSet& set);

  // ---- expressions.cpp: conversions, operators, names ---------------------
  // The value converted to `to` for storing in `what`, or an error.
  Expr convert(Expr value, Type to, Location at, const std::string& what);
  double constant_number(const Expr& e, Location at, const Scope& scope);

  Expr check(const ast::Chain& chain, Scope& scope);
  static ir::BinaryOp binary_op(const std::string& s);
  Expr fold_int_literals(ir::BinaryOp op, const Expr& a, const Expr& b, Location loc,
                         Location op_loc);
  Expr binary(ir::BinaryOp op, Expr a, Expr b, Location loc, Location op_loc);
  void warn_if_raw_displacement(const ir::ExprNode& a, const ir::ExprNode& b, Location loc);
  struct CheckOperand;
  Expr check(const ast::Operand& operand, Scope& scope);
  Expr check_name(const ast::Identifier& n, Scope& scope);
  Expr check_indexed(const ast::Indexed& n, Scope& scope);

  // ---- calls.cpp: built-in and user functions, random draws, accumulations
  static bool is_builtin_name(const std::string& name);
  static bool is_random_function(const std::string& name);
  Expr check_call(const ast::Call& n, Scope& scope);
  Expr check_user_call(const ast::Call& n, int index, std::vector<Expr> args);
  Expr check_select(const ast::Call& n, std::vector<Expr> args);
  void no_zero_divisor(const Expr& divisor, const std::string& what);
  Type call_type(ir::Function fn, const std::string& name, const std::vector<Expr>& args);
  Expr check_random(const ast::Call& n, Scope& scope);
  Expr check_accumulation(const ast::Call& n, ir::Reduction reduction, Scope& scope);
  Expr check_extremum_or_none(const ast::Call& n, ir::Reduction reduction, Scope& scope);
  Expr check_accumulation_over(const ast::Call& n, ir::Reduction reduction, int label_index,
                               Scope& inner);
  static const ast::Chain& argument_chain(const ast::Argument& a, const std::string& name);

  struct StatementRef {
    int stage, statement;
    Location loc;
  };
  struct Name {
    enum Kind { Param, Const, Set, Fn, Observable } kind;
    int index;
  };
  std::string source_text(Location loc) const { return std::string(file_.slice(loc)); }

  const SourceFile& file_;
  Location statement_target_;          // of the statement being checked
  std::optional<Location> time_read_;  // where t was first read (it needs a timestep)
  ir::Model model_;
  std::vector<Diagnostic> diagnostics_;  // errors and warnings, in the order found
  bool has_errors() const {
    for (const Diagnostic& d : diagnostics_)
      if (!d.warning) return true;
    return false;
  }
  std::set<std::string> failed_names_;  // declared with errors: later uses are follow-ons
  std::set<std::string> failed_sets_;   // sets whose name clashed with another declaration
  static constexpr int kMaxExpressionDepth = 2000;
  int expression_depth_ = 0;  // of the expression being checked
  std::map<std::string, Location> globals_;
  std::map<std::string, Name> names_;
  std::map<std::string, StatementRef> statement_names_;
  // Every param, const, function and observable the file declares, where:
  // declarations are read in order, so a name read above its declaration is
  // out of order, which the message says, rather than unknown.
  std::map<std::string, Location> declarations_;
  void fail_if_declared_below(const ast::Identifier& name) const;
};

}  // namespace partc::sema
