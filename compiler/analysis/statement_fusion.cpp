// Fusion across statements: consecutive statements of the step over one set
// whose neighbour sums one search serves share one pass, so their sums come
// from one walk of the pairs. LJ's force and, when a scene outputs e_lj, its
// per-particle energy at the same slot are the case this is for: two walks
// of the same pairs become one.
//
// A later member may be moved up to the pass past statements it commutes
// with (neither reads what the other writes): LJ's energy, then the force
// of every pair effect, then Coulomb's energy, with the energy observables
// between them, are one pass.
//
// It runs after the search plan and the symmetry analysis, whose facts
// decide: one walk needs one search (one group, built once in the stretch)
// or one set of Verlet lists, and one way of taking the pairs (each pair
// once, or both ways). The pass interleaves its members particle by
// particle, so it is legal only when no member reads what another writes
// (at j it would see some particles' new values and some old ones; at i,
// an earlier member's buffered value not yet swapped in). Candidates it
// refuses stay ordered passes and are reported; none is merged unproven.
#include "analysis/statement_fusion.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <set>

#include "ir/visitor.hpp"

namespace partc {

namespace {

using ir::Statement;

struct ReadsVar : ir::Visitor {
  int set, var;
  bool found = false;
  ReadsVar(int s, int v) : set(s), var(v) {}
  using Visitor::visit;
  void visit(const ir::VarRef& n) override { found = found || (n.set == set && n.var == var); }
};

bool reads(const Statement& st, int set, int var) {
  ReadsVar r(set, var);
  r.visit(st.value);
  r.visit(st.solve_operator);
  return r.found;
}

struct ReadsObservable : ir::Visitor {
  int observable;
  bool found = false;
  explicit ReadsObservable(int o) : observable(o) {}
  using Visitor::visit;
  void visit(const ir::ObservableRef& n) override { found = found || n.observable == observable; }
};

bool reads_observable(const Statement& st, int observable) {
  ReadsObservable r(observable);
  r.visit(st.value);
  r.visit(st.solve_operator);
  return r.found;
}

class Fuser {
 public:
  Fuser(const ir::Model& m, const NeighbourhoodReport& n, const PairSymmetryReport& s,
        const SearchPlan& p, const ObservedStepReport& o, const SourceFile& file, bool enabled)
      : m_(m),
        neighbourhoods_(n),
        symmetry_(s),
        plan_(p),
        observed_(o),
        file_(file),
        enabled_(enabled) {}

  StatementFusion run() {
    // The step's statements in the order step() runs them.
    std::vector<StatementPosition> order;
    for (int g = 0; g < static_cast<int>(m_.stages.size()); ++g)
      if (m_.stages[g].kind == ir::StageKind::Step)
        for (int k = 0; k < static_cast<int>(m_.stages[g].statements.size()); ++k)
          order.push_back({g, k});
    for (std::size_t n = 1; n < order.size(); ++n) {
      const StatementPosition b = order[n];
      if (!candidate(at(b))) continue;
      // The nearest earlier statement over b's set that walks, if b can be
      // moved up to it: past statements that neither read nor write what b
      // does (an observable summing another effect's energy, a kick of
      // another set), which then run after the pass instead of before it.
      auto shares = [&](std::size_t k) {
        return candidate(at(order[k])) && at(order[k]).set == at(b).set;
      };
      std::size_t back = n;
      while (back > 0 && !shares(back - 1) && commute(order[back - 1], b)) --back;
      if (back == 0 || !shares(back - 1)) continue;  // nothing b could share a walk with
      const StatementPosition a = order[back - 1];
      // b joins a's pass only if it may share it with every member.
      auto pass = out_.pass_of.find(a);
      std::string why_not;
      if (pass == out_.pass_of.end())
        why_not = refusal(a, b);
      else
        for (StatementPosition member : out_.passes[pass->second].statements)
          if (why_not.empty()) why_not = refusal(member, b);
      if (!why_not.empty()) {
        out_.refused.push_back({a, b, why_not});
        continue;
      }
      if (pass == out_.pass_of.end()) {
        out_.passes.push_back({{a}, shared_walk(a)});
        pass = out_.pass_of.emplace(a, static_cast<int>(out_.passes.size()) - 1).first;
      }
      out_.passes[pass->second].statements.push_back(b);
      out_.pass_of[b] = pass->second;
    }
    for (FusedPass& pass : out_.passes) {
      std::vector<std::string> members, every_step;
      for (StatementPosition p : pass.statements) {
        members.push_back(named(at(p)));
        const auto fact = observed_.find(p);
        if (fact == observed_.end() || !fact->second.observed_only)
          every_step.push_back(members.back());
      }
      pass.reason = fmt::format("{}: one pass over {}, {}", fmt::join(members, "; "),
                                m_.sets[at(pass.statements.front()).set].name, pass.reason);
      if (!every_step.empty() && every_step.size() < members.size())
        pass.reason +=
            fmt::format("; on steps not observed, {} alone", fmt::join(every_step, "; "));
    }
    return out_;
  }

 private:
  const Statement& at(StatementPosition p) const { return m_.stages[p.first].statements[p.second]; }

  // Its neighbour sums (the Accumulate ids): what a walk serves.
  std::vector<int> neighbour_sums(const Statement& st) const {
    std::vector<int> ids;
    for (const ir::Accumulate* acc : ir::accumulations_in(st))
      if (neighbourhoods_.at(acc->id).kind == SearchFact::Kind::Neighbours) ids.push_back(acc->id);
    return ids;
  }
  bool walks(const Statement& st) const { return !neighbour_sums(st).empty(); }
  bool candidate(const Statement& st) const { return st.observable < 0 && walks(st); }

  // Whether b may run before c instead of after it: neither reads what the
  // other writes, they write different things, and c moves no particle (a
  // neighbour sum reads positions through dx).
  bool commute(StatementPosition pc, StatementPosition pb) const {
    const Statement& c = at(pc);
    const Statement& b = at(pb);
    if (in_loop(pc)) return false;
    if (c.observable >= 0) return !reads_observable(b, c.observable) && !reads(c, b.set, b.var);
    return c.var != ir::kPosition && c.var != ir::kAlive && !(c.set == b.set && c.var == b.var) &&
           !reads(b, c.set, c.var) && !reads(c, b.set, b.var);
  }

  // As the code generator decides (ModelEmitter::newton_pairs).
  bool pairs_once(const Statement& st) const {
    if (st.schedule.compensated) return false;
    const std::vector<int> sums = neighbour_sums(st);
    return std::all_of(sums.begin(), sums.end(), [&](int id) { return symmetry_.at(id).newton; });
  }

  std::string text(const Location& loc) const { return std::string(file_.slice(loc)); }

  // "f[i] of lj, coulomb_cut", or "u[i] (md.part:12)" for the scene's own.
  std::string named(const Statement& st) const {
    if (st.origins.empty())
      return fmt::format("{} ({})", ir::target_name(m_, st), file_.line_reference(st.loc.begin));
    std::vector<std::string> effects;
    for (const ir::Origin& o : st.origins)
      if (std::find(effects.begin(), effects.end(), o.effect) == effects.end())
        effects.push_back(o.effect);
    return fmt::format("{} of {}", ir::target_name(m_, st), fmt::join(effects, ", "));
  }

  bool in_loop(StatementPosition p) const { return m_.stages[p.first].in_loop(p.second); }

  // Why a's pass may not take b too; "" when it may.
  std::string refusal(StatementPosition pa, StatementPosition pb) const {
    const Statement& a = at(pa);
    const Statement& b = at(pb);
    const std::string both = named(a) + " and " + named(b);
    if (!enabled_) return both + ": statement fusion is off (--no-fuse)";
    if (in_loop(pa) || in_loop(pb)) return both + ": an iterate block runs its statements alone";
    for (const Statement* st : {&a, &b})
      if (st->var == ir::kPosition || st->var == ir::kAlive || st->solve_operator)
        return named(*st) + " moves, removes or solves: a pass of its own";
    if (a.var == b.var) return both + " write the same variable";
    if (reads(b, a.set, a.var))
      return fmt::format("{} reads {}, which {} writes in the same pass", named(b),
                         m_.sets[a.set].vars[a.var].name, named(a));
    if (reads(a, b.set, b.var))
      return fmt::format("{} reads {}, which {} writes in the same pass", named(a),
                         m_.sets[b.set].vars[b.var].name, named(b));
    if (a.schedule.compensated != b.schedule.compensated)
      return both + ": one sums compensated, the other not";
    if (a.schedule.arithmetic != b.schedule.arithmetic)  // one vector loop has one lane type
      return both + ": one computes its pair terms in float, the other in double";
    if (pairs_once(a) != pairs_once(b))
      return both + ": one takes each pair once, the other both ways (one walk cannot do both)";
    if (static_cast<bool>(a.schedule.skin) != static_cast<bool>(b.schedule.skin) ||
        (a.schedule.skin && text(a.schedule.skin->loc) != text(b.schedule.skin->loc)))
      return both + ": their Verlet lists differ";
    if (!a.schedule.skin) {
      std::set<int> groups;
      for (const Statement* st : {&a, &b})
        for (int id : neighbour_sums(*st)) groups.insert(plan_.group_of.at(id));
      const std::vector<int>& linked = plan_.groups[*groups.begin()].chosen_at_run_time;
      if (groups.size() > 1 &&
          std::includes(linked.begin(), linked.end(), groups.begin(), groups.end()))
        return both +
               ": which searches their sums walk is chosen at run time (search plan), and "
               "one pass walks one search";
      if (groups.size() > 1) return both + ": their sums have searches of their own (search plan)";
    }
    return "";
  }

  std::string shared_walk(StatementPosition p) const {
    const Statement& st = at(p);
    if (st.schedule.skin)
      return "one walk of the Verlet lists with skin " + text(st.schedule.skin->loc);
    const int group = plan_.group_of.at(neighbour_sums(st).front());
    return fmt::format("one walk of search {}", plan_.groups[group].search + 1);
  }

  const ir::Model& m_;
  const NeighbourhoodReport& neighbourhoods_;
  const PairSymmetryReport& symmetry_;
  const SearchPlan& plan_;
  const ObservedStepReport& observed_;
  const SourceFile& file_;
  const bool enabled_;
  StatementFusion out_;
};

}  // namespace

StatementFusion fuse_statements(const ir::Model& model, const NeighbourhoodReport& neighbourhoods,
                                const PairSymmetryReport& symmetry, const SearchPlan& searches,
                                const ObservedStepReport& observed, const SourceFile& file,
                                bool enabled) {
  return Fuser(model, neighbourhoods, symmetry, searches, observed, file, enabled).run();
}

}  // namespace partc
