#include "ast/ast.hpp"

namespace partc::ast {

namespace {
struct LocationOf {
  template <class Node>
  Location operator()(const Node& node) const {
    return node.loc;
  }
  template <class Node>
  Location operator()(const x3::forward_ast<Node>& node) const {
    return node.get().loc;
  }
};
}  // namespace

const Operand* sole_operand(const Chain& chain) {
  const Operand* operand = &chain.first;
  if (!chain.rest.empty()) return nullptr;
  for (;;) {
    if (auto inner = boost::get<x3::forward_ast<Chain>>(operand)) {
      if (!inner->get().rest.empty()) return nullptr;
      operand = &inner->get().first;
    } else if (auto postfix = boost::get<x3::forward_ast<Postfix>>(operand)) {
      if (!postfix->get().components.empty()) return operand;
      operand = &postfix->get().base;
    } else {
      return operand;
    }
  }
}

Location location_of(const Operand& operand) { return boost::apply_visitor(LocationOf{}, operand); }
Location location_of(const Argument& argument) {
  return boost::apply_visitor(LocationOf{}, argument);
}

}  // namespace partc::ast

namespace partc::ast {

std::string dotted(const std::vector<Identifier>& parts) {
  std::string out;
  for (const Identifier& part : parts) out += (out.empty() ? "" : ".") + part.name;
  return out;
}

const Identifier* global_name(const Declaration& decl) {
  if (auto p = boost::get<ParamDecl>(&decl)) return &p->name;
  if (auto c = boost::get<ConstDecl>(&decl)) return &c->name;
  if (auto f = boost::get<FnDecl>(&decl)) return &f->name;
  if (auto o = boost::get<ObservableDecl>(&decl)) return &o->name;
  return nullptr;
}

}  // namespace partc::ast
