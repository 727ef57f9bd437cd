// Which functions and consts a model reads, and dropping those that only
// removed code read.
//
// A pass that removes code (fold_conditions, fold_zero_terms) can leave a
// function or a const that only the removed code read: a kernel whose branch
// an effect's const parameter did not choose, or that parameter itself.
// Comparing what is read before such passes and after says which; those are
// not emitted. A declaration nothing read to begin with (a scene's own
// function it never calls) is the scene's business and stays.
#pragma once

#include <string>
#include <vector>

#include "ir/ir.hpp"

namespace partc::ir {

// Indexed as Model::functions and Model::consts.
struct DeclarationsRead {
  std::vector<bool> functions, consts;
};

// What the model's statements, params, sets, observables, timestep, log and
// frames read, and through them the functions' bodies and consts' values.
DeclarationsRead declarations_read(const Model& model);

struct DroppedDeclaration {
  std::string kind;  // "fn" or "const"
  std::string name;
  Location loc;
};

// Removes the functions and consts `before` read and `model` reads no more,
// renumbering references to the others; returns them in declaration order.
std::vector<DroppedDeclaration> drop_unread_declarations(Model& model,
                                                          const DeclarationsRead& before);

}  // namespace partc::ir
