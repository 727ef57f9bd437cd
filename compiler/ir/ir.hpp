// The typed intermediate representation: what a model means.
//
// Sema builds it from the AST once names are resolved and types checked;
// analyses read it and record facts beside it; codegen prints it.
// Expressions are immutable nodes shared through Expr handles, each with a
// kind tag (for cheap `as<T>()`), a type and a source location. Passes that
// rewrite expressions derive from Mutator (ir/mutator.hpp); passes that
// only look derive from Visitor (ir/visitor.hpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ir/types.hpp"
#include "support/source.hpp"

namespace partc::ir {

enum class ExprKind {
  Literal,
  ParamRef,
  ConstRef,
  ObservableRef,
  VarRef,
  Dx,
  Unary,
  Binary,
  Call,
  MakeVec,
  Component,
  Random,
  Accumulate,
  FnArg,
  FnCall,
  Select,
};

struct ExprNode {
  ExprNode(ExprKind k, Type t, Location l) : kind(k), type(t), loc(l) {}
  virtual ~ExprNode() = default;
  const ExprKind kind;
  const Type type;
  const Location loc;
};
using Expr = std::shared_ptr<const ExprNode>;

template <class Node>
const Node* as(const Expr& e) {
  return e && e->kind == Node::node_kind ? static_cast<const Node*>(e.get()) : nullptr;
}

// A literal bool, int or real. An int is exact in `integer` (all 64 bits);
// `value` holds every literal as a double (ints rounded beyond 2^53).
struct Literal : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Literal;
  Literal(Type t, double v, Location l)
      : ExprNode(node_kind, t, l), value(v), integer(exact_integer(t, v)) {}
  Literal(std::int64_t i, Location l)
      : ExprNode(node_kind, Type::Int, l), value(static_cast<double>(i)), integer(i) {}
  const double value;
  const std::int64_t integer;

 private:
  // Sema refuses int values outside 64 bits before they reach a Literal.
  static std::int64_t exact_integer(Type t, double v) {
    return t == Type::Int && v >= -9223372036854775808.0 && v < 9223372036854775808.0
               ? static_cast<std::int64_t>(v)
               : 0;
  }
};

struct ParamRef : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::ParamRef;
  ParamRef(Type t, int i, Location l) : ExprNode(node_kind, t, l), param(i) {}
  const int param;  // index into Model::params
};

struct ConstRef : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::ConstRef;
  ConstRef(Type t, int i, Location l) : ExprNode(node_kind, t, l), constant(i) {}
  const int constant;  // index into Model::consts
};

// A model-level value: an observable, or the built-in step and t.
struct ObservableRef : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::ObservableRef;
  ObservableRef(Type t, int i, Location l) : ExprNode(node_kind, t, l), observable(i) {}
  const int observable;  // index into Model::observables
};

// A particle variable read through a label: v[i], p[j].
struct VarRef : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::VarRef;
  VarRef(Type t, int s, int v, int lab, Location l)
      : ExprNode(node_kind, t, l), set(s), var(v), label(lab) {}
  const int set;    // index into Model::sets
  const int var;    // index into ParticleSet::vars
  const int label;  // index into Statement::labels
};

// dx: the shortest vector from particle `from` (the statement's label) to
// particle `to` (the innermost accumulation's label).
struct Dx : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Dx;
  Dx(int from_label, int to_label, Location l)
      : ExprNode(node_kind, Type::Vec, l), from(from_label), to(to_label) {}
  const int from;
  const int to;
};

enum class UnaryOp { Neg, Not };
struct Unary : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Unary;
  Unary(Type t, UnaryOp o, Expr a, Location l)
      : ExprNode(node_kind, t, l), op(o), operand(std::move(a)) {}
  const UnaryOp op;
  const Expr operand;
};

// FloorDiv is `//` on ints: floored, as Python's (and 0 when dividing by 0).
enum class BinaryOp { Add, Sub, Mul, Div, FloorDiv, Lt, Le, Gt, Ge, Eq, Ne, And, Or };
const char* binary_op_spelling(BinaryOp op);  // as in .part: "+", "<=", "and"
struct Binary : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Binary;
  Binary(Type t, BinaryOp o, Expr a, Expr b, Location l)
      : ExprNode(node_kind, t, l), op(o), lhs(std::move(a)), rhs(std::move(b)) {}
  const BinaryOp op;
  const Expr lhs, rhs;
};

// Built-in pure functions. Norm covers both |v| and norm(v). Mod is floored
// (the sign of the divisor, as Python's %); Cross is a vec in 3D and the
// scalar z-component in 2D.
enum class Function {
  Exp,
  Log,
  Sqrt,
  Pow,
  Abs,
  Min,
  Max,
  Dot,
  Norm,
  Floor,
  Ceil,
  Round,
  Sin,
  Cos,
  Tan,
  Asin,
  Acos,
  Atan,
  Atan2,
  Tanh,
  Sign,
  Clamp,
  Mod,
  Cross
};
const char* function_name(Function f);
struct Call : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Call;
  Call(Type t, Function f, std::vector<Expr> a, Location l)
      : ExprNode(node_kind, t, l), fn(f), args(std::move(a)) {}
  const Function fn;
  const std::vector<Expr> args;
};

// vec(a, b, ...): one real per dimension.
struct MakeVec : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::MakeVec;
  MakeVec(std::vector<Expr> c, Location l)
      : ExprNode(node_kind, Type::Vec, l), components(std::move(c)) {}
  const std::vector<Expr> components;
};

// v.x, v.y, ...: one component of a vec.
struct Component : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Component;
  Component(Expr v, int k, Location l)
      : ExprNode(node_kind, Type::Real, l), vec(std::move(v)), index(k) {}
  const Expr vec;
  const int index;
};

// uniform(), normal(), uniform_vec(), normal_vec(). Each call site has its
// own stream so draws are independent; a draw is keyed by (seed, particle
// id, step, stream, component), so it does not depend on particle order or
// thread count. A draw in an effect's statement is keyed by its instance too
// (`owner`, streams counted per instance), so one effect's noise does not
// depend on which other effects a scene uses.
enum class Distribution { Uniform, Normal };
struct Random : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Random;
  Random(Type t, Distribution d, int s, std::string o, Location l)
      : ExprNode(node_kind, t, l), distribution(d), stream(s), owner(std::move(o)) {}
  const Distribution distribution;
  const int stream;
  const std::string owner;  // the effect instance; empty in a model's own statements
};

// sum / min / max / count over particles `label` that satisfy `condition`.
enum class Reduction { Sum, Min, Max, Count };
const char* reduction_name(Reduction r);
struct Accumulate : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Accumulate;
  Accumulate(Type t, Reduction r, int lab, Expr cond, Expr b, int i, Location l)
      : ExprNode(node_kind, t, l),
        reduction(r),
        label(lab),
        condition(std::move(cond)),
        body(std::move(b)),
        id(i) {}
  const Reduction reduction;
  const int label;       // index into Statement::labels
  const Expr condition;  // null: every particle
  const Expr body;       // null for count
  const int id;          // unique within the model, for naming and facts
};

// Inside a user function's body: its argument number `index`.
struct FnArg : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::FnArg;
  FnArg(Type t, int i, std::string n, Location l)
      : ExprNode(node_kind, t, l), index(i), name(std::move(n)) {}
  const int index;
  const std::string name;  // as the function names it
};

// A call of the user function Model::functions[fn].
struct FnCall : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::FnCall;
  FnCall(Type t, int f, std::vector<Expr> a, Location l)
      : ExprNode(node_kind, t, l), fn(f), args(std::move(a)) {}
  const int fn;
  const std::vector<Expr> args;
};

// if(condition, then, otherwise): only the chosen branch is evaluated, so
// a guarded division never produces a value that is then thrown away.
struct Select : ExprNode {
  static constexpr ExprKind node_kind = ExprKind::Select;
  Select(Type t, Expr c, Expr a, Expr b, Location l)
      : ExprNode(node_kind, t, l),
        condition(std::move(c)),
        then(std::move(a)),
        otherwise(std::move(b)) {}
  const Expr condition, then, otherwise;
};

// |dx| (norm(dx)) and dot(dx, dx): the ways an expression reads a pair's
// distance, which neighbourhood bounds and fast-sum kernels are made of.
inline bool is_norm_of_dx(const Call& c) { return c.fn == Function::Norm && as<Dx>(c.args[0]); }
inline bool is_squared_norm_of_dx(const Call& c) {
  return c.fn == Function::Dot && as<Dx>(c.args[0]) && as<Dx>(c.args[1]);
}
inline bool is_norm_of_dx(const Expr& e) {
  const Call* c = as<Call>(e);
  return c && is_norm_of_dx(*c);
}
inline bool is_squared_norm_of_dx(const Expr& e) {
  const Call* c = as<Call>(e);
  return c && is_squared_norm_of_dx(*c);
}

// ---- Declarations -------------------------------------------------------

// fn name(a: real, ...) = body: pure, of its arguments, params and consts.
struct UserFn {
  std::string name;
  std::vector<std::string> arg_names;
  std::vector<Type> arg_types;
  Expr body;  // its type is the result type
  Location loc;
};

struct Param {
  std::string name;
  Type type;
  Expr default_value;  // a Literal after fold_constants
  Location loc;
};

// A named value computed from params and literals once they are known.
struct Const {
  std::string name;
  Type type;
  Expr value;
  Location loc;
};

// A model-level value, the same for every particle: assigned by statements
// (e_kin = sum(i in P, ...)), read by later ones, logged by `output`.
struct Observable {
  std::string name;
  Type type;
  Expr initial;  // at init and load
  bool builtin;  // step, t
  Location loc;
};
// The builtin observables sit first, in this order.
enum BuiltinObservable { kStep = 0, kTime = 1, kFirstUserObservable = 2 };

// `output e_kin, t every 10`: the observables a run logs, and how often.
struct Log {
  std::vector<int> observables;  // into Model::observables; empty: no log
  Expr every;                    // an int; null: every step
  Location loc;
};

// `output F: v, rho every 100`: what VTK frames hold of a set, and how
// often they are written. With any of these, sets not named get no frames.
struct Frames {
  int set;
  std::vector<int> vars;  // into ParticleSet::vars; id and p are always written
  Expr every;             // an int; null: every step
  Location loc;
};

// How a particle variable is stored (schedule: precision = float). Every
// expression is computed in double whatever the storage: a load widens, a
// store rounds once; only a statement's arithmetic (Schedule) computes its
// vector pair terms in float.
enum class Precision { Double, Float };
const char* precision_name(Precision p);  // as .part spells it

struct Variable {
  std::string name;
  Type type;
  Expr initial;  // per particle at creation; null means zero
  bool builtin;  // p, id, alive
  Location loc;
  bool mirrored = false;                  // a vec turned with its particle at a reflecting face
  Precision storage = Precision::Double;  // Float only for real and vec variables and p
  std::string storage_reason;             // why, for --explain: set by sema's schedule checks
  bool effect_owned = false;  // declared by an effect's `owns`: passes may decide its storage
};

// The builtin variables sit first in every set, in this order.
enum BuiltinVar { kPosition = 0, kId = 1, kAlive = 2, kFirstUserVar = 3 };

struct ParticleSet {
  std::string name;
  Expr initial_count;  // int, from params/consts
  std::vector<Variable> vars;
  Location loc;
  int find_var(const std::string& var_name) const;  // -1 when absent
};

struct Label {
  std::string name;
  int set;
};

enum class AssignOp { Set, Add, Sub, Mul, Div };
const char* assign_op_spelling(AssignOp op);

// How a statement's neighbourhood sums find their particles, when the
// model's schedule says so; otherwise the runtime decides.
enum class SearchChoice { Auto, BruteForce, CellList, KdTree };
const char* search_choice_name(SearchChoice c);  // as .part spells it
// How a solve statement solves: auto is LU for a dense operator, BiCGSTAB
// for a sparse one.
enum class SolverChoice { Auto, Lu, Cg, Bicgstab, Gmres };
const char* solver_choice_name(SolverChoice c);  // as .part spells it
// Whether a statement's neighbourhood sums share their set's search with
// other statements' (analysis/search_plan.cpp): as the cost model decides,
// always (at the largest radius), or never (a search of their own).
enum class Sharing { Auto, Shared, Separate };
const char* sharing_name(Sharing s);  // as .part spells it
// How a statement's dense sums (no bound on |dx|) run: over every pair, or by
// a fast method with an accuracy knob (analysis/fast_sums.cpp).
enum class DenseMethod { Direct, Fmm };
const char* dense_method_name(DenseMethod d);  // as .part spells it
struct Schedule {
  SearchChoice search = SearchChoice::Auto;
  Sharing sharing = Sharing::Auto;
  Expr skin;  // non-null: Verlet lists with this skin, reused across steps
  SolverChoice solver = SolverChoice::Auto;
  Expr tolerance;       // of an iterative solver (null: 1e-10), or of a fast sum
  Expr max_iterations;  // of an iterative solver; null: 2n
  DenseMethod dense = DenseMethod::Direct;
  Expr order;  // of a fast sum: Chebyshev nodes per axis; null: chosen from the tolerance
  // summation = compensated: every sum of the statement adds with Neumaier's
  // compensation, each particle its own terms in order (no pair walks).
  bool compensated = false;
  // arithmetic = float: the statement's pair terms computed on vectors of
  // floats (twice the lanes), added into double sums per particle; only
  // vector pair terms (analysis/vector_terms.cpp) change, a scalar term
  // stays double. Its own entry (arithmetic_loc set), else the model's.
  Precision arithmetic = Precision::Double;
  std::string arithmetic_reason;  // for --explain: set by sema's schedule checks
  Location arithmetic_loc;        // of the statement's own entry; end 0 when none
  Location loc;
};

// target[labels[0]] op= value, run for every particle of the target's set;
// or, when `observable` is set, observable op= value, run once (its labels
// are its reductions', labels[0] a placeholder naming no particle).
// The effect instance and module statement a term of a statement came from.
struct Origin {
  std::string effect;
  Location loc;
};

struct Statement {
  std::string name;             // empty unless named for the schedule
  std::vector<Origin> origins;  // empty unless instantiated from effects
  // The value is the origins' terms joined, t1 + t2 - t3 (ir/terms.hpp): one
  // per origin, as channel merging made it; not once fusion inlined a writer.
  bool terms_by_origin = false;
  // A statement fusion made (ir/inline_single_use.cpp): its value without
  // some of its origins' contributions (indices into origins), for
  // --profile's calibration. Origins no entry leaves out are the reader's.
  struct Without {
    std::vector<std::size_t> origins;
    Expr value;
  };
  std::vector<Without> without;
  Schedule schedule;
  int set;
  int var;
  int observable = -1;  // >= 0: the target is Model::observables[observable]
  // Non-null: solve for the target var of every particle at once, so that
  // solve_operator (linear in it; analysis/linear_operator.cpp) = value.
  Expr solve_operator;
  AssignOp op;
  Expr value;
  std::vector<Label> labels;  // [0] is the statement's own label (i)
  Location loc;
  int line = 0;  // 1-based line in the .part file
};

// Passes [first, last) of a stage's statements run again and again until
// `until` (a bool of observables, params, consts) holds after a pass, at most
// `limit` passes; then the run stops with a message.
struct Iterate {
  int first, last;
  Expr until;
  Expr limit;  // an int
  Location loc;
};

// Named stages run when the driver or the C++ API asks for them by name.
enum class StageKind { Init, Step, Named };
struct Stage {
  StageKind kind;
  std::string name;              // of a named stage
  bool also_after_load = false;  // an init stage that also ends load (primed slots)
  std::vector<Iterate> loops;    // in order, not nested
  // Whether statement k runs in an iterate block's loop.
  bool in_loop(int k) const {
    return std::any_of(loops.begin(), loops.end(),
                       [&](const Iterate& l) { return k >= l.first && k < l.last; });
  }
  int set;  // -1: a block of a model with several sets that assigns only observables
  std::vector<Statement> statements;
  Location loc;
};

// Per axis, what happens at the faces lo and hi: periodic (wraps), reflect
// (a position past a face is mirrored back in), open (a particle past a face
// leaves its set, counted), or nothing (unbounded).
struct Domain {
  std::vector<double> lo, hi;
  std::vector<bool> periodic, reflect, open;
  static bool any(const std::vector<bool>& axes) {
    return std::find(axes.begin(), axes.end(), true) != axes.end();
  }
};

struct Model;
// How --explain and kernel comments name an accumulation: "sum(j)", or
// "sum(j in W)" when j runs over another set than the statement's.
std::string accumulation_heading(const Model& m, const Statement& st, const Accumulate& acc);
// "f[i]" (with the set, "P.f[i]", in a model of several sets), or an observable's name.
std::string target_name(const Model& m, const Statement& st);

struct Model {
  std::string name;
  int dim = 0;
  Domain domain;
  std::vector<Param> params;
  std::vector<Const> consts;
  std::vector<UserFn> functions;
  std::vector<ParticleSet> sets;
  std::vector<Observable> observables;  // step and t first
  Expr timestep;                        // null: t is not defined
  Log log;
  std::vector<Frames> frames;
  std::vector<Stage> stages;  // in file order
  int random_streams = 0;
  std::map<std::string, int> effect_random_streams;  // per effect instance
  int accumulations = 0;
};

}  // namespace partc::ir
