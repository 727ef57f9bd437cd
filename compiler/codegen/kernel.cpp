// Emits the kernels of a model's class: one private function per statement
// (or per fused pass of several, analysis/statement_fusion.cpp), one pass
// over its particle set. Before the pass, the searches and Verlet
// lists it needs are brought up to date (a rebuild may reorder the set) and
// sums that obey Newton's third law walk each pair once; in the pass, each
// particle sums its partners (or reads the pair walk's totals) and updates
// its own value, in place or through a buffer as the aliasing analysis
// decided. Accumulations over the same set found the same way share a loop.
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "codegen/model_emitter.hpp"
#include "ir/constant.hpp"
#include "ir/relabel.hpp"
#include "ir/terms.hpp"
#include "support/diagnostics.hpp"

namespace partc::codegen {

// A kernel's name: its stage's, then its target's.
std::string ModelEmitter::target(const Statement& st) const {
  return st.observable >= 0 ? m_.observables[st.observable].name
                            : (m_.sets.size() > 1 ? m_.sets[st.set].name + "_" : "") +
                                  m_.sets[st.set].vars[st.var].name;
}

bool ModelEmitter::observed_only(std::pair<int, int> position) const {
  const auto fact = facts_.observed_steps.find(position);
  return fact != facts_.observed_steps.end() && fact->second.observed_only;
}

// The kernel of a fused pass's members (positions, in order), at the
// first's position: one label table, the first member's then each later's.
ModelEmitter::Kernel ModelEmitter::pass_kernel(const std::vector<std::pair<int, int>>& positions,
                                               const std::string& stage_name, int pass) {
  const auto [g, k] = positions.front();
  const Statement& first = m_.stages[g].statements[k];
  Statement lead = first;
  std::vector<Statement> members;
  std::string name = stage_name + "_" + target(first);
  for (std::size_t n = 1; n < positions.size(); ++n) {
    const auto [mg, mk] = positions[n];
    Statement member = m_.stages[mg].statements[mk];
    member.value = append_labels(member.value, static_cast<int>(lead.labels.size()));
    lead.labels.insert(lead.labels.end(), member.labels.begin() + 1, member.labels.end());
    members.push_back(std::move(member));
    name += "_" + target(members.back());
  }
  Kernel kernel{members_.fresh(name), nullptr, &facts_.aliasing[g][k], positions.front()};
  kernel.pass = pass;
  for (std::size_t n = 0; n < members.size(); ++n) {
    members[n].labels = lead.labels;
    variants_.push_back(std::move(members[n]));
    const auto [mg, mk] = positions[n + 1];
    if (lists_.count(&m_.stages[mg].statements[mk]))
      lists_[&variants_.back()] = lists_.at(&m_.stages[mg].statements[mk]);
    kernel.fused.push_back({&variants_.back(), &facts_.aliasing[mg][mk]});
  }
  variants_.push_back(std::move(lead));
  if (lists_.count(&first)) lists_[&variants_.back()] = lists_.at(&first);
  kernel.st = &variants_.back();
  return kernel;
}

void ModelEmitter::plan_kernels() {
  if (!kernels_.empty()) return;
  for (std::size_t g = 0; g < m_.stages.size(); ++g) {
    const Stage& stage = m_.stages[g];
    for (std::size_t k = 0; k < stage.statements.size(); ++k) {
      const Statement& st = stage.statements[k];
      const std::pair<int, int> position{static_cast<int>(g), static_cast<int>(k)};
      const auto pass = facts_.fusion.pass_of.find(position);
      if (pass != facts_.fusion.pass_of.end() &&
          facts_.fusion.passes[pass->second].statements.front() != position)
        continue;  // a later member of a fused pass: computed in its first member's kernel
      const std::string stage_name = stage.kind == StageKind::Init   ? "init"
                                     : stage.kind == StageKind::Step ? "step"
                                                                     : stage.name;
      if (pass == facts_.fusion.pass_of.end()) {
        kernels_.push_back({members_.fresh(stage_name + "_" + target(st)), &st,
                            &facts_.aliasing[g][k], position});
        continue;
      }
      const std::vector<std::pair<int, int>>& all = facts_.fusion.passes[pass->second].statements;
      std::vector<std::pair<int, int>> every_step;
      for (const std::pair<int, int>& p : all)
        if (!observed_only(p)) every_step.push_back(p);
      Kernel whole = pass_kernel(all, stage_name, pass->second);
      if (every_step.empty() || every_step.size() == all.size()) {
        kernels_.push_back(std::move(whole));
        continue;
      }
      // Some members run only on observed steps: the whole pass then, and
      // the others alone (where the pass runs) on the steps not observed.
      whole.observed = 1;
      kernels_.push_back(std::move(whole));
      const auto [eg, ek] = every_step.front();
      Kernel rest = every_step.size() > 1
                        ? pass_kernel(every_step, stage_name, pass->second)
                        : Kernel{members_.fresh(stage_name + "_" + target(m_.stages[eg].statements[ek])),
                                 &m_.stages[eg].statements[ek], &facts_.aliasing[eg][ek], position};
      rest.position = position;
      rest.observed = 0;
      kernels_.push_back(std::move(rest));
    }
  }
  if (!options_.profile) return;
  // kernels_ grows with the variants: positions, not pointers, until it is whole.
  std::vector<std::size_t> step_kernels;
  for (std::size_t k = 0; k < kernels_.size(); ++k)
    if (m_.stages[kernels_[k].position.first].kind == StageKind::Step) step_kernels.push_back(k);
  for (std::size_t n = 0; n < step_kernels.size(); ++n) {
    kernels_[step_kernels[n]].profiled = static_cast<int>(n);
    plan_calibration(kernels_[step_kernels[n]]);
  }
  for (const Kernel& k : kernels_)
    if (k.profiled >= 0) profiled_.push_back(&k);
}

// A statement of several effects' terms (merged, or fused from several
// statements) is timed whole and without some of its origins' terms after the
// run (partc::Profile splits its time by their marginal costs). Not for
// observables or solves, or a statement whose variant would walk its pairs
// otherwise than it does (a term that breaks symmetry, dropped): the variant
// would time another walk.
void ModelEmitter::plan_calibration(const Kernel k) {
  const Statement& st = *k.st;
  // A fused pass's variants would have to leave out whole members: not yet.
  if (k.pass >= 0 || st.origins.size() < 2 || st.observable >= 0 || st.solve_operator) return;
  const std::vector<Statement::Without> parts = parts_without(st);
  if (parts.empty()) return;
  std::vector<Statement> statements{st};
  for (const Statement::Without& part : parts) {
    Statement variant = st;
    variant.value = part.value;
    variant.without.clear();
    variant.origins.clear();
    for (std::size_t o = 0; o < st.origins.size(); ++o)
      if (std::find(part.origins.begin(), part.origins.end(), o) == part.origins.end())
        variant.origins.push_back(st.origins[o]);
    if (walks_pairs(variant) && newton_pairs(variant) != newton_pairs(st)) return;
    statements.push_back(std::move(variant));
  }
  Calibration calibration{k.profiled, {}, {}, {}};
  const std::string sink = buffer_member(st.set, st.var, true);
  std::vector<Kernel> variants;
  for (std::size_t v = 0; v < statements.size(); ++v) {
    variants_.push_back(std::move(statements[v]));
    const Statement* variant = &variants_.back();
    if (lists_.count(&st)) lists_[variant] = lists_.at(&st);
    std::string suffix = "_whole";
    if (v > 0) {
      suffix = "_without";
      for (std::size_t o : parts[v - 1].origins) suffix += "_" + cpp_name(st.origins[o].effect);
      calibration.leaves_out.push_back(parts[v - 1].origins);
    }
    const std::string name = members_.fresh(k.name + suffix);
    variants.push_back({name, variant, k.alias, k.position, sink});
    if (v > 0) plan_calibration_searches(variants.back(), st, parts[v - 1].origins, calibration);
    calibration.variants.push_back(name);
  }
  kernels_.insert(kernels_.end(), variants.begin(), variants.end());
  calibrations_.push_back(std::move(calibration));
}

// The calls of every stage of one kind (of one name), in order; an iterate
// block's statements in a loop that ends when its condition holds, or stops
// the run with a message when its limit is reached first.
void ModelEmitter::stage_calls(StageKind kind, const std::string& name, bool after_load) {
  plan_kernels();
  for (std::size_t g = 0; g < m_.stages.size(); ++g) {
    const Stage& stage = m_.stages[g];
    if (stage.kind != kind || stage.name != name || (after_load && !stage.also_after_load)) continue;
    // Statements only the state after the step needs (analysis/observed_steps.cpp)
    // run when it will be read: a run of them under one `if (observed_)`.
    bool guarded = false;
    auto guard = [&](bool observed_only) {
      if (observed_only == guarded) return;
      line(observed_only ? "if (observed_) {  // what only the state after the step needs" : "}");
      guarded = observed_only;
    };
    auto call_one = [&](const Kernel& kernel) {
      if (kernel.profiled >= 0)
        linef("{{ const partc::ProfileTimer timer(profile_, profile_.kernel_slot({})); {}(); }}",
              kernel.profiled, kernel.name);
      else
        linef("{}();", kernel.name);
    };
    auto call = [&](int k) {
      const std::pair<int, int> position{static_cast<int>(g), k};
      std::vector<const Kernel*> here;
      for (const Kernel& kernel : kernels_)
        if (kernel.position == position && kernel.sink.empty()) here.push_back(&kernel);
      if (here.empty()) return;  // a later member of a fused pass
      if (here.front()->observed < 0) {
        guard(observed_only(position));
        for (const Kernel* kernel : here) call_one(*kernel);
        return;
      }
      guard(false);  // a pass of both kinds: whole when observed, else its every-step part
      line("if (observed_) {");
      call_one(*here[0]);
      line("} else {");
      call_one(*here[1]);
      line("}");
    };
    int next = 0;
    for (const Iterate& loop : stage.loops) {
      for (; next < loop.first; ++next) call(next);
      guard(false);
      const ExpressionNames names = base_names();
      const std::string passes = members_.fresh("passes");
      linef("// {}: iterate until {}, at most {} passes", source_line(loop.loc),
            source_text(loop.until->loc), source_text(loop.limit->loc));
      linef("for (std::int64_t {0} = 1;; ++{0}) {{", passes);
      for (; next < loop.last; ++next) call(next);
      guard(false);
      linef("if ({}) break;", expression(loop.until, names));
      linef("if ({} >= {}) {{", passes, expression(loop.limit, names));
      StatementUses reads;
      reads.visit(loop.until);
      std::string values;
      for (int o : reads.observables)
        if (m_.observables[o].type != Type::Vec)
          values += fmt::format(" + \"; {} = \" + partc::shown({})", m_.observables[o].name,
                                names.observables[o]);
      linef(
          "throw partc::NumericalError(\"{}: iterate did not converge in \" + "
          "std::to_string({}) + \" passes (until {})\"{});",
          source_line(loop.loc), passes, source_text(loop.until->loc), values);
      line("}");
      line("}");
    }
    for (; next < static_cast<int>(stage.statements.size()); ++next) call(next);
    guard(false);
  }
}

void ModelEmitter::kernels() {
  plan_kernels();
  for (const Kernel& k : kernels_) kernel(k);
}

void ModelEmitter::kernel(const Kernel& k) {
  const Statement& st = *k.st;  // a fused pass's first member, with every member's labels
  const int home = st.set;
  const auto members = k.members();
  StatementUses uses;
  for (const auto& [member, alias] : members) {
    uses.visit(member->value);
    uses.visit(member->solve_operator);
  }

  // Names local to this kernel: the model's own, then ours.
  NameTable locals;
  for (const Label& l : st.labels)
    if (!l.name.empty()) locals.reserve(cpp_name(l.name));
  for (std::size_t s = 0; s < m_.sets.size(); ++s)
    for (std::size_t v = kFirstUserVar; v < m_.sets[s].vars.size(); ++v)
      locals.reserve(tag(static_cast<int>(s), static_cast<int>(v)));
  std::map<std::pair<int, int>, std::string> arrays;
  auto array_name = [&](int s, int var) -> std::string {
    auto key = std::make_pair(s, var);
    auto it = arrays.find(key);
    if (it != arrays.end()) return it->second;
    // Another set's arrays are named "<var>_<set>" (strength_O): never a tag name.
    const std::string wanted = cpp_name(
        s == home ? m_.sets[s].vars[var].name : m_.sets[s].vars[var].name + "_" + m_.sets[s].name);
    return arrays[key] = locals.fresh(wanted);
  };
  std::set<std::pair<int, int>> needed = uses.arrays;
  // A variant of --profile reads its target only to add to it.
  for (const auto& [member, alias] : members)
    if (member->observable < 0 && (k.sink.empty() || member->op != AssignOp::Set))
      needed.insert({home, member->var});
  if (uses.random) needed.insert({home, kId});
  for (const Accumulate* acc : uses.accumulations) {
    UsesDx dx;
    dx.visit(acc->condition);
    dx.visit(acc->body);
    const SearchFact& fact = facts_.neighbourhoods.at(acc->id);
    // A search over another set is asked from p[i]; one over the home set and Verlet
    // lists by i alone; a dense loop computes dx itself, as does a fast
    // solve's entry for its preconditioner (a fast sum alone does not).
    if (fact.kind == SearchFact::Kind::Neighbours && !st.schedule.skin &&
        st.labels[acc->label].set != home)
      needed.insert({home, kPosition});
    if (fact.kind == SearchFact::Kind::Dense && dx.dx &&
        (!facts_.fast_sums.count(acc->id) || st.solve_operator)) {
      needed.insert({home, kPosition});
      needed.insert({st.labels[acc->label].set, kPosition});
    }
  }
  for (const auto& [s, var] : needed) array_name(s, var);

  ExpressionNames names = base_names();
  names.home_set = home;
  for (const Label& l : st.labels) names.labels.push_back(cpp_name(l.name));
  names.array = array_name;
  for (const Accumulate* acc : uses.accumulations) {
    names.accumulators[acc->id] =
        locals.fresh(std::string(reduction_name(acc->reduction)) + "_" + names.labels[acc->label]);
    if (st.schedule.compensated && acc->reduction == Reduction::Sum)
      compensation_[acc->id] = locals.fresh(names.accumulators[acc->id] + "_error");
  }
  const std::string count = locals.fresh("n");
  // A fused loop has one index: every label it serves is named after the first.
  std::vector<Loop> loops = fuse_loops(uses.accumulations, st);
  for (const Loop& l : loops)
    for (const Accumulate* acc : l.members)
      names.labels[acc->label] = names.labels[l.members.front()->label];
  const std::string i = names.labels[0];

  // The comment: the .part line (each effect's, for a statement they were
  // merged into) and the decisions behind the kernel; a variant's, what it is.
  if (!k.sink.empty()) {
    std::vector<std::string> effects;
    for (const Origin& o : st.origins) effects.push_back(o.effect);
    linef("// --profile: {} with the terms of {} only, into {}, which nobody reads",
          target_name(m_, st), fmt::join(effects, ", "), k.sink);
  } else {
    kernel_comment(k, uses);
  }
  linef("void {}() {{", k.name);
  kernel_constants(st, uses, names, locals);

  // Bring every search this statement needs up to date before any index
  // is taken: a rebuild may reorder its set. Verlet lists, per statement, at
  // this statement's largest radius; searches as the plan groups the sums.
  std::vector<int> groups;
  for (const Accumulate* acc : uses.accumulations) {
    if (st.schedule.skin ||
        facts_.neighbourhoods.at(acc->id).kind != SearchFact::Kind::Neighbours)
      continue;
    const int group = facts_.searches.group_of.at(acc->id);
    if (std::find(groups.begin(), groups.end(), group) == groups.end()) groups.push_back(group);
  }
  if (lists_.count(&st)) refresh_lists(st, locals.fresh("radius"), names);
  walked_search_.clear();
  std::map<int, std::string> walked;  // SearchPlan::searches index -> a calibration search
  for (int group : groups) {
    const auto own = k.calibration_searches.find(group);
    if (own == k.calibration_searches.end()) {
      refresh_search(group, st, names, locals);
      continue;
    }
    const int search = facts_.searches.groups[group].search;
    walked[search] = locals.fresh(m_.sets[facts_.searches.searches[search].set].name + "_search");
    linef("// The search calibrate_profile built at this variant's radius, if nearer than {}'s.",
          searches_[search]);
    linef("const auto& {} = {} ? *{} : {};", walked[search], own->second, own->second,
          searches_[search]);
  }
  // Each loop's search is named now: refresh_search may have bound a local
  // to the one the run's radii chose.
  for (Loop& l : loops)
    if (l.search >= 0 && !st.schedule.skin)
      l.searched = walked.count(l.search) ? walked.at(l.search) : search_for(l.members.front()->id);

  for (const auto& [key, name] : arrays) {
    const int var = key.second;  // a lambda may not capture a structured binding (C++17)
    const bool written =
        key.first == home && k.sink.empty() &&
        std::any_of(members.begin(), members.end(), [&](const auto& m) {
          return m.first->observable < 0 && m.first->var == var;
        });
    linef("{}auto& {} = {};", written ? "" : "const ", name, array_access(key.first, key.second));
  }
  if (st.observable >= 0) {  // one value: its reductions, then the assignment
    for (const Loop& l : loops) loop(l, st, names);
    linef("{} {} {};", names.observables[st.observable], assign_op_spelling(st.op),
          expression(st.value, names));
    line("}");
    line("");
    return;
  }
  linef("const std::size_t {} = {}.size();", count, set_member_[home]);
  if (st.solve_operator) {
    solve_body(k, names, locals, count);
    line("}");
    line("");
    return;
  }
  std::vector<std::string> buffers;  // per member: its buffer, or "" (in place)
  for (const auto& [member, alias] : members) {
    buffers.emplace_back();
    if (k.sink.empty() && !alias->buffered) continue;
    buffers.back() = k.sink.empty() ? buffer_member(home, member->var) : k.sink;
    linef("{}.resize({});", buffers.back(), count);
  }
  for (const Accumulate* acc : uses.accumulations)
    if (facts_.fast_sums.count(acc->id)) fast_sum(*acc, st, names, locals, count);
  std::vector<const Loop*> per_particle;
  std::string pairs_once;  // names the run-time choice of a search's pair walk
  const auto self_pair_comment = [&](const Loop& l) {
    if (!batch_self_pair(l)) line("// i's pair with itself left out: the condition excludes |dx| = 0.");
  };
  // The particle loop reads the sums a walk filled before it.
  const auto read_pair_sums = [&](const Loop& l) {
    for (const Accumulate* acc : l.members)
      names.accumulators[acc->id] = pair_sums_.at(acc->id).first + "[" + i + "]";
  };
  for (const Loop& l : loops) {
    if (!l.once && l.kind == SearchFact::Kind::Neighbours && k.sink.empty())
      linef("{}note_walk();", st.schedule.skin ? lists_.at(&st) + "->" : l.searched + ".");
    if (l.once) {
      loop(l, st, names);
    } else if (l.kind == SearchFact::Kind::Neighbours && half_lists(st)) {
      const std::string walk = lists_.at(&st) + "->for_each_pair";
      if (vector_terms(l)) {
        const std::string terms = batch_kernel(l, names, count, locals, k.name, BatchWalks::pairs);
        self_pair_comment(l);
        linef("{}_batch({}, {});", walk, batch_self_pair(l), terms);
      } else {
        pair_pass(l, names, count, locals, walk, k.name);
      }
      read_pair_sums(l);
    } else if (l.kind == SearchFact::Kind::Neighbours && newton_pairs(st)) {
      const std::string& search = l.searched;
      if (vector_terms(l) && packed_queries(l)) {
        const std::string terms =
            batch_kernel(l, names, count, locals, k.name, BatchWalks::pairs_or_queries);
        const bool self = batch_self_pair(l);
        line("// Each pair once when the search walks pairs in parallel, or the set is small;");
        line("// else each particle's neighbours, packed the same way.");
        self_pair_comment(l);
        linef("if ({}.pairs_once())", search);
        linef("{}.for_each_pair_batch({}, {});", search, self, terms);
        line("else");
        linef("{}.for_each_near_batch({}, {});", search, self, terms);
        read_pair_sums(l);
        continue;
      }
      pairs_once = locals.fresh("pairs_once");
      line("// Each pair once when the search walks pairs in parallel, or the set is small.");
      linef("const bool {} = {}.pairs_once();", pairs_once, search);
      linef("if ({}) {{", pairs_once);
      pair_pass(l, names, count, locals, search + ".for_each_pair", k.name);
      line("}");
      per_particle.push_back(&l);
    } else if (l.kind == SearchFact::Kind::Neighbours && vector_terms(l) && packed_queries(l)) {
      const std::string terms = batch_kernel(l, names, count, locals, k.name, BatchWalks::queries);
      self_pair_comment(l);
      linef("{}.for_each_near_batch({}, {});", l.searched, batch_self_pair(l), terms);
      read_pair_sums(l);
    } else {
      per_particle.push_back(&l);
    }
  }
  // Every iteration writes only particle i's value (aliasing saw to that).
  linef("partc::parallel_for({}, partc::LoopWork::{}, [&](std::size_t {}) {{", count,
        per_particle.empty() ? "light" : "heavy", i);
  for (const Loop* l : per_particle)
    loop(*l, st, names, l->kind == SearchFact::Kind::Neighbours ? pairs_once : "");
  for (std::size_t m = 0; m < members.size(); ++m) assignment(*members[m].first, names, buffers[m]);
  line("});");
  if (!k.sink.empty()) {  // a variant moves and removes nothing
    line("}");
    line("");
    return;
  }
  for (std::size_t m = 0; m < members.size(); ++m)
    if (!buffers[m].empty())
      linef("{}.swap({});", array_name(home, members[m].first->var), buffers[m]);
  if (st.var == kAlive) linef("{}.erase_dead();", set_member_[home]);
  // After the loop: other particles may read this set's mirrored variables in it.
  if (st.var == kPosition && Domain::any(m_.domain.reflect)) {
    std::string mirrored;
    for (std::size_t v = kFirstUserVar; v < m_.sets[home].vars.size(); ++v)
      if (m_.sets[home].vars[v].mirrored)
        mirrored += fmt::format(", {}.get<{}>()", set_member_[home], tag(home, static_cast<int>(v)));
    linef("// Past a reflecting face: mirrored back in{}.",
          mirrored.empty() ? "" : ", the mirrored variables turned");
    linef("partc::reflect_through_faces({}, faces_{});", set_member_[home], mirrored);
  }
  if (st.var == kPosition && Domain::any(m_.domain.open))
    linef("{} += partc::leave_through_open_faces({}, faces_);  // past an open face: gone",
          left_[home], set_member_[home]);
  if (st.var == kPosition || st.var == kAlive) linef("++{};", epoch_[home]);
  line("}");
  line("");
}

// The comment above a kernel: the .part line (each effect's, for a
// statement they were merged into) and the decisions behind it.
void ModelEmitter::kernel_comment(const Kernel& k, const StatementUses& uses) {
  const Statement& st = *k.st;
  const auto members = k.members();
  for (const auto& [member, alias] : members) {
    if (member->origins.empty()) {
      linef("// {}", source_line(member->loc));
      linef("//   {}", source_text(member->loc));
    }
    for (const Origin& o : member->origins) {
      linef("// effect {}, {}", o.effect, source_line(o.loc));
      linef("//   {}", source_text(o.loc));
    }
  }
  if (k.pass >= 0) comment("fused pass: " + facts_.fusion.passes[k.pass].reason);
  for (const Accumulate* acc : uses.accumulations) {
    comment(fmt::format("{}: {}", accumulation_heading(m_, st, *acc),
                        facts_.neighbourhoods.at(acc->id).reason));
    if (newton_pairs(st) && facts_.neighbourhoods.at(acc->id).kind == SearchFact::Kind::Neighbours)
      comment((st.schedule.skin ? "  each pair once, from half Verlet lists: "
                                : "  each pair once when the search can walk pairs: ") +
              facts_.symmetry.at(acc->id).reason);
    if (facts_.uniform_sums.at(acc->id).once)
      comment("  " + facts_.uniform_sums.at(acc->id).reason);
    if (auto fast = facts_.fast_sums.find(acc->id); fast != facts_.fast_sums.end())
      comment("  " + fast->second.reason);
  }
  if (st.solve_operator) comment(facts_.linear_operators.at(k.position).reason);
  for (const auto& [member, alias] : members)
    comment((members.size() > 1 ? target_name(m_, *member) + ": " : "") + alias->reason);
}

// The params and computed consts a kernel reads, as local constants named
// after them: the kernel reads like the model, and the C++ compiler need not
// reload them after every call it cannot see into (exp in a pair loop;
// the seed kernel at N = 20 timed alone: 4% faster).
void ModelEmitter::kernel_constants(const Statement& st, StatementUses uses, ExpressionNames& names,
                                    NameTable& locals) {
  if (st.schedule.skin) uses.visit(st.schedule.skin);
  for (int p : uses.params) {
    const Param& param = m_.params[p];
    names.params[p] = locals.fresh(cpp_name(param.name));
    linef("const {} {} = params_.{};", cpp_type(param.type), names.params[p], cpp_name(param.name));
  }
  for (int c : uses.consts) {
    if (evaluate_constant(m_.consts[c].value, m_)) continue;  // a static constexpr member already
    names.consts[c] = locals.fresh(cpp_name(m_.consts[c].name));
    linef("const {} {} = {};", cpp_type(m_.consts[c].type), names.consts[c], const_member_[c]);
  }
  // Observables are constant while a particle loop runs; an observable's own
  // statement reads and writes the member.
  if (st.observable >= 0) return;
  for (int o : uses.observables) {
    const std::string member = names.observables[o];
    names.observables[o] = locals.fresh(cpp_name(m_.observables[o].name));
    linef("const {} {} = {};", cpp_type(m_.observables[o].type), names.observables[o], member);
  }
}

std::string ModelEmitter::buffer_member(int s, int var, bool sink) {
  auto key = std::make_tuple(s, var, sink);
  auto it = buffers_.find(key);
  if (it != buffers_.end()) return it->second.first;
  const ParticleSet& set = m_.sets[s];
  const std::string name =
      members_.fresh((sink ? "profile_sink_" : "") + (m_.sets.size() > 1 ? set.name + "_" : "") +
                     set.vars[var].name + (sink ? "_" : "_next_"));
  // As the set stores the variable: a float one's buffer holds floats too.
  const Type type = set.vars[var].type;
  const std::string element =
      set.vars[var].storage == Precision::Float
          ? (var == kPosition ? set_type_[s] + "::position_type" : tag(s, var) + "::type")
      : type == Type::Bool ? "std::uint8_t"
                           : cpp_type(type);
  buffers_[key] = {name, element};
  return name;
}

// The .part lines of a search group's sums, each once.
static std::vector<int> group_lines(const Model& m, const SearchGroup& group) {
  std::vector<int> lines;
  for (const auto& [g, s] : group.statements)
    if (std::find(lines.begin(), lines.end(), m.stages[g].statements[s].line) == lines.end())
      lines.push_back(m.stages[g].statements[s].line);
  return lines;
}

// A search group's search, built at the largest radius of the group's sums
// (each in its own statement's names: this kernel's locals, or members), so
// that every kernel of the stretch asks the same radius and only the first
// builds. A search that keeps its set's order is built after the group that
// reorders the set in the stretch, which would otherwise scramble it.
// `walked`: this kernel walks the group's search (else it only builds it).
void ModelEmitter::refresh_search(int group_index, const Statement& st,
                                  const ExpressionNames& names, NameTable& locals, bool walked) {
  const SearchGroup& group = facts_.searches.groups.at(group_index);
  if (group.built_after >= 0) refresh_search(group.built_after, st, names, locals, false);
  if (!group.chosen_at_run_time.empty())
    return choose_search(group_index, st, names, locals, walked);
  const std::string radius = group_radius(group, st, names);
  const std::string local = locals.fresh("radius");
  if (group.sums.size() > 1 || group.built_after >= 0)
    comment(fmt::format("{}'s search, at the largest radius of its sums on line{} {}: {}",
                        m_.sets[facts_.searches.searches.at(group.search).set].name,
                        group.statements.size() > 1 ? "s" : "",
                        fmt::join(group_lines(m_, group), ", "), group.reason));
  linef("const double {} = {};", local, radius);
  build_if_stale(group.search, local, "");
}

// A group whose radius's ratio to its stretch's other groups' is known only
// at run time: the run's radii choose the search its sums walk (the search
// plan's rule, partc::search_to_walk), and only that one is brought up to
// date, so a search no group walks is never built.
void ModelEmitter::choose_search(int group_index, const Statement& st, const ExpressionNames& names,
                                 NameTable& locals, bool walked) {
  const SearchGroup& group = facts_.searches.groups.at(group_index);
  const std::vector<int>& linked = group.chosen_at_run_time;
  comment(fmt::format("{}'s search for the sums on line{} {}: {}",
                      m_.sets[facts_.searches.searches.at(group.search).set].name,
                      group.statements.size() > 1 ? "s" : "",
                      fmt::join(group_lines(m_, group), ", "), group.reason));
  std::vector<std::string> radii;
  for (int other : linked) {
    radii.push_back(locals.fresh("radius"));
    linef("const double {} = {};", radii.back(),
          group_radius(facts_.searches.groups.at(other), st, names));
  }
  const std::string chosen = locals.fresh("walked");
  linef("const std::size_t {} = partc::search_to_walk({{{}}}, {}, {}, {});", chosen,
        fmt::join(radii, ", "),
        std::find(linked.begin(), linked.end(), group_index) - linked.begin(), m_.dim,
        share_candidate_growth);
  std::string choice;
  for (std::size_t k = 0; k < linked.size(); ++k) {
    const int search = facts_.searches.groups.at(linked[k]).search;
    build_if_stale(search, radii[k], fmt::format("{} == {}", chosen, k));
    choice += k + 1 < linked.size()
                  ? fmt::format("{} == {} ? {} : ", chosen, k, searches_.at(search))
                  : searches_.at(search);
  }
  if (!walked) return;
  const std::string local = locals.fresh("search");
  linef("partc::NeighbourSearch<{}>& {} = {};", m_.dim, local, choice);
  walked_search_[group_index] = local;
}

// The radius a group's search is built at: the largest of its sums' radii,
// each in its own statement's names (this kernel's locals, or members).
std::string ModelEmitter::group_radius(const SearchGroup& group, const Statement& st,
                                       const ExpressionNames& names) const {
  std::vector<std::string> radii;
  for (std::size_t k = 0; k < group.sums.size(); ++k) {
    const auto [g, s] = group.statements[k];
    const Statement& owner = m_.stages[g].statements[s];
    const std::string radius = radius_expression(facts_.neighbourhoods.at(group.sums[k]), owner,
                                                 &owner == &st ? names : names_outside(owner));
    if (std::find(radii.begin(), radii.end(), radius) == radii.end()) radii.push_back(radius);
  }
  std::string radius = radii.front();
  for (std::size_t k = 1; k < radii.size(); ++k)
    radius = "std::max(" + radius + ", " + radii[k] + ")";
  return radius;
}

// Builds a search at the radius in the local `radius` unless its set is
// unchanged since its last build at that radius; `chosen`, when not "", is
// the run-time condition under which this kernel walks it.
void ModelEmitter::build_if_stale(int search_index, const std::string& radius,
                                  const std::string& chosen) {
  const PlannedSearch& plan = facts_.searches.searches.at(search_index);
  const std::string& search = searches_.at(search_index);
  const int s = plan.set;
  const std::string stale =
      fmt::format("{0}epoch_ != {1} || {0}radius_ != {2}", search, epoch_[s], radius);
  linef("if ({}) {{", chosen.empty() ? stale : chosen + " && (" + stale + ")");
  if (options_.profile)
    linef("const partc::ProfileTimer timer(profile_, profile_.search_slot({}));", search_index);
  linef("{}.build(domain_, {}, {});", search, radius, set_member_[s]);
  if (plan.reorders)
    linef("{}epoch_ = ++{};  // the build may reorder {}", search, epoch_[s], m_.sets[s].name);
  else
    linef("{}epoch_ = {};  // {} keeps its order", search, epoch_[s], m_.sets[s].name);
  linef("{}radius_ = {};", search, radius);
  line("}");
}

// Another statement's names, for its expressions in this kernel: members and
// arrays, not the locals its own kernel would have.
ExpressionNames ModelEmitter::names_outside(const Statement& owner) const {
  ExpressionNames theirs = base_names();
  theirs.home_set = owner.set;
  for (const Label& l : owner.labels) theirs.labels.push_back(cpp_name(l.name));
  theirs.array = [this](int set, int var) { return array_access(set, var); };
  return theirs;
}

// The search radius: the bound itself when it is uniform, else the sum of
// each term's largest value over the particles it reads (max r + max r for
// r[i] + r[j]), kept positive so coincident particles are still found.
std::string ModelEmitter::radius_expression(const SearchFact& fact, const Statement& st,
                                            const ExpressionNames& names) const {
  if (fact.radius_terms.size() == 1 && is_uniform(fact.radius_terms.front()))
    return expression(fact.radius_terms.front(), names);
  std::vector<std::string> parts;
  for (const Expr& term : fact.radius_terms) {
    StatementUses reads;
    reads.visit(term);
    if (reads.arrays.empty()) {
      parts.push_back(expression(term, names));
      continue;
    }
    const int label = reads.labels.front();
    const int set = st.labels[label].set;
    ExpressionNames over_k = names;
    over_k.labels[label] = "k";
    over_k.array = [this](int s, int var) { return array_access(s, var); };
    parts.push_back(fmt::format("partc::max_over({}.size(), [&](std::size_t k) {{ return {}; }})",
                                set_member_[set], expression(term, over_k)));
  }
  return fmt::format("std::max({}, std::numeric_limits<double>::min())", fmt::join(parts, " + "));
}

// Whether any of the statement's sums is over neighbours: a pair walk.
bool ModelEmitter::walks_pairs(const Statement& st) const {
  StatementUses uses;
  uses.visit(st.value);
  return std::any_of(uses.accumulations.begin(), uses.accumulations.end(), [&](const Accumulate* acc) {
    return facts_.neighbourhoods.at(acc->id).kind == SearchFact::Kind::Neighbours;
  });
}

bool ModelEmitter::newton_pairs(const Statement& st) const {
  if (st.schedule.compensated) return false;  // each particle sums its own terms, in order
  StatementUses uses;
  uses.visit(st.value);
  bool any = false;
  for (const Accumulate* acc : uses.accumulations) {
    if (facts_.neighbourhoods.at(acc->id).kind != SearchFact::Kind::Neighbours) continue;
    if (!facts_.symmetry.at(acc->id).newton) return false;
    any = true;
  }
  return any;
}

// Verlet lists: reused while no particle has moved half the skin since
// they were built; a rebuild may reorder the set, like a search build. Lists
// shared by several statements are built at the largest radius of all their
// sums (each in its own statement's names), so every kernel asks the same.
void ModelEmitter::refresh_lists(const Statement& st, const std::string& local,
                                 const ExpressionNames& names) {
  const std::string& lists = lists_.at(&st);
  std::vector<std::string> radii;
  for (const auto& [member, statements] : lists_served()) {
    if (member != lists) continue;
    for (const Statement* owner : statements) {
      StatementUses uses;
      uses.visit(owner->value);
      for (const Accumulate* acc : uses.accumulations) {
        const SearchFact& fact = facts_.neighbourhoods.at(acc->id);
        if (fact.kind != SearchFact::Kind::Neighbours) continue;
        const std::string radius =
            radius_expression(fact, *owner, owner == &st ? names : names_outside(*owner));
        if (std::find(radii.begin(), radii.end(), radius) == radii.end()) radii.push_back(radius);
      }
    }
  }
  std::string radius = radii.front();
  for (std::size_t k = 1; k < radii.size(); ++k)
    radius = "std::max(" + radius + ", " + radii[k] + ")";
  const std::string skin = expression(st.schedule.skin, names);
  linef("const double {} = {};", local, radius);
  const std::string pairs = lists_pairs(lists);
  linef("if (!{0} || {0}->skin() != {1}) {0}.emplace({1}{2});", lists, skin,
        pairs == "partc::VerletPairs::full" ? "" : ", " + pairs);
  if (options_.profile) {
    const auto served = lists_served();
    const auto it = std::find_if(served.begin(), served.end(),
                                 [&](const auto& entry) { return entry.first == lists; });
    linef("const partc::ProfileTimer timer(profile_, profile_.search_slot({}));",
          searches_.size() + static_cast<std::size_t>(it - served.begin()));
  }
  linef("if ({}->update(domain_, {}, {})) ++{};  // rebuilt: {} may be reordered", lists, local,
        set_member_[st.set], epoch_[st.set], m_.sets[st.set].name);
}

std::vector<ModelEmitter::Loop> ModelEmitter::fuse_loops(
    const std::vector<const Accumulate*>& accumulations, const Statement& st) const {
  std::vector<Loop> loops;
  for (const Accumulate* acc : accumulations) {
    if (facts_.fast_sums.count(acc->id)) continue;  // summed by fast_sum(), not in a loop
    const int set = st.labels[acc->label].set;
    const SearchFact::Kind kind = facts_.neighbourhoods.at(acc->id).kind;
    const bool once = facts_.uniform_sums.at(acc->id).once;
    const auto group = facts_.searches.group_of.find(acc->id);
    const int search =
        group == facts_.searches.group_of.end() ? -1 : facts_.searches.groups[group->second].search;
    auto same = std::find_if(loops.begin(), loops.end(), [&](const Loop& l) {
      return l.set == set && l.kind == kind && l.once == once && l.search == search;
    });
    if (same == loops.end())
      loops.push_back({set, kind, once, search, "", {acc}});
    else
      same->members.push_back(acc);
  }
  return loops;
}

std::string ModelEmitter::identity(const Accumulate& acc) const {
  switch (acc.reduction) {
    case Reduction::Sum: return acc.type == Type::Vec ? "Vec::zero()" : emit_literal(acc.type, 0);
    case Reduction::Count: return "0";
    case Reduction::Min:
      return acc.type == Type::Real ? "std::numeric_limits<double>::infinity()"
                                    : "std::numeric_limits<std::int64_t>::max()";
    case Reduction::Max:
      return acc.type == Type::Real ? "-std::numeric_limits<double>::infinity()"
                                    : "std::numeric_limits<std::int64_t>::min()";
  }
  internal_error("identity: unknown reduction");
}

std::string ModelEmitter::update(const Accumulate& acc, const ExpressionNames& names,
                                 bool compensated) const {
  const std::string& name = names.accumulators.at(acc.id);
  std::string step;
  switch (acc.reduction) {
    case Reduction::Sum:
      step = compensated ? fmt::format("partc::neumaier_add({}, {}, {});", name,
                                       compensation_.at(acc.id), expression(acc.body, names))
                         : name + " += " + expression(acc.body, names) + ";";
      break;
    case Reduction::Count: step = "++" + name + ";"; break;
    case Reduction::Min:
    case Reduction::Max:
      step = fmt::format("{0} = std::{1}<{2}>({0}, {3});", name, reduction_name(acc.reduction),
                         cpp_type(acc.type), expression(acc.body, names));
      break;
  }
  if (always_true(acc)) return step;
  return "if (" + expression(acc.condition, names) + ") " + step;
}

// No condition, or one always true (sum(j, true, ...)): no test.
bool ModelEmitter::always_true(const Accumulate& acc) const {
  const std::optional<double> constant =
      acc.condition ? evaluate_constant(acc.condition, m_) : std::optional<double>(1.0);
  return constant && *constant != 0;
}

std::string ModelEmitter::accumulator_type(const Accumulate& acc) const {
  return acc.reduction == Reduction::Count ? "std::int64_t" : cpp_type(acc.type);
}

// The loop of one particle i over its partners; with pairs_once (the name of
// the run-time choice) the totals come from the pair walk's sums instead.
void ModelEmitter::loop(const Loop& l, const Statement& st, const ExpressionNames& names,
                        const std::string& pairs_once) {
  UsesDx dx;
  bool reads_j = false;
  // Neumaier's summation keeps each sum's lost low-order part beside it.
  const auto compensated = [&](const Accumulate& acc) {
    return st.schedule.compensated && acc.reduction == Reduction::Sum;
  };
  for (const Accumulate* acc : l.members) {
    linef("{} {} = {};", accumulator_type(*acc), names.accumulators.at(acc->id), identity(*acc));
    if (compensated(*acc))
      linef("{} {} = {};", accumulator_type(*acc), compensation_.at(acc->id), identity(*acc));
    dx.visit(acc->condition);
    dx.visit(acc->body);
    ReadsLabel reads(acc->label);
    reads.visit(acc->condition);
    reads.visit(acc->body);
    reads_j |= reads.found;
  }
  ExpressionNames inner = names;
  inner.dx_norm = dx.norm ? "dx_norm" : "";
  std::string body;
  if (dx.norm) body += "const double dx_norm = partc::norm(dx);\n";
  for (const Accumulate* acc : l.members) body += update(*acc, inner, compensated(*acc)) + "\n";

  const std::string j = names.labels[l.members.front()->label];
  const std::string i = names.labels[0];
  const std::string home_p = names.array(st.set, kPosition);
  if (!pairs_once.empty()) {
    linef("if ({}) {{", pairs_once);
    for (const Accumulate* acc : l.members)
      linef("{} = {}[{}];", names.accumulators.at(acc->id), pair_sums_.at(acc->id).first, i);
    line("} else {");
  }
  if (l.kind == SearchFact::Kind::Neighbours) {
    if (st.schedule.skin)
      linef("{}->for_each_near({}, [&](std::size_t{}, const Vec&{}) {{", lists_.at(&st), i,
            reads_j ? " " + j : "", dx.dx ? " dx" : "");
    else  // a query from the searched set itself goes by index: the search knows its cell
      linef("{}.for_each_near({}, [&](std::size_t{}, const Vec&{}) {{", l.searched,
            l.set == st.set ? i : emit_load(m_, st.set, kPosition, home_p + "[" + i + "]"),
            reads_j ? " " + j : "", dx.dx ? " dx" : "");
    out_ += body;
    line("});");
    if (!pairs_once.empty()) line("}");
  } else {
    linef("for (std::size_t {0} = 0; {0} < {1}.size(); ++{0}) {{", j, set_member_[l.set]);
    if (dx.dx)
      linef("const Vec dx = domain_.minimum_image({} - {});",
            emit_load(m_, l.set, kPosition, names.array(l.set, kPosition) + "[" + j + "]"),
            emit_load(m_, st.set, kPosition, home_p + "[" + i + "]"));
    out_ += body;
    line("}");
  }
  for (const Accumulate* acc : l.members)
    if (compensated(*acc))
      linef("{} += {};", names.accumulators.at(acc->id), compensation_.at(acc->id));
}

// The sums of a loop over pairs (walk: half lists' or a search's
// for_each_pair), pair by pair, into per-particle member vectors (kept
// between steps for their memory) that the particle loop reads.
void ModelEmitter::pair_pass(const Loop& l, const ExpressionNames& names, const std::string& count,
                             NameTable& locals, const std::string& walk,
                             const std::string& kernel) {
  const std::string i = names.labels[0];
  const std::string j = names.labels[l.members.front()->label];
  UsesDx dx;
  for (const Accumulate* acc : l.members) {
    dx.visit(acc->condition);
    dx.visit(acc->body);
    linef("{}.assign({}, {});", pair_sums_member(*acc, kernel), count, identity(*acc));
  }
  ExpressionNames inner = names;
  inner.dx_norm = dx.norm ? "dx_norm" : "";
  // i's terms go to locals, stored once per group of i's pairs; j's straight to j.
  std::map<int, std::string> of_i;
  for (const Accumulate* acc : l.members)
    of_i[acc->id] = locals.fresh(std::string(reduction_name(acc->reduction)) + "_" + i);
  const std::string term = locals.fresh("term"), pairs = locals.fresh("pairs_of_" + i);
  line("// Each pair once (Newton's third law): i and j get the same term, or opposite ones.");
  linef("{}([&](std::size_t {}, const auto& {}) {{", walk, i, pairs);
  for (const Accumulate* acc : l.members)
    linef("{} {} = {};", accumulator_type(*acc), of_i.at(acc->id), identity(*acc));
  linef("{}([&](std::size_t {}, const Vec&{}) {{", pairs, j, dx.dx ? " dx" : "");
  if (dx.norm) line("const double dx_norm = partc::norm(dx);");
  for (const Accumulate* acc : l.members) {
    const std::string& sums = pair_sums_.at(acc->id).first;
    const bool test = !always_true(*acc);
    if (test) linef("if ({}) {{", expression(acc->condition, inner));
    if (acc->reduction == Reduction::Count) {
      linef("++{};", of_i.at(acc->id));
      linef("if ({2} != {1}) ++{0}[{2}];", sums, i, j);
    } else {
      linef("const {} {} = {};", cpp_type(acc->type), term, expression(acc->body, inner));
      linef("{} += {};", of_i.at(acc->id), term);
      linef("if ({2} != {1}) {0}[{2}] {3}= {4};", sums, i, j,
            facts_.symmetry.at(acc->id).sign > 0 ? "+" : "-", term);
    }
    if (test) line("}");
  }
  line("});");
  for (const Accumulate* acc : l.members)
    linef("{}[{}] += {};", pair_sums_.at(acc->id).first, i, of_i.at(acc->id));
  line("});");
}

// Named after the kernel: step_f_sum_, step_f_count_.
std::string ModelEmitter::pair_sums_member(const Accumulate& acc, const std::string& kernel) {
  auto it = pair_sums_.find(acc.id);
  if (it != pair_sums_.end()) return it->second.first;
  const std::string name =
      members_.fresh(kernel + "_" + std::string(reduction_name(acc.reduction)) + "_");
  pair_sums_[acc.id] = {name, accumulator_type(acc)};
  return name;
}

// A store rounds once to the target's storage: compound assignments to a
// float compute in double (float += double), Vec<D, float> likewise.
void ModelEmitter::assignment(const Statement& st, const ExpressionNames& names,
                              const std::string& buffer) {
  const std::string target = names.array(st.set, st.var) + "[" + names.labels[0] + "]";
  const bool wrap = st.var == kPosition && Domain::any(m_.domain.periodic);
  const std::string value = expression(st.value, names);
  if (buffer.empty() && !wrap) {
    linef("{} {} {};", target, assign_op_spelling(st.op), value);
    return;
  }
  // The new value as one expression: target op value.
  std::string updated = value;
  if (st.op != AssignOp::Set) {
    static const BinaryOp ops[] = {BinaryOp::Add, BinaryOp::Add, BinaryOp::Sub, BinaryOp::Mul,
                                   BinaryOp::Div};
    const BinaryOp op = ops[static_cast<int>(st.op)];
    updated = fmt::format("{} {} {}", emit_load(m_, st.set, st.var, target),
                          binary_op_spelling(op), codegen::emit_operand(st.value, op, m_, names));
  }
  const std::string stored = buffer.empty() ? target : buffer + "[" + names.labels[0] + "]";
  // A float position rounded to the float nearest the wrapped one could be hi.
  if (wrap && m_.sets[st.set].vars[kPosition].storage == Precision::Float)
    linef("domain_.wrap_into({}, {});", stored, updated);
  else
    linef("{} = {};", stored, wrap ? "domain_.wrap(" + updated + ")" : updated);
}

}  // namespace partc::codegen
