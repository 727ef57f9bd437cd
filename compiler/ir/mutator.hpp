// Rewriting of IR expressions.
//
// mutate(expr) returns the rewritten expression. The defaults rebuild a
// node only when one of its children changed, so untouched subtrees are
// shared, not copied. Override mutate() for the nodes a pass rewrites.
#pragma once

#include "ir/ir.hpp"

namespace partc::ir {

class Mutator {
 public:
  virtual ~Mutator() = default;
  Expr mutate(const Expr& e);

 protected:
  virtual Expr mutate(const Literal&, const Expr& self) { return self; }
  virtual Expr mutate(const ParamRef&, const Expr& self) { return self; }
  virtual Expr mutate(const ConstRef&, const Expr& self) { return self; }
  virtual Expr mutate(const ObservableRef&, const Expr& self) { return self; }
  virtual Expr mutate(const VarRef&, const Expr& self) { return self; }
  virtual Expr mutate(const Dx&, const Expr& self) { return self; }
  virtual Expr mutate(const Random&, const Expr& self) { return self; }
  virtual Expr mutate(const FnArg&, const Expr& self) { return self; }
  virtual Expr mutate(const FnCall& n, const Expr& self);
  virtual Expr mutate(const Unary& n, const Expr& self);
  virtual Expr mutate(const Binary& n, const Expr& self);
  virtual Expr mutate(const Call& n, const Expr& self);
  virtual Expr mutate(const MakeVec& n, const Expr& self);
  virtual Expr mutate(const Component& n, const Expr& self);
  virtual Expr mutate(const Select& n, const Expr& self);
  virtual Expr mutate(const Accumulate& n, const Expr& self);
};

}  // namespace partc::ir
