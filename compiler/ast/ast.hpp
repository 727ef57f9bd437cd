// The abstract syntax tree of a .part file, exactly as written.
//
// Plain structs that the Spirit X3 grammar (grammar/) fills in; no meaning is
// attached here: names are unresolved and types unknown until sema. Every
// node derives from Located, so later stages can point at the source.
// Binary operators of one precedence level are kept as a flat Chain
// (first op rhs op rhs ...); sema folds them left to right.
#pragma once

#include <boost/optional.hpp>
#include <boost/spirit/home/x3/support/ast/variant.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "support/source.hpp"

namespace partc::ast {

namespace x3 = boost::spirit::x3;

struct Located {
  Location loc;
};

struct Identifier : Located {
  std::string name;
};
struct IntLiteral : Located {
  std::int64_t value = 0;
};
struct RealLiteral : Located {
  double value = 0;
};
struct BoolLiteral : Located {
  bool value = false;
};
// name[label], e.g. v[i]
struct Indexed : Located {
  Identifier var;
  Identifier label;
};

struct Chain;
struct Unary;
struct Call;
struct Norm;
struct Postfix;

struct Operand : x3::variant<IntLiteral, RealLiteral, BoolLiteral, Identifier, Indexed,
                             x3::forward_ast<Call>, x3::forward_ast<Norm>, x3::forward_ast<Unary>,
                             x3::forward_ast<Postfix>, x3::forward_ast<Chain>> {
  using base_type::base_type;
  using base_type::operator=;
};

struct BinaryOp : Located {
  std::string op;
  Operand rhs;
};
// first op rhs op rhs ... at one precedence level
struct Chain : Located {
  Operand first;
  std::vector<BinaryOp> rest;
};
// -x, +x, not x
struct Unary : Located {
  std::string op;
  Operand operand;
};
// |x|
struct Norm : Located {
  Chain inner;
};
// x.y, v[i].x
struct Postfix : Located {
  Operand base;
  std::vector<Identifier> components;
};
// `j in Q`, or `j in (Q, R)` over several sets, as the first argument of an
// accumulation
struct LabelBinding : Located {
  Identifier label;
  std::vector<Identifier> sets;
};
struct Argument : x3::variant<LabelBinding, Chain> {
  using base_type::base_type;
  using base_type::operator=;
};
struct Call : Located {
  Identifier callee;
  std::vector<Argument> args;
  // Set by scene instantiation on uniform() and normal() inside an effect:
  // the instance whose random stream the draw belongs to.
  std::string random_key = {};
};

// v[i] (a particle variable) or e_kin (an observable)
struct Target : Located {
  Identifier var;
  boost::optional<Identifier> label;
};

// Where a statement instantiated from an effect came from: the instance
// and the statement of the module, one entry per term merged into it.
struct Origin {
  std::string effect;
  Location loc;
};

// target op value, op one of = += -= *= /=
struct Assignment : Located {
  boost::optional<Identifier> name;  // `force: v[i] += ...`, for the schedule
  Target target;
  std::string op;
  Chain value;
  std::vector<Origin> origins = {};  // empty when written in the model itself
};

// solve w[i]: operator = rhs, the operator linear in w (sums of
// coefficient * w[j], and w[i] itself): a linear system for every w at once.
struct SolveStatement : Located {
  boost::optional<Identifier> name;  // for the schedule, which chooses the solver
  Target unknown;
  Chain lhs;
  Chain rhs;
};

struct IterateBlock;
struct BlockStatement : x3::variant<Assignment, SolveStatement, x3::forward_ast<IterateBlock>> {
  using base_type::base_type;
  using base_type::operator=;
};

// iterate until CONDITION limit K { ... }: the statements again and again
// until the condition (on observables) holds after a pass, at most K passes.
struct IterateBlock : Located {
  Chain until;
  Chain limit;
  std::vector<BlockStatement> body;
};

struct ModelDecl : Located {
  Identifier name;
};
struct DimDecl : Located {
  IntLiteral value;
};
// periodic=(x, y), reflect=(z), open=(y): what happens at an axis's faces
struct BoundaryClause : Located {
  Identifier kind;
  std::vector<Identifier> axes;
};
struct DomainDecl : Located {
  std::vector<Chain> lo;
  std::vector<Chain> hi;
  std::vector<BoundaryClause> boundaries;
};
struct ParamDecl : Located {
  Identifier name;
  Identifier type;
  Chain value;
};
struct ConstDecl : Located {
  Identifier name;
  Chain value;
};
// observable e_kin: real = 0, a model-level value that statements assign
struct ObservableDecl : Located {
  Identifier name;
  Identifier type;
  Chain value;
};
// timestep = dt: how far each step advances t
struct TimestepDecl : Located {
  Chain value;
};
// output e_kin, p_tot every 10: the observables the run logs, how often
// `output e_kin, t every 10` (observables), or `output F: v, rho every 100`
// (the variables of set F in VTK frames)
struct OutputDecl : Located {
  boost::optional<Identifier> set;
  std::vector<Identifier> names;
  boost::optional<Chain> every;
};
// `mirrored v: vec = 0`: turned with the position at a reflecting face
struct VarDecl : Located {
  bool mirrored = false;
  Identifier name;
  Identifier type;
  boost::optional<Chain> value;
  bool effect_owned = false;  // set by scene instantiation for an effect's `owns`
};
struct ParticlesDecl : Located {
  Identifier name;
  Chain count;
  std::vector<VarDecl> vars;
};
// fn NAME(a: real, b: vec) = expression
struct FnParam : Located {
  Identifier name;
  Identifier type;
};
struct FnDecl : Located {
  Identifier name;
  std::vector<FnParam> params;
  Chain value;
  // A module's function (or a scene's alias of one): its parameters are its
  // own names, and may be those of the scene's declarations.
  bool from_module = false;
};
// init [SET] { ... }, step [SET] { ... } or stage NAME [SET] { ... }: the
// words after the keyword are the set, or the name and the set (sema reads them).
struct StageBlock : Located {
  std::string kind;
  std::vector<Identifier> words;
  std::vector<BlockStatement> body;
  // Set by scene instantiation on an integrator's primed slots: an init
  // block that runs after a state is loaded from files too.
  bool also_after_load = false;
};

// schedule { force: search = kd_tree, skin = 0.3  P.v: precision = float }:
// how named statements run and how variables are stored, kept apart from
// what they compute.
struct ScheduleOption : Located {
  Identifier key;
  Chain value;
};
struct ScheduleSubject : Located {
  Identifier name;                     // a statement, or the set of P.v
  boost::optional<Identifier> member;  // P.v: the variable v of set P
};
struct ScheduleItem : Located {
  boost::optional<ScheduleSubject> subject;  // none: the whole model (precision = float)
  std::vector<ScheduleOption> options;
};
struct ScheduleBlock : Located {
  std::vector<ScheduleItem> items;
};

// Modules and scenes. `module pair.lj` names a module file; a module holds
// functions and one effect; a scene `use`s effects on its particle sets.
struct ModuleDecl : Located {
  std::vector<Identifier> name;  // pair.lj
};
// An effect's parameter: `eps: real = 1`, or `const rc: real = 2.5` (folded).
struct EffectParam : Located {
  bool is_const = false;
  Identifier name;
  Identifier type;
  Chain value;
};
// owns [local] [mirrored] v: vec = 0 [channel]: a variable the effect
// declares on its set; a local one is the instance's own (named lj_u for
// instance lj), which no other effect sees.
struct OwnsItem : Located {
  bool local = false;
  bool mirrored = false;
  Identifier name;
  Identifier type;
  boost::optional<Chain> value;
  bool channel = false;
};
// reads x: real, sets v: vec, contributes f: vec: a variable another owns.
struct AccessItem : Located {
  std::string kind;
  Identifier name;
  Identifier type;
};
// provides e_lj: real: an observable the effect computes, kept if used.
struct ProvidesItem : Located {
  Identifier name;
  Identifier type;
};
// slots kick, drift, force (an integrator's step, in order), or prime
// force (slots that also run once after init).
struct SlotsItem : Located {
  std::string kind;
  std::vector<Identifier> names;
};
// at force: f[i] += ...: a statement placed at a slot of the step.
struct AtItem : Located {
  Identifier slot;
  Assignment statement;
};
// requires kernel == 0 or kernel == 1: a condition on the effect's const
// parameters, checked for each instance when partc runs.
struct RequiresItem : Located {
  Chain condition;
};
struct EffectItem : x3::variant<OwnsItem, AccessItem, ProvidesItem, SlotsItem, AtItem, ConstDecl,
                                TimestepDecl, RequiresItem> {
  using base_type::base_type;
  using base_type::operator=;
};
struct EffectDecl : Located {
  Identifier name;
  std::vector<EffectParam> params;
  std::vector<Identifier> sets;  // the formal sets, `on P` or `on P, Q`
  std::vector<EffectItem> items;
};
// use pair.lj(eps = 1.2) on A as lj_a
// eps = 1.2, or const g = 0: folded into the instance as the effect's own
// const parameters are (a literal, and a term it multiplies by 0 removed).
struct UseArgument : Located {
  bool is_const = false;
  Identifier name;
  Chain value;
};
struct UseDecl : Located {
  std::vector<Identifier> module;
  std::vector<UseArgument> args;
  std::vector<Identifier> sets;
  boost::optional<Identifier> alias;
};
// order wall_a, wall_b: writers of one variable at one slot, in this order.
struct OrderDecl : Located {
  std::vector<Identifier> instances;
};
// import sph.kernels: a module's functions and constants, by their own names.
struct ImportDecl : Located {
  std::vector<Identifier> module;
};

struct Declaration
    : x3::variant<ModelDecl, DimDecl, DomainDecl, ParamDecl, ConstDecl, ObservableDecl,
                  TimestepDecl, OutputDecl, FnDecl, ParticlesDecl, StageBlock, ScheduleBlock,
                  ModuleDecl, EffectDecl, UseDecl, OrderDecl, ImportDecl> {
  using base_type::base_type;
  using base_type::operator=;
};

// What an instance requires: one of its effect's requires items, made by
// scene instantiation in the scene's names, for sema to check.
struct Requirement {
  Chain condition;
  Location item;  // the requires line, in its module
  Location use;   // the use line that made the instance
  std::string instance;
};

struct Program {
  std::vector<Declaration> declarations;
  std::vector<Requirement> requirements;  // none in a parsed file
};

// The name a param, const, fn or observable declaration declares; null for
// any other declaration.
const Identifier* global_name(const Declaration& decl);

// "pair.lj" for the parts of a dotted name.
std::string dotted(const std::vector<Identifier>& parts);

// The single operand a chain is made of, looking through the nesting of
// precedence levels and parentheses ("j", "(j)"); null when the chain
// applies any operator.
const Operand* sole_operand(const Chain& chain);

// The source range of any operand or argument.
Location location_of(const Operand& operand);
Location location_of(const Argument& argument);

}  // namespace partc::ast
