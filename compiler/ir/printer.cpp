#include "ir/printer.hpp"

#include <fmt/format.h>

#include "support/diagnostics.hpp"

namespace partc::ir {

namespace {

std::string number(Type type, double value) {
  if (type == Type::Bool) return value != 0 ? "true" : "false";
  return fmt::format("{}", value);
}

std::string join(const std::vector<Expr>& items, const Model& model, const std::vector<Label>& labels) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k)
    out += (k ? ", " : "") + to_string(items[k], model, labels);
  return out;
}

}  // namespace

std::string to_string(const Expr& e, const Model& model, const std::vector<Label>& labels) {
  if (!e) return "<none>";
  switch (e->kind) {
    case ExprKind::Literal: return number(e->type, as<Literal>(e)->value);
    case ExprKind::ParamRef: return model.params[as<ParamRef>(e)->param].name;
    case ExprKind::ConstRef: return model.consts[as<ConstRef>(e)->constant].name;
    case ExprKind::ObservableRef: return model.observables[as<ObservableRef>(e)->observable].name;
    case ExprKind::VarRef: {
      auto v = as<VarRef>(e);
      return model.sets[v->set].vars[v->var].name + "[" + labels[v->label].name + "]";
    }
    case ExprKind::Dx: {
      auto d = as<Dx>(e);
      return "dx(" + labels[d->from].name + "->" + labels[d->to].name + ")";
    }
    case ExprKind::Unary: {
      auto u = as<Unary>(e);
      return (u->op == UnaryOp::Neg ? "-" : "not ") + to_string(u->operand, model, labels);
    }
    case ExprKind::Binary: {
      auto b = as<Binary>(e);
      return "(" + to_string(b->lhs, model, labels) + " " + binary_op_spelling(b->op) + " " +
             to_string(b->rhs, model, labels) + ")";
    }
    case ExprKind::Call: {
      auto c = as<Call>(e);
      return std::string(function_name(c->fn)) + "(" + join(c->args, model, labels) + ")";
    }
    case ExprKind::MakeVec: return "vec(" + join(as<MakeVec>(e)->components, model, labels) + ")";
    case ExprKind::Component: {
      auto c = as<Component>(e);
      return to_string(c->vec, model, labels) + "." + "xyzw"[c->index];
    }
    case ExprKind::Random: {
      auto r = as<Random>(e);
      return fmt::format("{}{}#{}{}()",
                         r->distribution == Distribution::Uniform ? "uniform" : "normal",
                         r->type == Type::Vec ? "_vec" : "", r->owner.empty() ? "" : r->owner + "#",
                         r->stream);
    }
    case ExprKind::FnArg: return as<FnArg>(e)->name;
    case ExprKind::FnCall: {
      auto c = as<FnCall>(e);
      return model.functions[c->fn].name + "(" + join(c->args, model, labels) + ")";
    }
    case ExprKind::Select: {
      auto c = as<Select>(e);
      return "if(" + join({c->condition, c->then, c->otherwise}, model, labels) + ")";
    }
    case ExprKind::Accumulate: {
      auto a = as<Accumulate>(e);
      const Label& l = labels[a->label];
      return fmt::format("{}#{}({} in {}, {}, {}):{}", reduction_name(a->reduction), a->id, l.name,
                         model.sets[l.set].name, a->condition ? to_string(a->condition, model, labels) : "true",
                         a->body ? to_string(a->body, model, labels) : "1", type_name(a->type));
    }
  }
  internal_error("ir::to_string: unknown expression kind");
}

std::string to_string(const Model& model) {
  std::string out = fmt::format("model {}\ndim {}\ndomain", model.name, model.dim);
  for (int k = 0; k < model.dim; ++k)
    out += fmt::format(" [{}, {}]{}", model.domain.lo[k], model.domain.hi[k],
                       model.domain.periodic[k] ? " periodic" : "");
  out += "\n";
  const std::vector<Label> none;
  for (const Param& p : model.params)
    out += fmt::format("param {}: {} = {}\n", p.name, type_name(p.type), to_string(p.default_value, model, none));
  for (const Const& c : model.consts)
    out += fmt::format("const {}: {} = {}\n", c.name, type_name(c.type), to_string(c.value, model, none));
  for (const UserFn& f : model.functions) {
    std::string args;
    for (std::size_t k = 0; k < f.arg_names.size(); ++k)
      args += fmt::format("{}{}: {}", k ? ", " : "", f.arg_names[k], type_name(f.arg_types[k]));
    out += fmt::format("fn {}({}): {} = {}\n", f.name, args, type_name(f.body->type),
                       to_string(f.body, model, none));
  }
  for (const ParticleSet& s : model.sets) {
    out += fmt::format("set {} (count {})\n", s.name, to_string(s.initial_count, model, none));
    for (const Variable& v : s.vars)
      out += fmt::format("  {}: {}{}{}{}\n", v.name, type_name(v.type),
                         v.builtin ? " (builtin)" : "",
                         v.storage == Precision::Float ? " (stored as float)" : "",
                         v.initial ? " = " + to_string(v.initial, model, {{"i", 0}}) : "");
  }
  for (const Observable& o : model.observables)
    if (!o.builtin)
      out += fmt::format("observable {}: {} = {}\n", o.name, type_name(o.type),
                         to_string(o.initial, model, none));
  if (model.timestep) out += "timestep " + to_string(model.timestep, model, none) + "\n";
  if (!model.log.observables.empty()) {
    out += "output";
    for (int o : model.log.observables) out += " " + model.observables[o].name;
    if (model.log.every) out += " every " + to_string(model.log.every, model, none);
    out += "\n";
  }
  for (const Stage& stage : model.stages) {
    out += fmt::format("{} {}\n",
                       stage.kind == StageKind::Init   ? "init"
                       : stage.kind == StageKind::Step ? "step"
                                                       : "stage " + stage.name,
                       stage.set >= 0 ? model.sets[stage.set].name : "(observables)");
    for (const Statement& st : stage.statements) {
      const std::string target = st.observable >= 0
                                     ? model.observables[st.observable].name
                                     : model.sets[st.set].vars[st.var].name + "[" + st.labels[0].name + "]";
      out += fmt::format("  {} {} {}  # line {}, {}\n", target, assign_op_spelling(st.op),
                         to_string(st.value, model, st.labels), st.line, type_name(st.value->type));
    }
  }
  return out;
}

}  // namespace partc::ir
