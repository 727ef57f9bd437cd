// Scene instantiation: each `use` becomes declarations and statements of a
// plain model.
//
// An instance's parameters become params named INSTANCE.NAME (--set
// lj.eps=1.2); its const parameters become consts, so a constant cutoff is a
// literal radius; a module's functions are named MODULE.NAME, once however
// many instances use them. Owned variables join their set; provided
// observables join the scene. Statements go to the slots of their set's
// integrator, slot by slot, in the order of the use lines (or of an order
// declaration); all contributions to one variable at one slot become one
// statement, so sums over one set share one pair walk. Random draws are
// keyed by instance, so adding or dropping one effect leaves the others'
// noise as it was.
#include <algorithm>
#include <set>
#include <stdexcept>

#include "sema/scene_parts.hpp"

namespace partc {

namespace {

using scene::Instance;

bool random_builtin(const std::string& name) {
  return name == "uniform" || name == "normal" || name == "uniform_vec" || name == "normal_vec";
}

// Renames an effect's (or module's) names in a copy of its text.
struct Renamer {
  std::map<std::string, std::string> names;  // local -> qualified
  std::map<std::string, std::string> sets;   // formal -> actual
  std::map<std::string, std::string> vars;   // local variables -> the instance's
  std::set<std::string> params;  // a function's own parameters, named as they are
  const std::set<std::string>* scene_names = nullptr;
  std::string instance;  // empty in a module's own functions and constants
  std::vector<Diagnostic>* problems = nullptr;

  void identifier(ast::Identifier& id) const {
    if (params.count(id.name)) return;
    if (auto it = names.find(id.name); it != names.end()) {
      id.name = it->second;
    } else if (auto set = sets.find(id.name); set != sets.end()) {
      id.name = set->second;
    } else if (scene_names->count(id.name)) {
      problems->push_back(
          {id.loc,
           (instance.empty() ? "a module" : "effect " + instance) + " names " + id.name +
               ", which is the scene's",
           "names inside a module are its own: pass the value as a parameter of the effect"});
    }
  }
  void chain(ast::Chain& c) const {
    operand(c.first);
    for (ast::BinaryOp& op : c.rest) operand(op.rhs);
  }
  void operand(ast::Operand& o) const;
  ast::Chain copy(const ast::Chain& c) const {
    ast::Chain out = c;
    chain(out);
    return out;
  }
};

// The walk of Renamer::operand over one operand's alternatives.
struct RenameWalk {
  const Renamer& r;
  void operator()(ast::Identifier& n) const { r.identifier(n); }
  void operator()(ast::Indexed& n) const {
    if (auto it = r.vars.find(n.var.name); it != r.vars.end()) n.var.name = it->second;
  }
  void operator()(ast::Chain& n) const { r.chain(n); }
  void operator()(ast::Unary& n) const { r.operand(n.operand); }
  void operator()(ast::Norm& n) const { r.chain(n.inner); }
  void operator()(ast::Postfix& n) const { r.operand(n.base); }
  void operator()(ast::Call& n) const {
    if (random_builtin(n.callee.name)) n.random_key = r.instance;
    if (auto it = r.names.find(n.callee.name); it != r.names.end()) n.callee.name = it->second;
    for (ast::Argument& a : n.args) {
      if (auto chain = boost::get<ast::Chain>(&a)) r.chain(*chain);
      if (auto binding = boost::get<ast::LabelBinding>(&a))
        for (ast::Identifier& set : binding->sets)
          if (auto it = r.sets.find(set.name); it != r.sets.end()) set.name = it->second;
    }
  }
  template <class T>
  void operator()(ast::x3::forward_ast<T>& n) const {
    (*this)(n.get());
  }
  template <class T>
  void operator()(T&) const {}
};

void Renamer::operand(ast::Operand& o) const { boost::apply_visitor(RenameWalk{*this}, o); }

ast::Chain literal_zero(const std::string& type, Location at) {
  ast::Chain c;
  c.loc = at;
  if (type == "bool") {
    ast::BoolLiteral b;
    b.loc = at;
    c.first = b;
  } else {
    ast::IntLiteral zero;
    zero.loc = at;
    c.first = zero;
  }
  return c;
}

ast::Identifier named(const std::string& name, Location at) {
  ast::Identifier id;
  id.name = name;
  id.loc = at;
  return id;
}

ast::Operand parenthesised(ast::Chain c) {
  return ast::Operand(ast::x3::forward_ast<ast::Chain>(c));
}

// The name a module's function or constant declares; null for anything else.
const ast::Identifier* declared_name(const ast::Declaration& decl) {
  if (auto f = boost::get<ast::FnDecl>(&decl)) return &f->name;
  if (auto c = boost::get<ast::ConstDecl>(&decl)) return &c->name;
  return nullptr;
}

// The statements of one slot on one set, as they run.
struct Placed {
  const Instance* inst;
  const ast::Assignment* st;
};

class Instantiation {
 public:
  Instantiation(const ast::Program& scene, SourceFile& file, const SceneOptions& options,
                SceneReport& report)
      : scene_(scene),
        file_(file),
        options_(options),
        report_(report),
        library_(file, options.roots, report) {}

  ast::Program run();

 private:
  // Where run() puts each of made_.declared: after the scene declaration of
  // this index (-1: where the scene first needs them).
  std::vector<int> made_declarations_after() const;
  void find_instances();
  void collect_scene_names();
  std::string qualified(const std::string& name, Location at);
  const Renamer& declare_module(const scene::Module& module);
  void import_into_scene();
  void declare_instances();
  void place_statements();
  std::vector<ast::BlockStatement> slot_statements(const std::string& set, const std::string& slot,
                                                   std::set<std::string>& cleared,
                                                   const char* stage);
  std::vector<std::string> slot_order() const;
  ast::ScheduleBlock schedule(const ast::ScheduleBlock& block) const;
  void error(Location at, std::string message, std::string note = {}) {
    problems_.push_back({at, std::move(message), std::move(note)});
  }
  void flush() {
    if (!problems_.empty()) throw CompileError(problems_);
  }

  const ast::Program& scene_;
  SourceFile& file_;
  const SceneOptions& options_;
  SceneReport& report_;
  scene::ModuleLibrary library_;
  std::vector<Diagnostic> problems_;
  std::vector<Instance> instances_;
  std::map<const Instance*, Renamer> renamers_;
  std::map<const scene::Module*, Renamer> module_scopes_;  // declared modules' own names
  std::map<std::string, std::string> mangled_;             // C++ name -> qualified name
  std::set<std::string> scene_names_;
  std::vector<std::string> set_names_;
  std::vector<std::string> order_;
  scene::Owners owners_;
  scene::Instantiated made_;
  std::map<std::string, std::vector<std::string>> statements_of_;  // instance -> names
  std::set<std::string> statement_names_;
};

void Instantiation::find_instances() {
  for (const ast::Declaration& decl : scene_.declarations) {
    if (auto set = boost::get<ast::ParticlesDecl>(&decl)) set_names_.push_back(set->name.name);
    if (auto order = boost::get<ast::OrderDecl>(&decl))
      for (const ast::Identifier& name : order->instances) order_.push_back(name.name);
  }
  std::set<std::string> seen;
  for (const ast::Declaration& decl : scene_.declarations) {
    auto use = boost::get<ast::UseDecl>(&decl);
    if (!use) continue;
    const std::string name = use->alias ? use->alias->name : use->module.back().name;
    if (!seen.insert(name).second) {
      error(use->alias ? use->alias->loc : use->module.back().loc,
            "a second instance named " + name,
            "name each instance of one effect: use " + ast::dotted(use->module) + " on ... as " +
                name + "_2");
      continue;
    }
    if (std::count(options_.drop.begin(), options_.drop.end(), name)) {
      report_.dropped.push_back(name);
      // The C++ numbers the scene's lines as if this one were deleted.
      file_.omit_lines(file_.line_column(use->loc.begin).line,
                       file_.line_column(use->loc.end - 1).line);
      continue;
    }
    Instance inst;
    inst.name = name;
    inst.use = use;
    inst.module = &library_.open(*use);
    const ast::EffectDecl& effect = inst.effect();
    for (const ast::EffectItem& item : effect.items)
      if (auto owns = boost::get<ast::OwnsItem>(&item); owns && owns->local)
        inst.locals[owns->name.name] = name + "_" + owns->name.name;
    if (use->sets.size() != effect.sets.size()) {
      error(use->sets.front().loc,
            "effect " + effect.name.name + " acts on " + std::to_string(effect.sets.size()) +
                " set(s), not " + std::to_string(use->sets.size()),
            "declared at " + file_.line_reference(effect.loc.begin));
      continue;
    }
    for (std::size_t k = 0; k < use->sets.size(); ++k) {
      const std::string& actual = use->sets[k].name;
      if (!std::count(set_names_.begin(), set_names_.end(), actual))
        error(use->sets[k].loc, "no particle set named " + actual,
              "declare it with: particles " + actual + "(N) { }");
      inst.sets[effect.sets[k].name] = actual;
      inst.actual_sets.push_back(actual);
    }
    std::set<std::string> given;
    for (const ast::UseArgument& arg : use->args) {
      const bool known =
          std::any_of(effect.params.begin(), effect.params.end(),
                      [&](const ast::EffectParam& p) { return p.name.name == arg.name.name; });
      if (!known) {
        std::string list;
        for (const ast::EffectParam& p : effect.params)
          list += (list.empty() ? "" : ", ") + p.name.name;
        error(arg.name.loc, "effect " + effect.name.name + " has no parameter " + arg.name.name,
              list.empty() ? "it takes none" : "its parameters are " + list);
      }
      if (!given.insert(arg.name.name).second)
        error(arg.name.loc, "parameter " + arg.name.name + " given twice");
    }
    report_.kept.push_back({name, inst.module->name, inst.module->path, inst.actual_sets, use->loc});
    instances_.push_back(std::move(inst));
  }
  for (const std::string& name : options_.drop)
    if (!seen.count(name)) {
      std::string list;
      for (const std::string& s : seen) list += (list.empty() ? "" : ", ") + s;
      throw std::invalid_argument("--drop " + name + ": the scene has no effect instance named " +
                                  name + (list.empty() ? "" : " (it has " + list + ")"));
    }
  flush();
}

void Instantiation::collect_scene_names() {
  for (const ast::Declaration& decl : scene_.declarations) {
    if (auto p = boost::get<ast::ParamDecl>(&decl)) scene_names_.insert(p->name.name);
    if (auto c = boost::get<ast::ConstDecl>(&decl)) scene_names_.insert(c->name.name);
    if (auto f = boost::get<ast::FnDecl>(&decl)) scene_names_.insert(f->name.name);
    if (auto o = boost::get<ast::ObservableDecl>(&decl)) scene_names_.insert(o->name.name);
  }
}

std::string Instantiation::qualified(const std::string& name, Location at) {
  const std::string cpp = scene::mangled(name);
  auto [it, fresh] = mangled_.insert({cpp, name});
  if (scene_names_.count(cpp) || (!fresh && it->second != name))
    error(at,
          name + " would be named " + cpp + " in C++, as " +
              (scene_names_.count(cpp) ? "the scene's " + cpp : it->second) + " is",
          "rename the scene's declaration or the instance (use ... as NAME)");
  return name;
}

// The names a module's text sees: its own functions and constants and those
// of the modules it imports, each named MODULE.NAME. Declares the module's
// functions and constants once, after those of its imports.
const Renamer& Instantiation::declare_module(const scene::Module& module) {
  if (auto it = module_scopes_.find(&module); it != module_scopes_.end()) return it->second;
  Renamer scope;
  scope.scene_names = &scene_names_;
  scope.problems = &problems_;
  std::map<std::string, std::string> from;  // imported name -> the module it came from
  for (const scene::Module* imported : module.imports) {
    const Renamer& theirs = declare_module(*imported);
    for (const ast::Declaration& decl : imported->program.declarations) {
      const ast::Identifier* name = declared_name(decl);
      if (!name) continue;
      auto [it, fresh] = from.insert({name->name, imported->name});
      if (!fresh && it->second != imported->name)
        error(name->loc, module.name + " imports " + name->name + " from both " + it->second +
                             " and " + imported->name,
              "import one of them, or rename one");
      scope.names[name->name] = theirs.names.at(name->name);
    }
  }
  for (const ast::Declaration& decl : module.program.declarations) {
    const ast::Identifier* name = declared_name(decl);
    if (!name) continue;
    if (auto it = from.find(name->name); it != from.end())
      error(name->loc, module.name + " declares " + name->name + ", which it imports from " +
                           it->second,
            "rename one of them");
    scope.names[name->name] = qualified(module.name + "." + name->name, name->loc);
  }
  for (const ast::Declaration& decl : module.program.declarations) {
    if (auto f = boost::get<ast::FnDecl>(&decl)) {
      ast::FnDecl copy = *f;
      Renamer body = scope;
      for (const ast::FnParam& a : f->params) body.params.insert(a.name.name);
      copy.name.name = scope.names[f->name.name];
      copy.from_module = true;
      body.chain(copy.value);
      made_.declared.emplace_back(copy);
    }
    if (auto c = boost::get<ast::ConstDecl>(&decl)) {
      ast::ConstDecl copy = *c;
      copy.name.name = scope.names[c->name.name];
      scope.chain(copy.value);
      made_.declared.emplace_back(copy);
    }
  }
  return module_scopes_[&module] = scope;
}

// `import M` in a scene: M's functions and constants under their own names,
// each a one-line alias of the module's (inlined like any call).
void Instantiation::import_into_scene() {
  std::map<std::string, std::string> from;
  for (const ast::Declaration& decl : scene_.declarations) {
    auto import = boost::get<ast::ImportDecl>(&decl);
    if (!import) continue;
    const scene::Module& module = library_.open(*import);
    const Renamer& scope = declare_module(module);
    for (const ast::Declaration& d : module.program.declarations) {
      const ast::Identifier* name = declared_name(d);
      if (!name) continue;
      if (scene_names_.count(name->name) && !from.count(name->name)) {
        error(import->loc,
              "import " + module.name + " brings " + name->name + ", which the scene declares",
              "rename the scene's " + name->name + " (" + module.name + "'s is at " +
                  file_.line_reference(name->loc.begin) + ")");
        continue;
      }
      if (auto [it, fresh] = from.insert({name->name, module.name}); !fresh) {
        error(import->loc,
              "import " + module.name + " brings " + name->name + ", which " + it->second +
                  " brought too",
              "import one of them");
        continue;
      }
      scene_names_.insert(name->name);
      const ast::Identifier original = named(scope.names.at(name->name), name->loc);
      if (auto c = boost::get<ast::ConstDecl>(&d)) {
        ast::ConstDecl alias;
        alias.loc = c->loc;
        alias.name = c->name;
        alias.value.loc = c->loc;
        alias.value.first = original;
        made_.declared.emplace_back(alias);
        continue;
      }
      const auto& f = boost::get<ast::FnDecl>(d);
      ast::FnDecl alias;
      alias.loc = f.loc;
      alias.name = f.name;
      alias.params = f.params;
      alias.from_module = true;
      ast::Call call;
      call.loc = f.loc;
      call.callee = original;
      for (const ast::FnParam& a : f.params) {
        ast::Chain arg;
        arg.loc = a.loc;
        arg.first = a.name;
        call.args.emplace_back(arg);
      }
      alias.value.loc = f.loc;
      alias.value.first = ast::x3::forward_ast<ast::Call>(call);
      made_.declared.emplace_back(alias);
    }
  }
  flush();
}

void Instantiation::declare_instances() {
  for (const Instance& inst : instances_) {
    Renamer r = declare_module(*inst.module);
    r.sets = inst.sets;
    r.vars = inst.locals;
    r.instance = inst.name;
    const ast::EffectDecl& effect = inst.effect();
    for (const ast::EffectParam& p : effect.params)
      r.names[p.name.name] = qualified(inst.name + "." + p.name.name, p.name.loc);
    for (const ast::EffectItem& item : effect.items)
      if (auto c = boost::get<ast::ConstDecl>(&item))
        r.names[c->name.name] = qualified(inst.name + "." + c->name.name, c->name.loc);

    for (const ast::EffectParam& p : effect.params) {
      // A value given at the use line is the scene's expression; a default is the module's.
      const ast::UseArgument* arg = nullptr;
      for (const ast::UseArgument& a : inst.use->args)
        if (a.name.name == p.name.name) arg = &a;
      const ast::Chain value = arg ? arg->value : r.copy(p.value);
      const ast::Identifier name = named(r.names[p.name.name], p.name.loc);
      if (p.is_const || (arg && arg->is_const)) {
        ast::ConstDecl c;
        c.loc = p.loc;
        c.name = name;
        c.value = value;
        made_.declared.emplace_back(c);
      } else {
        ast::ParamDecl d;
        d.loc = p.loc;
        d.name = name;
        d.type = p.type;
        d.value = value;
        made_.declared.emplace_back(d);
      }
    }
    for (const ast::EffectItem& item : effect.items) {
      if (auto c = boost::get<ast::ConstDecl>(&item)) {
        ast::ConstDecl copy = *c;
        copy.name.name = r.names[c->name.name];
        r.chain(copy.value);
        made_.declared.emplace_back(copy);
      } else if (auto t = boost::get<ast::TimestepDecl>(&item)) {
        ast::TimestepDecl copy = *t;
        r.chain(copy.value);
        made_.declared.emplace_back(copy);
      } else if (auto o = boost::get<ast::ProvidesItem>(&item)) {
        ast::ObservableDecl d;
        d.loc = o->loc;
        d.name = o->name;
        d.type = o->type;
        d.value = literal_zero(o->type.name, o->loc);
        made_.declared.emplace_back(d);
      } else if (auto owns = boost::get<ast::OwnsItem>(&item)) {
        ast::VarDecl v;
        v.loc = owns->loc;
        v.mirrored = owns->mirrored;
        v.effect_owned = true;
        v.name = named(inst.var(owns->name.name), owns->name.loc);
        v.type = owns->type;
        if (owns->value) v.value = r.copy(*owns->value);
        made_.owned[inst.home()].push_back(v);
      } else if (auto req = boost::get<ast::RequiresItem>(&item)) {
        made_.requirements.push_back({r.copy(req->condition), req->loc, inst.use->loc, inst.name});
      }
    }
    renamers_[&inst] = r;
  }
  flush();
}

// The slots of every integrator, merged: each keeps its own order, and a
// slot two integrators share runs once for both sets.
std::vector<std::string> Instantiation::slot_order() const {
  std::vector<std::string> order;
  for (const Instance& inst : instances_) {
    if (!inst.integrator()) continue;
    auto at = order.begin();
    for (const std::string& slot : inst.slots("slots")) {
      auto found = std::find(order.begin(), order.end(), slot);
      at = found != order.end() ? found + 1 : order.insert(at, slot) + 1;
    }
  }
  return order;
}

std::vector<ast::BlockStatement> Instantiation::slot_statements(const std::string& set,
                                                                const std::string& slot,
                                                                std::set<std::string>& cleared,
                                                                const char* stage) {
  std::vector<Placed> placed;
  for (const Instance& inst : instances_)
    if (inst.home() == set)
      for (const ast::EffectItem& item : inst.effect().items)
        if (auto at = boost::get<ast::AtItem>(&item); at && at->slot.name == slot)
          placed.push_back({&inst, &at->statement});
  // An order declaration reorders the instances it names among themselves.
  std::vector<std::size_t> listed;
  for (std::size_t k = 0; k < placed.size(); ++k)
    if (std::count(order_.begin(), order_.end(), placed[k].inst->name)) listed.push_back(k);
  std::vector<Placed> sorted;
  for (std::size_t k : listed) sorted.push_back(placed[k]);
  auto rank = [&](const Placed& p) {
    return std::find(order_.begin(), order_.end(), p.inst->name) - order_.begin();
  };
  std::stable_sort(sorted.begin(), sorted.end(),
                   [&](const Placed& a, const Placed& b) { return rank(a) < rank(b); });
  for (std::size_t k = 0; k < listed.size(); ++k) placed[listed[k]] = sorted[k];

  // The contributions to one variable become one statement, placed where
  // the last of them was: every effect's earlier statements at the slot
  // (which its term may read) run before it. Named after the first.
  auto adds = [](const Placed& p) { return p.st->op == "+=" || p.st->op == "-="; };
  std::map<std::string, std::size_t> first_of, last_of;
  for (std::size_t k = 0; k < placed.size(); ++k)
    if (adds(placed[k])) {
      const std::string var = placed[k].inst->var(placed[k].st->target.var.name);
      first_of.emplace(var, k);
      last_of[var] = k;
    }
  std::vector<ast::BlockStatement> out;
  for (std::size_t k = 0; k < placed.size(); ++k) {
    const std::string var = placed[k].inst->var(placed[k].st->target.var.name);
    if (adds(placed[k]) && last_of[var] != k) continue;
    const Placed& first = adds(placed[k]) ? placed[first_of[var]] : placed[k];
    ast::Assignment st;
    st.loc = first.st->loc;
    st.target = first.st->target;
    st.target.var.name = var;
    std::vector<std::string> effects;
    if (!adds(first)) {
      st.op = first.st->op;
      st.value = renamers_.at(first.inst).copy(first.st->value);
      st.origins.push_back({first.inst->name, first.st->loc});
      effects.push_back(first.inst->name);
    } else {
      const auto owner = owners_.find({set, var});
      const bool clears =
          owner != owners_.end() && owner->second.channel && cleared.insert(var).second;
      st.op = clears ? "=" : "+=";
      st.value.loc = first.st->value.loc;
      bool empty = true;
      for (const Placed& term : placed) {
        // An effect's own statement replacing the variable at this slot is not a term.
        if (!adds(term) || term.inst->var(term.st->target.var.name) != var) continue;
        if (term.st->target.label && first.st->target.label &&
            term.st->target.label->name != first.st->target.label->name)
          error(term.st->target.loc,
                "contributions to " + var +
                    " at one slot must name the particle alike: " + first.st->target.label->name +
                    " (as " + first.inst->name + " does), not " + term.st->target.label->name);
        ast::Chain value = renamers_.at(term.inst).copy(term.st->value);
        const bool minus = term.st->op == "-=";
        if (empty) {
          if (minus) {
            ast::Unary negated;
            negated.loc = value.loc;
            negated.op = "-";
            negated.operand = parenthesised(value);
            st.value.first = ast::Operand(ast::x3::forward_ast<ast::Unary>(negated));
          } else {
            st.value.first = parenthesised(value);
          }
        } else {
          ast::BinaryOp op;
          op.loc = value.loc;
          op.op = minus ? "-" : "+";
          op.rhs = parenthesised(value);
          st.value.rest.push_back(op);
        }
        empty = false;
        st.origins.push_back({term.inst->name, term.st->loc});
        effects.push_back(term.inst->name);
      }
    }
    std::string name = std::string(stage) + "_" + slot + "_" + var;
    for (int k = 2; statement_names_.count(name); ++k)
      name = std::string(stage) + "_" + slot + "_" + var + "_" + std::to_string(k);
    statement_names_.insert(name);
    st.name = named(name, st.loc);
    for (const std::string& e : effects)
      if (std::find(statements_of_[e].begin(), statements_of_[e].end(), name) ==
          statements_of_[e].end())
        statements_of_[e].push_back(name);
    std::string line = std::string(stage) + ", slot " + slot + ", " + set + ": " + var +
                       (st.target.label ? "[" + st.target.label->name + "]" : "") + " " + st.op +
                       " ";
    for (std::size_t k = 0; k < effects.size(); ++k) line += (k ? " + " : "") + effects[k];
    if (effects.size() > 1) line += " (merged into one statement)";
    report_.placements.push_back({name, line});
    out.emplace_back(std::move(st));
  }
  return out;
}

void Instantiation::place_statements() {
  for (const ast::Declaration& decl : scene_.declarations)
    if (auto stage = boost::get<ast::StageBlock>(&decl))
      for (const ast::BlockStatement& s : stage->body)
        if (auto a = boost::get<ast::Assignment>(&s); a && a->name)
          statement_names_.insert(a->name->name);
  const std::map<std::string, const Instance*> integrator = scene::integrators(instances_);
  auto block = [&](const char* kind, const std::string& set,
                   std::vector<ast::BlockStatement> body) {
    ast::StageBlock b;
    b.kind = kind;
    b.loc = boost::get<ast::Assignment>(body.front()).loc;
    b.words.push_back(named(set, b.loc));
    b.body = std::move(body);
    return b;
  };
  // Slots an integrator primes run once after init, in their order.
  for (const std::string& set : set_names_) {
    auto it = integrator.find(set);
    if (it == integrator.end()) continue;
    std::set<std::string> cleared;
    for (const std::string& slot : it->second->slots("slots")) {
      const std::vector<std::string> primed = it->second->slots("prime");
      if (!std::count(primed.begin(), primed.end(), slot)) continue;
      auto body = slot_statements(set, slot, cleared, "init");
      if (body.empty()) continue;
      made_.init.push_back(block("init", set, std::move(body)));
      made_.init.back().also_after_load = true;
    }
  }
  std::map<std::string, std::set<std::string>> cleared;  // per set
  for (const std::string& slot : slot_order())
    for (const std::string& set : set_names_) {
      auto body = slot_statements(set, slot, cleared[set], "step");
      if (!body.empty()) made_.step.push_back(block("step", set, std::move(body)));
    }
  flush();
}

// A schedule entry for an instance applies to every statement it is in
// that liveness kept and that runs over particles (an observable's
// statement has no search to schedule).
ast::ScheduleBlock Instantiation::schedule(const ast::ScheduleBlock& block) const {
  std::set<std::string> schedulable;
  for (const auto* blocks : {&made_.init, &made_.step})
    for (const ast::StageBlock& b : *blocks)
      for (const ast::BlockStatement& s : b.body)
        if (auto a = boost::get<ast::Assignment>(&s); a && a->name && a->target.label)
          schedulable.insert(a->name->name);
  ast::ScheduleBlock out = block;
  out.items.clear();
  for (const ast::ScheduleItem& item : block.items) {
    auto it = item.subject && !item.subject->member ? statements_of_.find(item.subject->name.name)
                                                    : statements_of_.end();
    if (it == statements_of_.end()) {
      out.items.push_back(item);
      continue;
    }
    for (const std::string& statement : it->second) {
      if (!schedulable.count(statement)) continue;
      ast::ScheduleItem copy = item;
      copy.subject->name.name = statement;
      out.items.push_back(copy);
    }
  }
  return out;
}

std::vector<int> Instantiation::made_declarations_after() const {
  // A scene name -> its declaration's index and where it is declared.
  std::map<std::string, std::pair<std::size_t, Location>> scene_names;
  for (std::size_t k = 0; k < scene_.declarations.size(); ++k) {
    const ast::Declaration& decl = scene_.declarations[k];
    if (const ast::Identifier* name = ast::global_name(decl))
      scene_names.emplace(name->name, std::make_pair(k, name->loc));
  }
  std::vector<int> after(made_.declared.size(), -1);
  std::map<std::string, std::size_t> made_names;  // those before the one looked at
  for (std::size_t m = 0; m < made_.declared.size(); ++m) {
    const ast::Declaration& decl = made_.declared[m];
    const ast::Chain* value = nullptr;
    std::set<std::string> own;  // a function's parameters shadow the scene's names
    if (auto p = boost::get<ast::ParamDecl>(&decl)) value = &p->value;
    if (auto c = boost::get<ast::ConstDecl>(&decl)) value = &c->value;
    if (auto o = boost::get<ast::ObservableDecl>(&decl)) value = &o->value;
    if (auto t = boost::get<ast::TimestepDecl>(&decl)) value = &t->value;
    if (auto f = boost::get<ast::FnDecl>(&decl)) {
      value = &f->value;
      for (const ast::FnParam& a : f->params) own.insert(a.name.name);
    }
    if (!value) continue;
    scene::for_each_name_read(*value, [&](const ast::Identifier& n) {
      if (own.count(n.name)) return;
      // Only a scene declaration above the reader (the use line's argument)
      // defers it: one below is out of order, and sema says so.
      if (auto it = scene_names.find(n.name);
          it != scene_names.end() && it->second.second.begin < n.loc.begin)
        after[m] = std::max(after[m], static_cast<int>(it->second.first));
      else if (auto mine = made_names.find(n.name); mine != made_names.end())
        after[m] = std::max(after[m], after[mine->second]);
    });
    if (const ast::Identifier* name = ast::global_name(decl)) made_names[name->name] = m;
  }
  return after;
}

ast::Program Instantiation::run() {
  find_instances();
  collect_scene_names();
  import_into_scene();
  owners_ = scene::check_interfaces(instances_, scene_, file_);
  declare_instances();
  place_statements();
  scene::drop_dead(scene_, made_, report_);

  ast::Program out;
  auto& decls = out.declarations;
  std::size_t last_init = scene_.declarations.size();
  for (std::size_t k = 0; k < scene_.declarations.size(); ++k)
    if (auto s = boost::get<ast::StageBlock>(&scene_.declarations[k]); s && s->kind == "init")
      last_init = k;
  const std::vector<int> after = made_declarations_after();
  bool declared = false, primed = false, stepped = false;
  auto emit_declared = [&](int k) {  // those that may stand before scene declaration k
    if (declared) return;
    declared = true;
    for (std::size_t m = 0; m < made_.declared.size(); ++m)
      if (after[m] < k) decls.push_back(made_.declared[m]);
  };
  auto emit_deferred = [&](int k) {  // those that wait for scene declaration k
    if (!declared) return;
    for (std::size_t m = 0; m < made_.declared.size(); ++m)
      if (after[m] == k) decls.push_back(made_.declared[m]);
  };
  auto emit_primes = [&] {
    if (primed) return;
    primed = true;
    decls.insert(decls.end(), made_.init.begin(), made_.init.end());
  };
  for (std::size_t k = 0; k < scene_.declarations.size(); ++k) {
    const ast::Declaration& decl = scene_.declarations[k];
    const int at = static_cast<int>(k);
    if (boost::get<ast::UseDecl>(&decl) || boost::get<ast::ImportDecl>(&decl)) {
      emit_declared(at);
      continue;
    }
    if (boost::get<ast::OrderDecl>(&decl)) continue;
    if (auto set = boost::get<ast::ParticlesDecl>(&decl)) {
      emit_declared(at);
      ast::ParticlesDecl copy = *set;
      for (const ast::VarDecl& v : made_.owned[set->name.name]) copy.vars.push_back(v);
      decls.emplace_back(copy);
      continue;
    }
    if (auto s = boost::get<ast::StageBlock>(&decl); s && s->kind == "step" && !stepped) {
      emit_primes();
      stepped = true;
      decls.insert(decls.end(), made_.step.begin(), made_.step.end());
    }
    if (auto s = boost::get<ast::ScheduleBlock>(&decl))
      decls.emplace_back(schedule(*s));
    else
      decls.push_back(decl);
    emit_deferred(at);
    if (k == last_init) emit_primes();
  }
  emit_declared(static_cast<int>(scene_.declarations.size()));
  emit_primes();
  out.requirements = made_.requirements;
  if (!stepped) decls.insert(decls.end(), made_.step.begin(), made_.step.end());
  return out;
}

}  // namespace

ast::Program instantiate_scene(const ast::Program& scene, SourceFile& file,
                               const SceneOptions& options, SceneReport& report) {
  bool uses = false;
  for (const ast::Declaration& decl : scene.declarations) {
    if (auto m = boost::get<ast::ModuleDecl>(&decl))
      throw CompileError(Diagnostic{
          m->loc, "this file is module " + ast::dotted(m->name),
          "a module is compiled by a scene that uses it: use " + ast::dotted(m->name) + " on SET"});
    if (auto e = boost::get<ast::EffectDecl>(&decl))
      throw CompileError(Diagnostic{e->loc, "an effect is declared in a module of its own",
                                    "move it to a file NAME.part that begins: module NAME"});
    uses = uses || boost::get<ast::UseDecl>(&decl) || boost::get<ast::OrderDecl>(&decl) ||
           boost::get<ast::ImportDecl>(&decl);
  }
  if (!uses) {
    for (const std::string& name : options.drop)
      throw std::invalid_argument("--drop " + name + ": the model uses no effects");
    return scene;
  }
  return Instantiation(scene, file, options, report).run();
}

}  // namespace partc
