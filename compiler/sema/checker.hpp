// The semantic checker's class, shared by the files that implement it.
//
// Sema is split by concern, one file each: declarations.cpp (the model's
// header, params, consts, functions, particle sets), statements.cpp (stages,
// statements, the schedule), expressions.cpp (names, operators, conversions)
// and calls.cpp (built-in functions, user functions, random draws,
// accumulations). Internal to sema/; the entry point is sema.hpp.
#pragma once

#include <map>
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
struct SemaError {
  Diagnostic diagnostic;
};

[[noreturn]] inline void fail(Location loc, std::string message, std::string note = {}) {
  throw SemaError{Diagnostic{loc, std::move(message), std::move(note)}};
}

inline std::string quoted(const std::string& name) { return "'" + name + "'"; }

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
  const ir::UserFn* function = nullptr;  // whose arguments are in scope
};

class Sema {
 public:
  explicit Sema(const SourceFile& file) : file_(file) {}
  ir::Model run(const ast::Program& program);

 private:
  template <class F>
  void guarded(F&& f) {
    try {
      f();
    } catch (const SemaError& e) {
      errors_.push_back(e.diagnostic);
    }
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

  // ---- statements.cpp: stages, statements and the schedule ----------------
  void check_stage(const ast::StageBlock& block);
  int resolve_stage_set(const ast::StageBlock& block);
  int set_named(const ast::Identifier& name);
  std::vector<std::string> set_names() const;
  ir::Statement check_statement(const ast::Assignment& a, int set_index);

  void check_schedule(const ast::ScheduleItem& item);
  ir::SearchChoice search_choice(const ast::Chain& value);
  static std::vector<std::string> var_names(const ir::ParticleSet& set);

  // ---- expressions.cpp: conversions, operators, names ---------------------
  // The value converted to `to` for storing in `what`, or an error.
  Expr convert(Expr value, Type to, Location at, const std::string& what);
  double constant_number(const Expr& e, Location at, const Scope& scope);

  Expr check(const ast::Chain& chain, Scope& scope);
  static ir::BinaryOp binary_op(const std::string& s);
  Expr binary(ir::BinaryOp op, Expr a, Expr b, Location loc, Location op_loc);
  struct CheckOperand;
  Expr check(const ast::Operand& operand, Scope& scope);
  Expr check_name(const ast::Identifier& n, Scope& scope);
  Expr check_indexed(const ast::Indexed& n, Scope& scope);

  // ---- calls.cpp: built-in and user functions, random draws, accumulations
  static bool is_builtin_name(const std::string& name);
  static bool is_random_function(const std::string& name);
  Expr check_call(const ast::Call& n, Scope& scope);
  Expr check_user_call(const ast::Call& n, int index, std::vector<Expr> args);
  Type call_type(ir::Function fn, const std::string& name, const std::vector<Expr>& args);
  Expr check_random(const ast::Call& n, Scope& scope);
  Expr check_accumulation(const ast::Call& n, ir::Reduction reduction, Scope& scope);
  static const ast::Chain& argument_chain(const ast::Argument& a, const std::string& name);

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

}  // namespace partc::sema
