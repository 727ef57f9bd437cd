#include "sema/sema.hpp"

#include "sema/checker.hpp"

namespace partc {

ir::Model build_ir(const ast::Program& program, const SourceFile& file,
                   std::vector<Diagnostic>& warnings) {
  sema::Sema sema(file);
  ir::Model model = sema.run(program);
  warnings = sema.warnings();
  return model;
}

}  // namespace partc
