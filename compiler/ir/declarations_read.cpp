#include "ir/declarations_read.hpp"

#include <memory>

#include "ir/mutator.hpp"
#include "ir/visitor.hpp"

namespace partc::ir {

namespace {

// Calls f on every expression of the model that is not a function's body or
// a const's value: those are read only through these. M is Model or const Model.
template <class M, class F>
void for_each_root(M& model, F&& f) {
  for (auto& p : model.params) f(p.default_value);
  for (auto& set : model.sets) {
    f(set.initial_count);
    for (auto& var : set.vars) f(var.initial);
  }
  for (auto& o : model.observables) f(o.initial);
  f(model.timestep);
  f(model.log.every);
  for (auto& frames : model.frames) f(frames.every);
  for (auto& stage : model.stages) {
    for (auto& st : stage.statements) {
      f(st.value);
      f(st.solve_operator);
      for (auto& part : st.without) f(part.value);
      f(st.schedule.skin);
      f(st.schedule.tolerance);
      f(st.schedule.max_iterations);
      f(st.schedule.order);
    }
    for (auto& loop : stage.loops) {
      f(loop.until);
      f(loop.limit);
    }
  }
}

// Marks what an expression reads; what is newly marked is read in turn.
class Reader : public Visitor {
 public:
  Reader(const Model& model, DeclarationsRead& read) : model_(model), read_(read) {}
  using Visitor::visit;

 protected:
  void visit(const FnCall& n) override {
    if (!read_.functions[n.fn]) {
      read_.functions[n.fn] = true;
      visit(model_.functions[n.fn].body);
    }
    Visitor::visit(n);
  }
  void visit(const ConstRef& n) override {
    if (read_.consts[n.constant]) return;
    read_.consts[n.constant] = true;
    visit(model_.consts[n.constant].value);
  }

 private:
  const Model& model_;
  DeclarationsRead& read_;
};

// References renumbered after some functions and consts were removed.
class Renumber : public Mutator {
 public:
  Renumber(std::vector<int> functions, std::vector<int> consts)
      : functions_(std::move(functions)), consts_(std::move(consts)) {}
  using Mutator::mutate;

 protected:
  Expr mutate(const FnCall& n, const Expr& self) override {
    Expr out = Mutator::mutate(n, self);  // its arguments
    if (functions_[n.fn] == n.fn) return out;
    return std::make_shared<FnCall>(n.type, functions_[n.fn], as<FnCall>(out)->args, n.loc);
  }
  Expr mutate(const ConstRef& n, const Expr& self) override {
    if (consts_[n.constant] == n.constant) return self;
    return std::make_shared<ConstRef>(n.type, consts_[n.constant], n.loc);
  }

 private:
  std::vector<int> functions_, consts_;  // old index -> new (-1: removed)
};

// Keeps the elements `keep` says, returning each old index's new one (-1: removed).
template <class T>
std::vector<int> keep_only(std::vector<T>& items, const std::vector<bool>& keep) {
  std::vector<int> index(items.size(), -1);
  std::vector<T> kept;
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (!keep[k]) continue;
    index[k] = static_cast<int>(kept.size());
    kept.push_back(std::move(items[k]));
  }
  items = std::move(kept);
  return index;
}

}  // namespace

DeclarationsRead declarations_read(const Model& model) {
  DeclarationsRead read{std::vector<bool>(model.functions.size(), false),
                        std::vector<bool>(model.consts.size(), false)};
  Reader reader(model, read);
  for_each_root(model, [&](const Expr& e) { reader.visit(e); });
  return read;
}

std::vector<DroppedDeclaration> drop_unread_declarations(Model& model,
                                                          const DeclarationsRead& before) {
  const DeclarationsRead now = declarations_read(model);
  std::vector<DroppedDeclaration> dropped;
  std::vector<bool> keep_functions(model.functions.size()), keep_consts(model.consts.size());
  for (std::size_t f = 0; f < model.functions.size(); ++f) {
    keep_functions[f] = now.functions[f] || !before.functions[f];
    if (!keep_functions[f])
      dropped.push_back({"fn", model.functions[f].name, model.functions[f].loc});
  }
  for (std::size_t c = 0; c < model.consts.size(); ++c) {
    keep_consts[c] = now.consts[c] || !before.consts[c];
    if (!keep_consts[c]) dropped.push_back({"const", model.consts[c].name, model.consts[c].loc});
  }
  if (dropped.empty()) return dropped;
  Renumber renumber(keep_only(model.functions, keep_functions), keep_only(model.consts, keep_consts));
  const auto rewrite = [&](Expr& e) { e = renumber.mutate(e); };
  for_each_root(model, rewrite);
  for (UserFn& f : model.functions) rewrite(f.body);
  for (Const& c : model.consts) rewrite(c.value);
  return dropped;
}

}  // namespace partc::ir
