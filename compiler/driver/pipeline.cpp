#include "driver/pipeline.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "analysis/fast_sums.hpp"
#include "analysis/schedule.hpp"
#include "ast/schedule_overrides.hpp"
#include "grammar/parser.hpp"
#include "ir/visitor.hpp"
#include "sema/sema.hpp"

namespace partc {

namespace {

// The passes, in order: each fills its part of `c`.
void run_passes(SourceFile& file, const SceneOptions& scene, const PassOptions& passes,
                Compilation& c) {
  // Text to syntax tree; syntax errors stop here, with what was expected.
  // A scene's effects are opened and instantiated: a plain model from here on.
  c.ast = instantiate_scene(parse_program(file), file, scene, c.scene);
  // Schedule entries from the command line, over the model's own.
  ast::apply_schedule_overrides(c.ast, file, passes.schedule);
  // Names and types: everything later can trust the IR to be well typed.
  c.model = build_ir(c.ast, file, c.warnings);
  // Conditionals a constant decides (use sph.pressure(const kernel = 1)),
  // then terms a constant 0 removes (use force.gravity(const g = 0)): before
  // fusion and the analyses, so nothing only the folded code read is loaded
  // or searched; then its functions and consts, which are not emitted.
  const ir::DeclarationsRead read = ir::declarations_read(c.model);
  c.folded_conditions = ir::fold_conditions(c.model);
  c.folded = ir::fold_zero_terms(c.model);
  c.unread = ir::drop_unread_declarations(c.model, read);
  // Fusion across statements: an effect's variable set and read once per
  // step is computed where it is read. Before the analyses, which see the
  // fused statements.
  c.single_use = ir::inline_single_use(c.model);
  // Facts the code generator acts on. Each pass reads the IR only.
  c.facts.uniform_sums = find_uniform_sums(c.model);
  c.facts.aliasing = detect_aliasing(c.model, c.facts.uniform_sums);
  c.facts.neighbourhoods = find_neighbourhoods(c.model, file.text());
  c.facts.symmetry = find_pair_symmetry(c.model);
  // Terms that are NaN or Inf for coincident particles (warnings, at the end),
  // and conditions that keep coincident pairs out.
  c.coincident = find_coincident_pairs(c.model, file.text());
  // Which sums over neighbours compute their terms on vectors of pairs, and
  // whether their walk needs i's pair with itself.
  c.facts.vector_terms = find_vector_terms(c.model, c.facts.neighbourhoods, c.facts.symmetry,
                                           c.coincident, passes.simd);
  // A solve's matrix: dense or sparse as its sums' neighbourhoods say.
  c.facts.linear_operators = find_linear_operators(c.model, c.facts.neighbourhoods);
  // The schedule can only be judged once neighbourhood sums are known; so
  // can which dense sums it runs fast, and with what kernel and charges.
  check_schedule(c.model, c.facts.neighbourhoods);
  c.facts.fast_sums =
      find_fast_sums(c.model, c.facts.neighbourhoods, c.facts.linear_operators, file.text());
  // Which sums share a search, and at what radius: needs the schedule checked.
  c.facts.searches = plan_searches(c.model, c.facts.neighbourhoods, file.text());
  // What only the state after a step needs (an observable nothing in a step
  // reads, and what only it reads) runs only on observed steps: judged on the
  // statements codegen emits (after fusion and folding); needs no other fact.
  c.facts.observed_steps = find_observed_steps(c.model);
  // Consecutive statements one walk can serve: needs the plan and symmetry,
  // and which statements run only on observed steps (a pass runs whole or not).
  c.facts.fusion =
      fuse_statements(c.model, c.facts.neighbourhoods, c.facts.symmetry, c.facts.searches,
                      c.facts.observed_steps, file, passes.fuse_statements);
  for (const auto& [id, fact] : c.coincident)
    if (fact.warning) c.warnings.push_back(*fact.warning);
}

}  // namespace

Compilation analyse(SourceFile& file, const SceneOptions& scene, const PassOptions& passes) {
  Compilation c;
  try {
    run_passes(file, scene, passes, c);
  } catch (const CompileError& e) {
    std::vector<Diagnostic> diagnostics = e.diagnostics();
    add_scene_context(diagnostics, c.scene, file);
    throw CompileError(diagnostics);
  }
  add_scene_context(c.warnings, c.scene, file);
  return c;
}

// Each search of the plan: its set, structure and order, then per stretch
// between position changes the sums it serves, the radius it is built at,
// and why they share it (or have it apart from others).
static std::string explain_search_plan(const Compilation& c) {
  const SearchPlan& plan = c.facts.searches;
  if (plan.searches.empty()) return "";
  std::string out =
      "search plan (one build per position change and search, at the largest "
      "radius of the sums it serves; each sum keeps its own cutoff test):\n";
  for (std::size_t k = 0; k < plan.searches.size(); ++k) {
    const PlannedSearch& search = plan.searches[k];
    out += fmt::format("  search {}: over {}{}; {}\n", k + 1, c.model.sets[search.set].name,
                       search.structure == ir::SearchChoice::Auto
                           ? ""
                           : std::string(", always ") + ir::search_choice_name(search.structure),
                       search.order_reason);
    for (const SearchGroup& group : plan.groups) {
      if (group.search != static_cast<int>(k)) continue;
      std::vector<int> lines;
      for (const auto& [g, s] : group.statements)
        if (std::find(lines.begin(), lines.end(), c.model.stages[g].statements[s].line) ==
            lines.end())
          lines.push_back(c.model.stages[g].statements[s].line);
      out += fmt::format(
          "    line{} {}: radius {}{}: {}\n", lines.size() > 1 ? "s" : "", fmt::join(lines, ", "),
          group.radii.size() > 1 ? fmt::format("max({})", fmt::join(group.radii, ", "))
                                 : group.radii.front(),
          group.built_after >= 0
              ? fmt::format(", built after search {}", plan.groups[group.built_after].search + 1)
              : "",
          group.reason);
    }
  }
  return out;
}

namespace {

// "57 bytes per particle (p 24, id 8, alive 1, q 8, v 16)": what the
// generated set's arrays hold (partc::BasicParticleSet::bytes_per_particle).
std::string bytes_per_particle(const ir::ParticleSet& set, int dim) {
  std::size_t total = 0;
  std::vector<std::string> parts;
  for (std::size_t v = 0; v < set.vars.size(); ++v) {
    const ir::Variable& var = set.vars[v];
    const std::size_t scalar = var.storage == ir::Precision::Float ? 4 : 8;
    const std::size_t bytes = v == ir::kAlive || var.type == ir::Type::Bool ? 1
                              : v == ir::kId || var.type == ir::Type::Int   ? 8
                              : var.type == ir::Type::Vec                   ? scalar * dim
                                                                            : scalar;
    total += bytes;
    parts.push_back(fmt::format("{} {}", var.name, bytes));
  }
  return fmt::format("{} bytes per particle ({})", total, fmt::join(parts, ", "));
}

}  // namespace

std::string explain(const Compilation& c, const SourceFile& file) {
  std::string out = fmt::format("model {}: {} particle set(s), {} stage block(s)\n", c.model.name,
                                c.model.sets.size(), c.model.stages.size());
  out += explain_scene(c.scene, file);
  for (const ir::FoldedCondition& f : c.folded_conditions)
    out += fmt::format("folded: {}'s {} ({}) is decided when partc runs: its condition is {}\n",
                       f.effect.empty() ? "a statement" : "effect " + f.effect, file.slice(f.loc),
                       file.line_reference(f.loc.begin), f.condition ? "true" : "false");
  for (const ir::FoldedTerm& t : c.folded)
    out +=
        fmt::format("folded: {}'s term of {} ({}) is 0 whatever the data (a constant 0 factor)\n",
                    t.effect.empty() ? "a statement" : "effect " + t.effect, t.target,
                    file.line_reference(t.loc.begin));
  for (const ir::DroppedDeclaration& d : c.unread)
    out += fmt::format("folded: {} {} ({}) is not emitted: only folded code read it\n", d.kind,
                       d.name, file.line_reference(d.loc.begin));
  for (const ir::InlinedVariable& v : c.single_use.inlined)
    out +=
        fmt::format("fused: {}.{} is not stored: {} computes it where {} reads it\n", v.set, v.var,
                    file.line_reference(v.writer.begin), file.line_reference(v.reader.begin));
  for (const ir::InlineRefusal& r : c.single_use.refused)
    out += fmt::format("not fused: {}.{} stays stored: {}\n", r.set, r.var, r.reason);
  for (const FusedPass& pass : c.facts.fusion.passes) out += "fused pass: " + pass.reason + "\n";
  for (const FusionRefusal& r : c.facts.fusion.refused) out += "not fused pass: " + r.reason + "\n";
  out +=
      "storage (computed in double however stored, except pair terms on float lanes "
      "(arithmetic = float): a load widens, a store rounds once):\n";
  for (const ir::ParticleSet& set : c.model.sets) {
    for (const ir::Variable& var : set.vars)
      if (!var.storage_reason.empty())
        out += "  " + set.name + "." + var.name + ": " + var.storage_reason + "\n";
    out += "  " + set.name + ": " + bytes_per_particle(set, c.model.dim) + "\n";
  }
  for (std::size_t g = 0; g < c.model.stages.size(); ++g) {
    const ir::Stage& stage = c.model.stages[g];
    for (std::size_t k = 0; k < stage.statements.size(); ++k) {
      const ir::Statement& st = stage.statements[k];
      const LineColumn at = file.line_column(st.loc.begin);
      const std::string kind = stage.kind == ir::StageKind::Init   ? "init"
                               : stage.kind == ir::StageKind::Step ? "step"
                                                                   : "stage " + stage.name;
      if (st.origins.empty()) {
        out += fmt::format("{}:{}: {} {}\n", file.path(), at.line, kind, file.slice(st.loc));
      } else {  // instantiated: the statement, then each effect's term of it
        out += fmt::format("{} {} {} ... ({}):\n", kind, ir::target_name(c.model, st),
                           ir::assign_op_spelling(st.op), st.name);
        for (const ir::Origin& o : st.origins)
          out += fmt::format("  effect {}, {}: {}\n", o.effect, file.line_reference(o.loc.begin),
                             file.slice(o.loc));
      }
      out += "  update: " + c.facts.aliasing[g][k].reason + "\n";
      if (auto observed = c.facts.observed_steps.find({static_cast<int>(g), static_cast<int>(k)});
          observed != c.facts.observed_steps.end())
        out += "  runs: " + observed->second.reason + "\n";
      if (st.solve_operator)
        out += "  solve: " +
               c.facts.linear_operators.at({static_cast<int>(g), static_cast<int>(k)}).reason +
               "\n";
      for (const ir::Accumulate* acc : ir::accumulations_in(st)) {
        const SearchFact& fact = c.facts.neighbourhoods.at(acc->id);
        out += fmt::format("  {}: {}\n", ir::accumulation_heading(c.model, st, *acc), fact.reason);
        if (c.facts.uniform_sums.at(acc->id).once)
          out += "    " + c.facts.uniform_sums.at(acc->id).reason + "\n";
        if (c.coincident.at(acc->id).singular)
          out += "    coincident particles: " + c.coincident.at(acc->id).reason + "\n";
        if (auto fast = c.facts.fast_sums.find(acc->id); fast != c.facts.fast_sums.end())
          out += "    " + fast->second.reason + "\n";
        if (fact.kind != SearchFact::Kind::Neighbours) continue;
        const PairSymmetryFact& pairs = c.facts.symmetry.at(acc->id);
        out +=
            std::string("    pairs: ") +
            (pairs.newton ? (st.schedule.skin
                                 ? "each pair once, from half Verlet lists (Newton's third law): "
                                 : "each pair once (Newton's third law) when the search "
                                   "walks pairs in parallel (a cell list) or the set is small "
                                   "enough for one thread; else per-particle queries: ")
                          : "both ways: ") +
            pairs.reason + "\n";
        if (auto vector = c.facts.vector_terms.find(acc->id); vector != c.facts.vector_terms.end())
          out += "    terms: " + vector->second.reason + "\n";
        if (!st.schedule.skin) {
          const int group = c.facts.searches.group_of.at(acc->id);
          out += fmt::format("    search {} (search plan below)\n",
                             c.facts.searches.groups[group].search + 1);
        }
        if (st.schedule.skin)
          out += "    schedule: Verlet lists with skin " +
                 std::string(file.slice(st.schedule.skin->loc)) +
                 ", rebuilt only when a particle has moved more than half the skin (a radius over "
                 "half "
                 "a periodic box length is refused at run time: lists keep one image)\n";
        else if (st.schedule.search != ir::SearchChoice::Auto)
          out += std::string("    schedule: always ") + ir::search_choice_name(st.schedule.search) +
                 " (brute force for a radius over half a periodic box length)\n";
        else
          out +=
              "    at run time, from the data: brute force when a cell list would save each query "
              "fewer than partc::NeighbourSearch::default_margin pair tests (few particles, or "
              "a radius near the box size); a k-d tree when the particles are so clustered that "
              "a cell list's queries would examine more than "
              "NeighbourSearch::kd_tree_above_examined points; else an ordered cell list. "
              "A radius over half a periodic box length always means brute force, which sums "
              "every periodic image within it. Rebuilt only after positions change. Override "
              "with a schedule.\n";
      }
    }
  }
  return out + explain_search_plan(c);
}

}  // namespace partc
