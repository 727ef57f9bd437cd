// --explain for scenes: the text lives beside the instantiation that decided it.
#include <fmt/format.h>

#include "sema/scene.hpp"

namespace partc {

std::string explain_scene(const SceneReport& report, const SourceFile& file) {
  if (!report.is_scene()) return {};
  std::string out = report.kept.empty() && report.dropped.empty() ? "" : "effects kept:\n";
  for (const SceneReport::Instance& inst : report.kept) {
    std::string sets;
    for (const std::string& s : inst.sets) sets += (sets.empty() ? "" : ", ") + s;
    out += fmt::format("  {} ({} on {}, {})\n", inst.name, inst.module, sets,
                       file.line_reference(inst.use.begin));
  }
  for (const std::string& name : report.dropped) out += "  dropped: " + name + " (--drop)\n";
  out += "modules opened (no other module of the library was read):\n";
  for (const std::string& path : report.modules_opened) out += "  " + path + "\n";
  if (!report.placements.empty()) out += "statements placed at slots:\n";
  for (const SceneReport::Placement& p : report.placements) {
    const SceneReport::DroppedStatement* dropped = report.dropped_statement(p.statement);
    out += "  " + p.text + (dropped ? " -- dropped: nothing kept reads " + dropped->target : "") +
           "\n";
  }
  if (!report.variables.empty() || !report.dropped_statements.empty()) {
    out += "liveness (from the scene's statements, outputs and schedule):\n";
    for (const SceneReport::Decision& d : report.variables)
      out += fmt::format("  {}: {}, {}\n", d.what, d.kept ? "kept" : "dropped", d.why);
    for (const SceneReport::DroppedStatement& d : report.dropped_statements)
      out += fmt::format("  statement {} dropped ({}): nothing kept reads {}\n", d.name,
                         file.line_reference(d.loc.begin), d.target);
  }
  return out;
}

}  // namespace partc
