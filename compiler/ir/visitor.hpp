// Read-only traversal of IR expressions.
//
// Override the visit() of the nodes a pass cares about; the defaults visit
// children left to right, so a pass that looks for one kind of node is a
// few lines long. Call visit(expr) on a root; null handles are skipped.
#pragma once

#include <set>
#include <utility>
#include <vector>

#include "ir/ir.hpp"

namespace partc::ir {

class Visitor {
 public:
  virtual ~Visitor() = default;
  void visit(const Expr& e);

 protected:
  virtual void visit(const Literal&) {}
  virtual void visit(const ParamRef&) {}
  virtual void visit(const ConstRef&) {}
  virtual void visit(const ObservableRef&) {}
  virtual void visit(const VarRef&) {}
  virtual void visit(const Dx&) {}
  virtual void visit(const Random&) {}
  virtual void visit(const FnArg&) {}
  virtual void visit(const FnCall& n) {
    for (const Expr& a : n.args) visit(a);
  }
  virtual void visit(const Unary& n) { visit(n.operand); }
  virtual void visit(const Binary& n) {
    visit(n.lhs);
    visit(n.rhs);
  }
  virtual void visit(const Call& n) {
    for (const Expr& a : n.args) visit(a);
  }
  virtual void visit(const MakeVec& n) {
    for (const Expr& c : n.components) visit(c);
  }
  virtual void visit(const Component& n) { visit(n.vec); }
  virtual void visit(const Select& n) {
    visit(n.condition);
    visit(n.then);
    visit(n.otherwise);
  }
  virtual void visit(const Accumulate& n) {
    visit(n.condition);
    visit(n.body);
  }
};

// The accumulations in e, in reading order.
std::vector<const Accumulate*> accumulations_in(const Expr& e);
// Those of a statement: its value's, then its solve operator's.
std::vector<const Accumulate*> accumulations_in(const Statement& st);
// The particle variables e reads, (set, var), each once.
std::set<std::pair<int, int>> variables_read(const Expr& e);

}  // namespace partc::ir
