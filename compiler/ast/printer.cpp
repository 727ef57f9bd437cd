#include "ast/printer.hpp"

#include <fmt/format.h>

namespace partc::ast {

namespace {

struct Printer {
  const SourceFile& file;

  std::string at(const Located& node) const {
    const LineColumn lc = file.line_column(node.loc.begin);
    return fmt::format("@{}:{}", lc.line, lc.column);
  }

  std::string operator()(const IntLiteral& n) const { return std::to_string(n.value); }
  std::string operator()(const RealLiteral& n) const { return fmt::format("{}", n.value); }
  std::string operator()(const BoolLiteral& n) const { return n.value ? "true" : "false"; }
  std::string operator()(const Identifier& n) const { return n.name; }
  std::string operator()(const Indexed& n) const { return n.var.name + "[" + n.label.name + "]"; }
  std::string operator()(const Target& n) const {
    return n.var.name + (n.label ? "[" + n.label->name + "]" : "");
  }
  std::string operator()(const Norm& n) const { return "(norm " + (*this)(n.inner) + ")"; }
  std::string operator()(const Unary& n) const {
    return "(" + n.op + " " + boost::apply_visitor(*this, n.operand) + ")";
  }
  std::string operator()(const Postfix& n) const {
    std::string out = boost::apply_visitor(*this, n.base);
    for (const Identifier& c : n.components) out = "(." + c.name + " " + out + ")";
    return out;
  }
  std::string operator()(const Chain& n) const {
    std::string out = boost::apply_visitor(*this, n.first);
    for (const BinaryOp& op : n.rest)
      out = "(" + op.op + " " + out + " " + boost::apply_visitor(*this, op.rhs) + ")";
    return out;
  }
  std::string operator()(const LabelBinding& n) const {
    std::string out = "(in " + n.label.name;
    for (const Identifier& s : n.sets) out += " " + s.name;
    return out + ")";
  }
  std::string operator()(const Call& n) const {
    std::string out = "(call " + n.callee.name;
    for (const Argument& a : n.args) out += " " + boost::apply_visitor(*this, a);
    return out + ")";
  }
  template <class Node>
  std::string operator()(const x3::forward_ast<Node>& n) const {
    return (*this)(n.get());
  }

  std::string operator()(const ModelDecl& n) const {
    return "(model " + n.name.name + ") " + at(n);
  }
  std::string operator()(const DimDecl& n) const {
    return "(dim " + std::to_string(n.value.value) + ") " + at(n);
  }
  std::string tuple(const std::vector<Chain>& items) const {
    std::string out;
    for (const Chain& c : items) out += " " + (*this)(c);
    return out;
  }
  std::string operator()(const DomainDecl& n) const {
    std::string out = "(domain (lo" + tuple(n.lo) + ") (hi" + tuple(n.hi) + ")";
    for (const BoundaryClause& b : n.boundaries) {
      out += " (" + b.kind.name;
      for (const Identifier& axis : b.axes) out += " " + axis.name;
      out += ")";
    }
    return out + ") " + at(n);
  }
  std::string operator()(const ParamDecl& n) const {
    return "(param " + n.name.name + " " + n.type.name + " " + (*this)(n.value) + ") " + at(n);
  }
  std::string operator()(const ConstDecl& n) const {
    return "(const " + n.name.name + " " + (*this)(n.value) + ") " + at(n);
  }
  std::string operator()(const ObservableDecl& n) const {
    return "(observable " + n.name.name + " " + n.type.name + " " + (*this)(n.value) + ") " + at(n);
  }
  std::string operator()(const TimestepDecl& n) const {
    return "(timestep " + (*this)(n.value) + ") " + at(n);
  }
  std::string operator()(const OutputDecl& n) const {
    std::string out = "(output";
    if (n.set) out += " " + n.set->name + ":";
    for (const Identifier& name : n.names) out += " " + name.name;
    if (n.every) out += " (every " + (*this)(*n.every) + ")";
    return out + ") " + at(n);
  }
  std::string operator()(const FnDecl& n) const {
    std::string out = "(fn " + n.name.name + " (";
    for (std::size_t k = 0; k < n.params.size(); ++k)
      out += (k ? " " : "") + n.params[k].name.name + ":" + n.params[k].type.name;
    return out + ") " + (*this)(n.value) + ") " + at(n);
  }
  std::string operator()(const ParticlesDecl& n) const {
    std::string out = "(particles " + n.name.name + " " + (*this)(n.count) + ") " + at(n);
    for (const VarDecl& v : n.vars)
      out += std::string("\n  (") + (v.mirrored ? "mirrored " : "") + "var " + v.name.name + " " + v.type.name +
             (v.value ? " " + (*this)(*v.value) : "") + ") " + at(v);
    return out;
  }
  std::string assignment(const Assignment& a) const {
    return "(" + (a.name ? a.name->name + ": " : std::string()) + a.op + " " + (*this)(a.target) +
           " " + (*this)(a.value) + ") " + at(a);
  }
  std::string statements(const std::vector<BlockStatement>& body, const std::string& indent) const {
    std::string out;
    for (const BlockStatement& s : body) {
      if (auto a = boost::get<Assignment>(&s)) out += "\n" + indent + assignment(*a);
      if (auto solve = boost::get<SolveStatement>(&s))
        out += "\n" + indent + "(" + (solve->name ? solve->name->name + ": " : std::string()) +
               "solve " + (*this)(solve->unknown) + " " + (*this)(solve->lhs) + " " +
               (*this)(solve->rhs) + ") " + at(*solve);
      if (auto loop = boost::get<x3::forward_ast<IterateBlock>>(&s))
        out += "\n" + indent + "(iterate (until " + (*this)(loop->get().until) + ") (limit " +
               (*this)(loop->get().limit) + ")) " + at(loop->get()) +
               statements(loop->get().body, indent + "  ");
    }
    return out;
  }
  std::string operator()(const StageBlock& n) const {
    std::string out = "(" + n.kind;
    for (const Identifier& w : n.words) out += " " + w.name;
    return out + ") " + at(n) + statements(n.body, "  ");
  }
  std::string operator()(const ScheduleBlock& n) const {
    std::string out = "(schedule) " + at(n);
    for (const ScheduleItem& item : n.items) {
      out += "\n  (" + (!item.subject           ? std::string("model")
                         : item.subject->member ? item.subject->name.name + "." +
                                                      item.subject->member->name
                                                : item.subject->name.name);
      for (const ScheduleOption& o : item.options)
        out += " (" + o.key.name + " " + (*this)(o.value) + ")";
      out += ") " + at(item);
    }
    return out;
  }
  static std::string names(const std::vector<Identifier>& list, const char* separator) {
    std::string out;
    for (const Identifier& name : list) out += (out.empty() ? "" : separator) + name.name;
    return out;
  }
  std::string operator()(const ModuleDecl& n) const {
    return "(module " + dotted(n.name) + ") " + at(n);
  }
  std::string operator()(const OwnsItem& n) const {
    return std::string("(owns ") + (n.local ? "local " : "") + (n.mirrored ? "mirrored " : "") + n.name.name + " " +
           n.type.name + (n.value ? " " + (*this)(*n.value) : "") + (n.channel ? " channel" : "") +
           ") " + at(n);
  }
  std::string operator()(const AccessItem& n) const {
    return "(" + n.kind + " " + n.name.name + " " + n.type.name + ") " + at(n);
  }
  std::string operator()(const ProvidesItem& n) const {
    return "(provides " + n.name.name + " " + n.type.name + ") " + at(n);
  }
  std::string operator()(const SlotsItem& n) const {
    return "(" + n.kind + " " + names(n.names, " ") + ") " + at(n);
  }
  std::string operator()(const RequiresItem& n) const {
    return "(requires " + (*this)(n.condition) + ") " + at(n);
  }
  std::string operator()(const AtItem& n) const {
    return "(at " + n.slot.name + " " + assignment(n.statement) + ") " + at(n);
  }
  std::string operator()(const EffectDecl& n) const {
    std::string out = "(effect " + n.name.name + " (";
    for (std::size_t k = 0; k < n.params.size(); ++k)
      out += (k ? " " : "") + std::string(n.params[k].is_const ? "const " : "") +
             n.params[k].name.name + ":" + n.params[k].type.name + " " + (*this)(n.params[k].value);
    out += ") (on " + names(n.sets, " ") + ")) " + at(n);
    for (const EffectItem& item : n.items) out += "\n  " + boost::apply_visitor(*this, item);
    return out;
  }
  std::string operator()(const UseDecl& n) const {
    std::string out = "(use " + dotted(n.module) + " (";
    for (std::size_t k = 0; k < n.args.size(); ++k)
      out += (k ? " " : "") + std::string(n.args[k].is_const ? "const " : "") +
             n.args[k].name.name + "=" + (*this)(n.args[k].value);
    out += ") (on " + names(n.sets, " ") + ")";
    if (n.alias) out += " (as " + n.alias->name + ")";
    return out + ") " + at(n);
  }
  std::string operator()(const OrderDecl& n) const {
    return "(order " + names(n.instances, " ") + ") " + at(n);
  }
  std::string operator()(const ImportDecl& n) const {
    return "(import " + dotted(n.module) + ") " + at(n);
  }
};

}  // namespace

std::string to_string(const Program& program, const SourceFile& file) {
  std::string out;
  for (const Declaration& d : program.declarations)
    out += boost::apply_visitor(Printer{file}, d) + "\n";
  return out;
}

}  // namespace partc::ast
