#include "sema/sema.hpp"

#include "sema/checker.hpp"

namespace partc {

ir::Model build_ir(const ast::Program& program, const SourceFile& file) {
  return sema::Sema(file).run(program);
}

}  // namespace partc
