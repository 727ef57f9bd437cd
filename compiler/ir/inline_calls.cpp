#include "ir/inline_calls.hpp"

#include <vector>

#include "ir/mutator.hpp"

namespace partc::ir {

namespace {

class Inliner : public Mutator {
 public:
  Inliner(const Model& model, std::size_t max_calls) : model_(model), calls_left_(max_calls) {}
  bool exhausted = false;
  using Mutator::mutate;

 protected:
  // The arguments first, in the caller's frame; then the body in its own.
  Expr mutate(const FnCall& n, const Expr& self) override {
    if (exhausted || calls_left_ == 0) {
      exhausted = true;
      return self;
    }
    --calls_left_;
    std::vector<Expr> args;
    for (const Expr& a : n.args) args.push_back(mutate(a));
    frames_.push_back(std::move(args));
    Expr body = mutate(model_.functions[n.fn].body);
    frames_.pop_back();
    return body;
  }
  Expr mutate(const FnArg& n, const Expr& self) override {
    return frames_.empty() ? self : frames_.back()[n.index];
  }

 private:
  const Model& model_;
  std::size_t calls_left_;
  std::vector<std::vector<Expr>> frames_;
};

}  // namespace

Expr inline_calls(const Expr& e, const Model& model, std::size_t max_calls) {
  Inliner inliner(model, max_calls);
  Expr inlined = inliner.mutate(e);
  return inliner.exhausted ? nullptr : inlined;
}

}  // namespace partc::ir
