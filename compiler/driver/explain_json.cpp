// --explain=json: the facts --explain prints, as one JSON document, for
// tests and tools. The reasons are the analyses' own strings; this file only
// arranges them (nlohmann::json writes and escapes).
#include <algorithm>
#include <nlohmann/json.hpp>

#include "driver/pipeline.hpp"
#include "ir/visitor.hpp"

namespace partc {

namespace {

using Json = nlohmann::ordered_json;

std::string where(const SourceFile& file, Location loc) {
  return file.path_of(loc.begin) + ":" + std::to_string(file.line_column(loc.begin).line);
}

Json scene_facts(const SceneReport& scene, const SourceFile& file) {
  Json out;
  out["kept"] = Json::array();
  for (const SceneReport::Instance& inst : scene.kept)
    out["kept"].push_back({{"name", inst.name},
                           {"module", inst.module},
                           {"sets", inst.sets},
                           {"use", where(file, inst.use)}});
  out["dropped"] = scene.dropped;
  out["modules_opened"] = scene.modules_opened;
  out["placements"] = Json::array();
  for (const SceneReport::Placement& p : scene.placements)
    out["placements"].push_back({{"statement", p.statement},
                                 {"text", p.text},
                                 {"kept", !scene.dropped_statement(p.statement)}});
  out["liveness"] = Json::array();
  for (const SceneReport::Decision& d : scene.variables)
    out["liveness"].push_back({{"what", d.what}, {"kept", d.kept}, {"why", d.why}});
  out["dropped_statements"] = Json::array();
  for (const SceneReport::DroppedStatement& d : scene.dropped_statements)
    out["dropped_statements"].push_back(
        {{"name", d.name}, {"target", d.target}, {"at", where(file, d.loc)}});
  return out;
}

}  // namespace

std::string explain_json(const Compilation& c, const SourceFile& file) {
  Json out;
  out["model"] = c.model.name;
  if (c.scene.is_scene()) out["effects"] = scene_facts(c.scene, file);
  out["folded"] = Json::array();
  for (const ir::FoldedTerm& t : c.folded)
    out["folded"].push_back(
        {{"effect", t.effect}, {"target", t.target}, {"at", where(file, t.loc)}});
  out["folded_conditions"] = Json::array();
  for (const ir::FoldedCondition& f : c.folded_conditions)
    out["folded_conditions"].push_back(
        {{"effect", f.effect}, {"condition", f.condition}, {"at", where(file, f.loc)}});
  out["not_emitted"] = Json::array();
  for (const ir::DroppedDeclaration& d : c.unread)
    out["not_emitted"].push_back({{"kind", d.kind}, {"name", d.name}, {"at", where(file, d.loc)}});
  out["fused"] = Json::array();
  for (const ir::InlinedVariable& v : c.single_use.inlined)
    out["fused"].push_back({{"set", v.set},
                            {"var", v.var},
                            {"writer", where(file, v.writer)},
                            {"reader", where(file, v.reader)}});
  out["not_fused"] = Json::array();
  for (const ir::InlineRefusal& r : c.single_use.refused)
    out["not_fused"].push_back({{"set", r.set}, {"var", r.var}, {"reason", r.reason}});
  out["fused_passes"] = Json::array();
  for (const FusedPass& pass : c.facts.fusion.passes) {
    Json lines = Json::array();
    for (const auto& [g, k] : pass.statements)
      lines.push_back(c.model.stages[g].statements[k].line);
    out["fused_passes"].push_back({{"lines", lines}, {"reason", pass.reason}});
  }
  out["not_fused_passes"] = Json::array();
  for (const FusionRefusal& r : c.facts.fusion.refused)
    out["not_fused_passes"].push_back(
        {{"lines",
          {c.model.stages[r.first.first].statements[r.first.second].line,
           c.model.stages[r.second.first].statements[r.second.second].line}},
         {"reason", r.reason}});
  // The search plan: each group of sums, its search, and whether the choice
  // between sharing and a search of its own is made here or at run time.
  out["search_groups"] = Json::array();
  for (const SearchGroup& group : c.facts.searches.groups) {
    Json lines = Json::array();
    for (const auto& [g, k] : group.statements) {
      const int line = c.model.stages[g].statements[k].line;
      if (std::find(lines.begin(), lines.end(), line) == lines.end()) lines.push_back(line);
    }
    Json j = {{"search", group.search + 1},
              {"set", c.model.sets[c.facts.searches.searches[group.search].set].name},
              {"lines", lines},
              {"radii", group.radii},
              {"chosen", group.chosen_at_run_time.empty() ? "compile time" : "run time"},
              {"reason", group.reason}};
    if (!group.chosen_at_run_time.empty()) {
      Json with = Json::array();
      for (int other : group.chosen_at_run_time)
        with.push_back(c.facts.searches.groups[other].search + 1);
      j["rule"] = {{"walks",
                    "the search at M, the largest radius of these searches' groups, "
                    "while (M / r)^dim <= growth, with r this group's radius; else its "
                    "own search, built at r"},
                   {"dim", c.model.dim},
                   {"growth", share_candidate_growth},
                   {"searches", with}};
    }
    out["search_groups"].push_back(j);
  }
  out["sets"] = Json::array();
  for (const ir::ParticleSet& set : c.model.sets) {
    Json vars = Json::array();
    for (const ir::Variable& var : set.vars)
      vars.push_back({{"name", var.name}, {"storage", var.storage_reason}});
    out["sets"].push_back({{"name", set.name}, {"variables", vars}});
  }
  out["statements"] = Json::array();
  for (std::size_t g = 0; g < c.model.stages.size(); ++g) {
    const ir::Stage& stage = c.model.stages[g];
    for (std::size_t k = 0; k < stage.statements.size(); ++k) {
      const ir::Statement& st = stage.statements[k];
      Json s;
      s["stage"] = stage.kind == ir::StageKind::Init   ? "init"
                   : stage.kind == ir::StageKind::Step ? "step"
                                                       : stage.name;
      s["target"] = ir::target_name(c.model, st);
      s["at"] = where(file, st.loc);
      s["origins"] = Json::array();
      for (const ir::Origin& o : st.origins)
        s["origins"].push_back({{"effect", o.effect}, {"at", where(file, o.loc)}});
      s["update"] = c.facts.aliasing[g][k].reason;
      if (auto observed = c.facts.observed_steps.find({static_cast<int>(g), static_cast<int>(k)});
          observed != c.facts.observed_steps.end())
        s["runs"] = {{"observed_only", observed->second.observed_only},
                     {"reason", observed->second.reason}};
      s["accumulations"] = Json::array();
      for (const ir::Accumulate* acc : ir::accumulations_in(st)) {
        const SearchFact& fact = c.facts.neighbourhoods.at(acc->id);
        Json a = {{"heading", ir::accumulation_heading(c.model, st, *acc)},
                  {"search", fact.reason},
                  {"neighbours", fact.kind == SearchFact::Kind::Neighbours}};
        if (fact.kind == SearchFact::Kind::Neighbours) {
          a["newton"] = c.facts.symmetry.at(acc->id).newton;
          a["pairs"] = c.facts.symmetry.at(acc->id).reason;
          if (auto vector = c.facts.vector_terms.find(acc->id);
              vector != c.facts.vector_terms.end())
            a["terms"] = {{"vector", vector->second.vector},
                          {"arithmetic", ir::precision_name(vector->second.arithmetic)},
                          {"reason", vector->second.reason}};
        }
        if (auto fast = c.facts.fast_sums.find(acc->id); fast != c.facts.fast_sums.end())
          a["fast_sum"] = fast->second.reason;
        s["accumulations"].push_back(a);
      }
      out["statements"].push_back(s);
    }
  }
  return out.dump(2) + "\n";
}

}  // namespace partc
