// Scene instantiation: what the scene's effects declare but nothing needs
// is never made.
//
// Runs on the instantiated declarations, before names are resolved: what is
// dropped here never reaches sema, so no variable is stored, no statement
// computed, no search built and no function emitted for it. The roots are
// explicit: everything the scene itself declares or writes (its functions'
// calls too), positions, `output` lines and schedule entries. From them, a statement an effect placed is kept
// when its target is kept, and a target is kept when a kept statement (or a
// kept variable's initial value) reads it; functions of a module are kept
// when something kept calls them. Names are compared as written, so a
// variable read on any set keeps the one of that name on every set: a
// conservative answer, never a wrong one.
#include <functional>
#include <set>

#include "sema/scene_parts.hpp"

namespace partc::scene {

namespace {

// Calls seen(name) on every name an expression reads, as written.
template <class F>
struct IdentifiersRead {
  F seen;
  void chain(const ast::Chain& c) const {
    operand(c.first);
    for (const ast::BinaryOp& op : c.rest) operand(op.rhs);
  }
  void operand(const ast::Operand& o) const { boost::apply_visitor(*this, o); }
  void operator()(const ast::Identifier& n) const { seen(n); }
  void operator()(const ast::Indexed& n) const { seen(n.var); }
  void operator()(const ast::Chain& n) const { chain(n); }
  void operator()(const ast::Unary& n) const { operand(n.operand); }
  void operator()(const ast::Norm& n) const { chain(n.inner); }
  void operator()(const ast::Postfix& n) const { operand(n.base); }
  void operator()(const ast::Call& n) const {
    seen(n.callee);
    for (const ast::Argument& a : n.args)
      if (auto c = boost::get<ast::Chain>(&a)) chain(*c);
  }
  template <class T>
  void operator()(const ast::x3::forward_ast<T>& n) const {
    (*this)(n.get());
  }
  template <class T>
  void operator()(const T&) const {}
};

// Variables, observables, functions and consts read, into `names`.
auto reads_into(std::set<std::string>& names) {
  auto insert = [&names](const ast::Identifier& n) { names.insert(n.name); };
  return IdentifiersRead<decltype(insert)>{insert};
}

void read_statements(const std::vector<ast::BlockStatement>& body, std::set<std::string>& names);

struct StatementReads {
  std::set<std::string>& names;
  void operator()(const ast::Assignment& a) const { reads_into(names).chain(a.value); }
  void operator()(const ast::SolveStatement& s) const {
    reads_into(names).chain(s.lhs);
    reads_into(names).chain(s.rhs);
  }
  void operator()(const ast::x3::forward_ast<ast::IterateBlock>& loop) const {
    reads_into(names).chain(loop.get().until);
    reads_into(names).chain(loop.get().limit);
    read_statements(loop.get().body, names);
  }
};

void read_statements(const std::vector<ast::BlockStatement>& body, std::set<std::string>& names) {
  for (const ast::BlockStatement& s : body) boost::apply_visitor(StatementReads{names}, s);
}

}  // namespace

void for_each_name_read(const ast::Chain& value,
                        const std::function<void(const ast::Identifier&)>& seen) {
  IdentifiersRead<const std::function<void(const ast::Identifier&)>&>{seen}.chain(value);
}

void drop_dead(const ast::Program& scene, Instantiated& made, SceneReport& report) {
  // Roots: what the scene itself writes, reads, outputs and schedules.
  std::set<std::string> live;
  std::set<std::string> roots;  // kept whatever reads them, and why
  for (const ast::Declaration& decl : scene.declarations) {
    if (auto stage = boost::get<ast::StageBlock>(&decl)) read_statements(stage->body, live);
    if (auto out = boost::get<ast::OutputDecl>(&decl))
      for (const ast::Identifier& name : out->names) roots.insert(name.name);
    if (auto schedule = boost::get<ast::ScheduleBlock>(&decl))
      for (const ast::ScheduleItem& item : schedule->items)
        if (item.subject && item.subject->member) roots.insert(item.subject->member->name);
    if (auto set = boost::get<ast::ParticlesDecl>(&decl)) reads_into(live).chain(set->count);
    if (auto c = boost::get<ast::ConstDecl>(&decl)) reads_into(live).chain(c->value);
    if (auto f = boost::get<ast::FnDecl>(&decl)) reads_into(live).chain(f->value);
    if (auto o = boost::get<ast::ObservableDecl>(&decl)) reads_into(live).chain(o->value);
    if (auto t = boost::get<ast::TimestepDecl>(&decl)) reads_into(live).chain(t->value);
  }
  for (const char* builtin : {"p", "id", "alive"}) roots.insert(builtin);
  live.insert(roots.begin(), roots.end());
  // What the scene declares itself is its own business: kept.
  std::set<std::string> candidates;
  for (const auto& [set, vars] : made.owned)
    for (const ast::VarDecl& v : vars) candidates.insert(v.name.name);
  for (const ast::Declaration& decl : made.declared) {
    if (auto o = boost::get<ast::ObservableDecl>(&decl)) candidates.insert(o->name.name);
    if (auto f = boost::get<ast::FnDecl>(&decl)) candidates.insert(f->name.name);
  }

  // A placed statement is kept once its target is; its reads then keep others.
  std::vector<std::pair<ast::StageBlock*, std::size_t>> placed;
  for (auto* blocks : {&made.init, &made.step})
    for (ast::StageBlock& b : *blocks)
      for (std::size_t k = 0; k < b.body.size(); ++k) placed.push_back({&b, k});
  std::set<std::pair<ast::StageBlock*, std::size_t>> kept;
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& at : placed) {
      if (kept.count(at)) continue;
      const auto& st = boost::get<ast::Assignment>(at.first->body[at.second]);
      const std::string& target = st.target.var.name;
      if (candidates.count(target) && !live.count(target)) continue;
      kept.insert(at);
      reads_into(live).chain(st.value);
      changed = true;  // a statement kept: its reads may keep others
    }
    for (const auto& [set, vars] : made.owned)
      for (const ast::VarDecl& v : vars)
        if (live.count(v.name.name) && v.value) {
          const std::size_t before = live.size();
          reads_into(live).chain(*v.value);
          changed |= live.size() != before;
        }
    for (const ast::Declaration& decl : made.declared)
      if (auto f = boost::get<ast::FnDecl>(&decl); f && live.count(f->name.name)) {
        const std::size_t before = live.size();
        reads_into(live).chain(f->value);
        changed |= live.size() != before;
      }
  }

  // Remove what was not kept, saying what would have kept it.
  for (auto* blocks : {&made.init, &made.step}) {
    for (ast::StageBlock& b : *blocks) {
      std::vector<ast::BlockStatement> body;
      for (std::size_t k = 0; k < b.body.size(); ++k) {
        if (kept.count({&b, k})) {
          body.push_back(b.body[k]);
          continue;
        }
        const auto& st = boost::get<ast::Assignment>(b.body[k]);
        report.dropped_statements.push_back(
            {st.name ? st.name->name : st.target.var.name, st.target.var.name, st.loc});
      }
      b.body = std::move(body);
    }
    std::vector<ast::StageBlock> nonempty;
    for (ast::StageBlock& b : *blocks)
      if (!b.body.empty()) nonempty.push_back(std::move(b));
    *blocks = std::move(nonempty);
  }
  for (auto& [set, vars] : made.owned) {
    std::vector<ast::VarDecl> stored;
    for (ast::VarDecl& v : vars) {
      const bool keep = live.count(v.name.name) > 0;
      report.variables.push_back(
          {set + "." + v.name.name, keep,
           keep ? (roots.count(v.name.name) ? "named by the scene (output or schedule)"
                                            : "read by a statement kept")
                : "nothing reads it; output " + set + ": " + v.name.name + " would keep it"});
      if (keep) stored.push_back(std::move(v));
    }
    vars = std::move(stored);
  }
  std::vector<ast::Declaration> declared;
  for (ast::Declaration& decl : made.declared) {
    if (auto o = boost::get<ast::ObservableDecl>(&decl)) {
      const bool keep = live.count(o->name.name) > 0;
      report.variables.push_back(
          {"observable " + o->name.name, keep,
           keep ? "output or read"
                : "nothing reads it; output " + o->name.name + " would keep it"});
      if (!keep) continue;
    }
    if (auto f = boost::get<ast::FnDecl>(&decl); f && !live.count(f->name.name)) {
      report.variables.push_back({"fn " + f->name.name, false, "nothing kept calls it"});
      continue;
    }
    declared.push_back(std::move(decl));
  }
  made.declared = std::move(declared);
}

}  // namespace partc::scene
