// Scene instantiation: each effect's body against its interface, and the
// instances of a scene against each other.
//
// An effect says what it owns, reads, sets and contributes to; its
// statements may touch nothing else, so a scene can be assembled from the
// interfaces alone and a conflict is found where it is made: two owners of a
// variable, two integrators on a set, a contribution nobody owns, two
// writers of one variable at one slot that nothing orders. Types are the
// owner's; a reader or contributor that says otherwise is an error at its
// own line, with the owner's in the note.
#include <algorithm>
#include <set>

#include "sema/scene_parts.hpp"

namespace partc::scene {

namespace {

// Builtin variables every set has: any effect reads them.
bool builtin_var(const std::string& name) { return name == "p" || name == "id" || name == "alive"; }

// The particle variables an expression reads (x[i], x[j]).
void collect_reads(const ast::Chain& chain, std::vector<const ast::Indexed*>& out);
struct ReadsOf {
  std::vector<const ast::Indexed*>& out;
  void operator()(const ast::Indexed& n) const { out.push_back(&n); }
  void operator()(const ast::Chain& n) const { collect_reads(n, out); }
  void operator()(const ast::Unary& n) const { boost::apply_visitor(*this, n.operand); }
  void operator()(const ast::Norm& n) const { collect_reads(n.inner, out); }
  void operator()(const ast::Postfix& n) const { boost::apply_visitor(*this, n.base); }
  void operator()(const ast::Call& n) const {
    for (const ast::Argument& a : n.args)
      if (auto chain = boost::get<ast::Chain>(&a)) collect_reads(*chain, out);
  }
  template <class T>
  void operator()(const ast::x3::forward_ast<T>& n) const {
    (*this)(n.get());
  }
  template <class T>
  void operator()(const T&) const {}
};
void collect_reads(const ast::Chain& chain, std::vector<const ast::Indexed*>& out) {
  boost::apply_visitor(ReadsOf{out}, chain.first);
  for (const ast::BinaryOp& op : chain.rest) boost::apply_visitor(ReadsOf{out}, op.rhs);
}

bool additive(const std::string& op) { return op == "+=" || op == "-="; }

struct Checker {
  const std::vector<Instance>& instances;
  const ast::Program& scene;
  const SourceFile& file;
  std::vector<Diagnostic> problems;
  Owners owners;

  void error(Location at, std::string message, std::string note = {}) {
    problems.push_back({at, std::move(message), std::move(note)});
  }
  std::string where(Location loc) const { return file.line_reference(loc.begin); }

  void collect_owners() {
    for (const ast::Declaration& decl : scene.declarations)
      if (auto set = boost::get<ast::ParticlesDecl>(&decl))
        for (const ast::VarDecl& var : set->vars)
          owners[{set->name.name, var.name.name}] = {var.type.name, false, nullptr, var.loc};
    for (const Instance& inst : instances)
      for (const ast::EffectItem& item : inst.effect().items) {
        const std::string& set = inst.home();
        if (auto owns = boost::get<ast::OwnsItem>(&item)) {
          own(inst, set, inst.var(owns->name.name), owns->type.name, owns->channel, owns->loc);
        } else if (auto provides = boost::get<ast::ProvidesItem>(&item)) {
          // An observable is the scene's: keyed by no set.
          own(inst, "", provides->name.name, provides->type.name, false, provides->loc);
        }
      }
  }
  void own(const Instance& inst, const std::string& set, const std::string& var,
           const std::string& type, bool channel, Location loc) {
    if (builtin_var(var) && !set.empty())
      return error(loc, "effect " + inst.name + " declares " + var + ", which every set has",
                   "read it without declaring it; write p with: sets p: vec");
    auto [it, fresh] = owners.insert({{set, var}, {type, channel, &inst, loc}});
    if (fresh) return;
    const Owner& first = it->second;
    const std::string what = set.empty() ? "observable " + var : var + " on " + set;
    error(loc,
          "effect " + inst.name + " and " +
              (first.instance ? "effect " + first.instance->name : std::string("the scene")) +
              " both own " + what,
          "the other is at " + where(first.loc) +
              ": one owns it, the other declares reads, sets or contributes");
  }

  // The owner an access names, checked for type; null when there is none.
  const Owner* owner_of(const Instance& inst, const ast::AccessItem& access) {
    const std::string& var = access.name.name;
    if (builtin_var(var)) {
      if (access.kind != "sets" || var != "p")
        error(access.loc, var + " is a builtin variable of every set",
              "effects read p, id and alive without declaring them; only sets p is declared");
      return nullptr;
    }
    const Owner* found = nullptr;
    for (const std::string& set : inst.actual_sets)
      if (auto it = owners.find({set, var}); it != owners.end()) found = &it->second;
    if (auto it = owners.find({"", var}); !found && it != owners.end()) found = &it->second;
    if (!found) {
      error(access.loc,
            "effect " + inst.name + " " + access.kind + " " + var +
                ", which nothing in the scene owns",
            access.kind == "contributes"
                ? "a channel is owned by an effect (owns " + var + ": " + access.type.name +
                      " = 0 channel, usually the integrator's) or declared in the set"
                : "declare it in particles " + inst.home() + " { " + var + ": " + access.type.name +
                      " = ... }, or use an effect that owns it");
      return nullptr;
    }
    if (found->type != access.type.name)
      error(access.type.loc,
            "effect " + inst.name + " takes " + var + " as " + access.type.name + ", but it is " +
                found->type,
            "declared at " + where(found->loc));
    return found;
  }

  void check_instance(const Instance& inst, const std::vector<std::string>& slots) {
    std::map<std::string, std::string> access;  // var -> owns/reads/sets/contributes
    for (const ast::EffectItem& item : inst.effect().items) {
      if (auto owns = boost::get<ast::OwnsItem>(&item)) access[owns->name.name] = "owns";
      if (auto provides = boost::get<ast::ProvidesItem>(&item))
        access[provides->name.name] = "owns";
      if (auto a = boost::get<ast::AccessItem>(&item)) {
        owner_of(inst, *a);
        access[a->name.name] = a->kind;
      }
    }
    std::set<std::string> missing;  // slots reported, once each
    for (const ast::EffectItem& item : inst.effect().items) {
      auto at = boost::get<ast::AtItem>(&item);
      if (!at) continue;
      if (std::find(slots.begin(), slots.end(), at->slot.name) == slots.end() &&
          missing.insert(at->slot.name).second) {
        std::string list;
        for (const std::string& s : slots) list += (list.empty() ? "" : ", ") + s;
        error(at->slot.loc,
              "effect " + inst.name + " acts at slot " + at->slot.name + ", which " +
                  (slots.empty() ? "no integrator on " + inst.home() + " declares"
                                 : "the integrator on " + inst.home() + " does not have"),
              slots.empty()
                  ? "use an integrator on " + inst.home() + ", such as integrate.velocity_verlet"
                  : "its slots are " + list);
      }
      const ast::Assignment& st = at->statement;
      const std::string& target = st.target.var.name;
      auto it = access.find(target);
      const std::string how = it == access.end() ? "" : it->second;
      if (target == "p" && how != "sets")
        error(st.target.loc, "effect " + inst.name + " moves particles without saying so",
              "declare it: sets p: vec");
      else if (target != "p" && how.empty())
        error(
            st.target.loc,
            "effect " + inst.name + " writes " + target + ", which its interface does not declare",
            "declare it: owns, sets or contributes " + target);
      else if (how == "reads")
        error(st.target.loc, "effect " + inst.name + " writes " + target + ", which it only reads",
              "declare it: sets " + target + " (or contributes, for +=)");
      else if (how == "contributes" && !additive(st.op))
        error(st.target.loc,
              "effect " + inst.name + " contributes to " + target + " but writes it with " + st.op,
              "a contribution is += or -=; a writer that replaces the value declares: sets " +
                  target);
      std::vector<const ast::Indexed*> reads;
      collect_reads(st.value, reads);
      for (const ast::Indexed* read : reads) {
        const std::string& var = read->var.name;
        if (builtin_var(var)) continue;
        auto found = access.find(var);
        if (found == access.end())
          error(read->var.loc,
                "effect " + inst.name + " reads " + var + ", which its interface does not declare",
                "declare it: reads " + var + ": TYPE");
        else if (found->second == "contributes")
          error(read->var.loc,
                "effect " + inst.name + " reads " + var + ", which it only contributes to",
                "a channel's value is its owner's to read: declare reads " + var +
                    " to read the previous value");
      }
    }
  }

  // Two writers of one variable at one slot conflict unless both add, or
  // an order names both.
  void check_writers(const std::vector<std::string>& order) {
    struct Writer {
      const Instance* inst;
      const ast::Assignment* st;
    };
    std::map<std::tuple<std::string, std::string, std::string>, std::vector<Writer>> writers;
    for (const Instance& inst : instances)
      for (const ast::EffectItem& item : inst.effect().items)
        if (auto at = boost::get<ast::AtItem>(&item))
          writers[{inst.home(), at->slot.name, inst.var(at->statement.target.var.name)}].push_back(
              {&inst, &at->statement});
    auto ordered = [&](const Instance* a, const Instance* b) {
      return std::count(order.begin(), order.end(), a->name) &&
             std::count(order.begin(), order.end(), b->name);
    };
    for (const auto& [key, list] : writers)
      for (std::size_t a = 0; a < list.size(); ++a)
        for (std::size_t b = a + 1; b < list.size(); ++b) {
          const Writer& x = list[a];
          const Writer& y = list[b];
          if (x.inst == y.inst || (additive(x.st->op) && additive(y.st->op)) ||
              ordered(x.inst, y.inst))
            continue;
          const std::string& var = std::get<2>(key);
          const bool mixed = additive(x.st->op) != additive(y.st->op);
          error(y.st->loc,
                "effects " + x.inst->name + " and " + y.inst->name + " both write " + var +
                    " at slot " + std::get<1>(key) +
                    (mixed ? ", one replacing what the other adds to" : ""),
                x.inst->name + "'s is at " + where(x.st->loc) +
                    "; if the order is what you mean, say it: order " + x.inst->name + ", " +
                    y.inst->name);
        }
  }
};

}  // namespace

bool Instance::integrator() const {
  for (const ast::EffectItem& item : effect().items)
    if (auto slots = boost::get<ast::SlotsItem>(&item); slots && slots->kind == "slots")
      return true;
  return false;
}

std::vector<std::string> Instance::slots(const char* kind) const {
  std::vector<std::string> out;
  for (const ast::EffectItem& item : effect().items)
    if (auto slots = boost::get<ast::SlotsItem>(&item); slots && slots->kind == kind)
      for (const ast::Identifier& name : slots->names) out.push_back(name.name);
  return out;
}

std::map<std::string, const Instance*> integrators(const std::vector<Instance>& instances) {
  std::map<std::string, const Instance*> out;
  for (const Instance& inst : instances)
    if (inst.integrator()) out.emplace(inst.home(), &inst);
  return out;
}

Owners check_interfaces(const std::vector<Instance>& instances, const ast::Program& scene,
                        const SourceFile& file) {
  Checker c{instances, scene, file, {}, {}};
  // Two integrators on a set make every other conflict on it a consequence: alone.
  std::map<std::string, const Instance*> integrator;
  for (const Instance& inst : instances) {
    if (!inst.integrator()) continue;
    auto [it, fresh] = integrator.insert({inst.home(), &inst});
    if (!fresh)
      c.error(inst.use->loc,
              "two integrators on " + inst.home() + ": " + it->second->name + " and " + inst.name,
              it->second->name + " is used at " + c.where(it->second->use->loc) +
                  "; a set is stepped by one integrator");
    const std::vector<std::string> slots = inst.slots("slots");
    for (const std::string& primed : inst.slots("prime"))
      if (std::find(slots.begin(), slots.end(), primed) == slots.end())
        c.error(inst.effect().loc, "effect " + inst.name + " primes slot " + primed +
                                       ", which is not one of its slots");
  }
  if (!c.problems.empty()) throw CompileError(c.problems);
  c.collect_owners();
  std::vector<std::string> order;
  for (const ast::Declaration& decl : scene.declarations)
    if (auto o = boost::get<ast::OrderDecl>(&decl))
      for (const ast::Identifier& name : o->instances) {
        const bool known = std::any_of(instances.begin(), instances.end(),
                                       [&](const Instance& i) { return i.name == name.name; });
        if (!known)
          c.error(name.loc, "order names " + name.name + ", which no use line instantiates",
                  "an order lists effect instances: their names, or the names given with as");
        order.push_back(name.name);
      }
  for (const Instance& inst : instances) {
    auto it = integrator.find(inst.home());
    c.check_instance(
        inst, it == integrator.end() ? std::vector<std::string>{} : it->second->slots("slots"));
  }
  c.check_writers(order);
  if (!c.problems.empty()) throw CompileError(c.problems);
  return c.owners;
}

std::string mangled(const std::string& qualified) {
  std::string out = qualified;
  std::replace(out.begin(), out.end(), '.', '_');
  return out;
}

}  // namespace partc::scene
