// Plans the neighbour searches of a model: which sums share one search, at
// which radius it is built, and which search may reorder its set.
//
// It runs after the neighbourhood analysis (which sums search, at what
// radius) and after the schedule checks (a statement's forced structure and
// sharing are valid), and only reads the IR; the code generator follows it.
//
// A search serves the sums over its set between two position changes of the
// set (a stretch: a statement writing p or alive starts the next one; the
// step stage wraps around, its last stretch going on into its first). Built
// at the largest radius of the stretch's sums, it is built once there, where
// per-statement radii rebuilt it at each change of radius. Sums whose radii
// differ a lot get searches of their own when one walk at the largest
// radius costs more than a second build (share_candidate_growth). When the
// ratio of two radii is known only at run time (two params), each gets a
// group and a search, and the generated code makes the same choice with the
// run's radii (SearchGroup::chosen_at_run_time): a search is built only if
// some group walks it, so still at most once per position change. Sums of
// one statement share its search whatever their radii: their loops are one
// walk. The plan is about speed only: the generated code still rebuilds
// whenever the set has changed or the radius a search is asked differs from
// its build's.
#include "analysis/search_plan.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <tuple>

#include "ir/constant.hpp"
#include "ir/printer.hpp"
#include "ir/visitor.hpp"

namespace partc {

namespace {

struct Consumer {
  int sum;                        // Accumulate id
  std::pair<int, int> statement;  // (stage, statement)
  double factor;                  // the radius is factor * rest
  std::string rest;               // in the IR's names; "" for a constant radius
  std::string radius_text;        // as written, for people (unless ambiguous: see below)
  ir::Sharing sharing;
  int line;
};

// Stretch ids per set: stretches[(stage, statement)][set].
std::map<std::pair<int, int>, std::vector<int>> find_stretches(const ir::Model& model) {
  std::map<std::pair<int, int>, std::vector<int>> out;
  const int sets = static_cast<int>(model.sets.size());
  std::vector<int> next(sets, 0);
  // The stages that run one after another: all init blocks, all step blocks,
  // and the blocks of each named stage.
  std::vector<std::pair<ir::StageKind, std::string>> sequences;
  for (const ir::Stage& stage : model.stages)
    if (std::find(sequences.begin(), sequences.end(), std::make_pair(stage.kind, stage.name)) ==
        sequences.end())
      sequences.push_back({stage.kind, stage.name});
  for (const auto& [kind, name] : sequences) {
    std::vector<int> current(sets), first(sets);
    std::vector<bool> moved(sets, false);
    for (int s = 0; s < sets; ++s) first[s] = current[s] = next[s]++;
    for (std::size_t g = 0; g < model.stages.size(); ++g) {
      const ir::Stage& stage = model.stages[g];
      if (stage.kind != kind || stage.name != name) continue;
      for (std::size_t k = 0; k < stage.statements.size(); ++k) {
        const ir::Statement& st = stage.statements[k];
        out[{static_cast<int>(g), static_cast<int>(k)}] = current;
        if (st.observable < 0 && (st.var == ir::kPosition || st.var == ir::kAlive)) {
          current[st.set] = next[st.set]++;
          moved[st.set] = true;
        }
      }
    }
    if (kind != ir::StageKind::Step) continue;
    // The next step's first statements see the positions its last ones saw.
    for (auto& [position, ids] : out)
      for (int s = 0; s < sets; ++s)
        if (moved[s] && ids[s] == first[s]) ids[s] = current[s];
  }
  return out;
}

// A radius as factor * rest, rest in the IR's names ("" when the radius is
// a constant): radii with the same rest compare by their factors even when
// rest is known only at run time (2 * h against h: a ratio of 2). Not the
// text as written: two effects' `rc * rc` are lj.rc and coulomb.rc.
std::pair<double, std::string> scaled(const ir::Expr& e, const ir::Model& model,
                                      const std::vector<ir::Label>& labels) {
  if (const std::optional<double> value = evaluate_constant(e, model)) return {*value, ""};
  if (const auto* b = ir::as<ir::Binary>(e)) {
    const std::optional<double> left = evaluate_constant(b->lhs, model),
                                right = evaluate_constant(b->rhs, model);
    if (b->op == ir::BinaryOp::Mul && (left || right)) {
      auto [factor, rest] = scaled(left ? b->rhs : b->lhs, model, labels);
      return {factor * (left ? *left : *right), rest};
    }
    if (b->op == ir::BinaryOp::Div && right) {
      auto [factor, rest] = scaled(b->lhs, model, labels);
      return {factor / *right, rest};
    }
  }
  return {1.0, ir::to_string(e, model, labels)};
}

std::string growth_text(double ratio, int dim) {
  return fmt::format("{:.3g}^{} = {:.3g}", ratio, dim, std::pow(ratio, dim));
}

// A stretch's groups whose leaders' radii do not all compare here (their
// rests differ) leave the choice to the run: the groups the schedule does not
// keep apart (sharing = separate) are linked, each to all, and say the rule.
// `first` is the index the stretch's first group will have in the plan.
void choose_at_run_time(std::vector<SearchGroup>& groups,
                        const std::vector<const Consumer*>& leaders, int first, int dim) {
  std::vector<int> linked;
  std::vector<std::string> rests;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    if (leaders[k]->sharing == ir::Sharing::Separate) continue;
    linked.push_back(first + static_cast<int>(k));
    if (std::find(rests.begin(), rests.end(), leaders[k]->rest) == rests.end())
      rests.push_back(leaders[k]->rest);
  }
  if (rests.size() < 2) return;
  std::vector<std::string> radii;
  for (int index : linked) {
    const SearchGroup& group = groups[index - first];
    radii.push_back(group.radii.size() > 1 ? fmt::format("max({})", fmt::join(group.radii, ", "))
                                           : group.radii.front());
  }
  for (std::size_t k = 0; k < linked.size(); ++k) {
    SearchGroup& group = groups[linked[k] - first];
    group.chosen_at_run_time = linked;
    group.reason += (group.reason.empty() ? "" : "; ") +
                    fmt::format(
                        "chosen at run time, as the ratios of {} are known only there: with M "
                        "the largest, these sums walk the search at M while (M / {})^{} <= {}, "
                        "else this search of their own (tests/bench/bench_two_cutoffs)",
                        fmt::join(radii, ", "), radii[k], dim, share_candidate_growth);
  }
}

}  // namespace

SearchPlan plan_searches(const ir::Model& model, const NeighbourhoodReport& neighbourhoods,
                         const std::string& source) {
  const auto stretches = find_stretches(model);
  // (set, structure, stretch) -> its consumers, in statement order.
  std::map<std::tuple<int, ir::SearchChoice, int>, std::vector<Consumer>> buckets;
  std::vector<bool> listed(model.sets.size(), false);
  for (std::size_t g = 0; g < model.stages.size(); ++g)
    for (std::size_t k = 0; k < model.stages[g].statements.size(); ++k) {
      const ir::Statement& st = model.stages[g].statements[k];
      const std::pair<int, int> at{static_cast<int>(g), static_cast<int>(k)};
      for (const ir::Accumulate* acc : ir::accumulations_in(st)) {
        const SearchFact& fact = neighbourhoods.at(acc->id);
        if (fact.kind != SearchFact::Kind::Neighbours) continue;
        if (st.schedule.skin) {
          listed[st.set] = true;
          continue;
        }
        const int set = st.labels[acc->label].set;
        const Location loc = fact.radius->loc;
        const auto [factor, rest] = scaled(fact.radius, model, st.labels);
        buckets[{set, st.schedule.search, stretches.at(at)[set]}].push_back(
            {acc->id, at, factor, rest, source.substr(loc.begin, loc.end - loc.begin),
             st.schedule.sharing, st.line});
      }
    }

  SearchPlan plan;
  std::map<std::tuple<int, ir::SearchChoice, int>, int> search_of;  // (set, structure, slot)
  for (auto& [key, consumers] : buckets) {
    const auto [set, structure, stretch] = key;
    // Radii written alike that differ (two modules' `rc * rc`) are named
    // as the IR names them in what people read.
    std::set<std::string> ambiguous;
    for (const Consumer& c : consumers)
      for (const Consumer& other : consumers)
        if (other.radius_text == c.radius_text && (other.rest != c.rest || other.factor != c.factor))
          ambiguous.insert(c.radius_text);
    for (Consumer& c : consumers)
      if (ambiguous.count(c.radius_text))
        c.radius_text = c.rest.empty() ? fmt::format("{:g}", c.factor)
                        : c.factor == 1 ? c.rest
                                        : fmt::format("{:g} * {}", c.factor, c.rest);
    // Largest radius first among those that compare (the same rest).
    std::stable_sort(consumers.begin(), consumers.end(), [](const Consumer& a, const Consumer& b) {
      return a.rest != b.rest ? a.rest < b.rest : a.factor > b.factor;
    });
    std::vector<SearchGroup> groups;
    std::vector<const Consumer*> leaders;
    for (const Consumer& c : consumers) {
      std::string why;
      std::size_t joined = 0;
      for (; joined < groups.size(); ++joined) {
        const Consumer& leader = *leaders[joined];
        if (leader.sharing == ir::Sharing::Separate) {
          if (model.stages[leader.statement.first].statements[leader.statement.second].loc.begin ==
              model.stages[c.statement.first].statements[c.statement.second].loc.begin)
            break;  // the sums of one statement scheduled apart share its search
          continue;
        }
        if (c.sharing == ir::Sharing::Separate) continue;
        if (c.rest == leader.rest && c.factor == leader.factor) break;  // the same radius
        const auto& mine = groups[joined].statements;
        if (std::find(mine.begin(), mine.end(), c.statement) != mine.end()) {
          why = fmt::format(
              "line {}'s radius {} joins {}: a sum of the same statement walks this search, and "
              "one walk serves both",
              c.line, c.radius_text, leader.radius_text);
          break;
        }
        if (c.sharing == ir::Sharing::Shared || leader.sharing == ir::Sharing::Shared) {
          why = fmt::format("line {}'s radius {} joins {}: the schedule says sharing = shared",
                            c.line, c.radius_text, leader.radius_text);
          break;
        }
        if (c.rest != leader.rest) continue;  // their ratio is known only at run time: decided there
        const double ratio = leader.factor / c.factor;
        if (std::pow(ratio, model.dim) <= share_candidate_growth) {
          why = fmt::format(
              "line {}'s radius {} joins {}: its candidates grow {} <= {}, cheaper than a "
              "second build (tests/bench/bench_two_cutoffs)",
              c.line, c.radius_text, leader.radius_text, growth_text(ratio, model.dim),
              share_candidate_growth);
          break;
        }
        why = fmt::format(
            "apart from the search at {}: line {}'s candidates would grow {} > {}, dearer than "
            "a second build (tests/bench/bench_two_cutoffs)",
            leader.radius_text, c.line, growth_text(ratio, model.dim), share_candidate_growth);
      }
      if (joined == groups.size()) {
        groups.push_back({});
        leaders.push_back(&c);
        if (c.sharing == ir::Sharing::Separate)
          why = fmt::format(
              "line {}'s sums have a search of their own: the schedule says "
              "sharing = separate",
              c.line);
      }
      SearchGroup& group = groups[joined];
      group.sums.push_back(c.sum);
      group.statements.push_back(c.statement);
      if (!why.empty()) group.reason += (group.reason.empty() ? "" : "; ") + why;
      if (std::find(group.radii.begin(), group.radii.end(), c.radius_text) == group.radii.end())
        group.radii.push_back(c.radius_text);
    }
    choose_at_run_time(groups, leaders, static_cast<int>(plan.groups.size()), model.dim);
    for (std::size_t slot = 0; slot < groups.size(); ++slot) {
      SearchGroup& group = groups[slot];
      auto [it, fresh] = search_of.emplace(std::make_tuple(set, structure, static_cast<int>(slot)),
                                           static_cast<int>(plan.searches.size()));
      if (fresh) plan.searches.push_back({set, structure, false, ""});
      group.search = it->second;
      group.stretch = stretch;
      if (group.reason.empty())
        group.reason = group.sums.size() == 1 ? "the only sum searched this way here"
                                              : "every sum asks the same radius";
      for (int sum : group.sums) plan.group_of[sum] = static_cast<int>(plan.groups.size());
      plan.groups.push_back(std::move(group));
    }
  }

  // Who owns each set's order.
  for (std::size_t s = 0; s < model.sets.size(); ++s) {
    bool first = true;
    for (PlannedSearch& search : plan.searches) {
      if (search.set != static_cast<int>(s)) continue;
      search.reorders = first && !listed[s];
      search.order_reason =
          listed[s] ? "keeps the set's order: its Verlet lists own it (a reorder would move "
                      "every particle's slot and so rebuild them)"
          : first   ? "reorders the set (its first search): queries then walk memory in order"
                    : "keeps the set's order, which its first search owns (a reorder would make "
                      "that one rebuild), and is built after it";
      first = false;
    }
  }
  for (SearchGroup& group : plan.groups) {
    const PlannedSearch& mine = plan.searches[group.search];
    if (mine.reorders) continue;
    for (std::size_t other = 0; other < plan.groups.size(); ++other) {
      const PlannedSearch& theirs = plan.searches[plan.groups[other].search];
      if (theirs.set == mine.set && theirs.reorders && plan.groups[other].stretch == group.stretch)
        group.built_after = static_cast<int>(other);
    }
  }
  return plan;
}

}  // namespace partc
