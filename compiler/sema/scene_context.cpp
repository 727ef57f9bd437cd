// A mistake in a module's text is reported where it is, in the module; the
// note says which of the scene's instances brought it in, and from which
// use line, since the same module may serve several scenes and instances.
#include <fmt/format.h>

#include "sema/scene.hpp"

namespace partc {

void add_scene_context(std::vector<Diagnostic>& diagnostics, const SceneReport& report,
                       const SourceFile& file) {
  for (Diagnostic& d : diagnostics) {
    if (!d.context.empty() || file.file_of(d.loc.begin) == 0) continue;
    std::string uses;
    for (const SceneReport::Instance& inst : report.kept)
      if (inst.path == file.path_of(d.loc.begin))
        uses += fmt::format("{}effect {}, used at {}:{}", uses.empty() ? "" : "; ", inst.name,
                            file.path_of(inst.use.begin), file.line_column(inst.use.begin).line);
    if (!uses.empty()) d.context = "in " + uses;
  }
}

}  // namespace partc
