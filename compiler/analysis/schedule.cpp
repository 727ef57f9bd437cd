// Decides whether each schedule entry applies to something.
//
// A schedule says how a statement's neighbourhood sums search (a forced
// structure, Verlet lists with a skin) and compute their pair terms
// (arithmetic). It runs after the neighbourhood analysis because only that
// analysis knows which sums are neighbourhood sums: `search = kd_tree` on a
// statement whose sums are all dense would silently do nothing, so it is an
// error instead.
#include "analysis/schedule.hpp"

#include "ir/visitor.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace {
// The neighbourhood sums of a statement, and whether one runs over another set.
class NeighbourhoodSums : public ir::Visitor {
 public:
  NeighbourhoodSums(const NeighbourhoodReport& report, const ir::Statement& st)
      : report_(report), st_(st) {}
  bool found = false, over_other_set = false;
  using ir::Visitor::visit;

 protected:
  void visit(const ir::Accumulate& n) override {
    if (report_.at(n.id).kind != SearchFact::Kind::Neighbours) return;
    found = true;
    over_other_set |= st_.labels[n.label].set != st_.set;
  }

 private:
  const NeighbourhoodReport& report_;
  const ir::Statement& st_;
};
}  // namespace

void check_schedule(const ir::Model& model, const NeighbourhoodReport& neighbourhoods) {
  std::vector<Diagnostic> errors;
  for (const ir::Stage& stage : model.stages)
    for (const ir::Statement& st : stage.statements) {
      if (st.schedule.loc.end == 0) continue;
      NeighbourhoodSums sums(neighbourhoods, st);
      sums.visit(st.value);
      sums.visit(st.solve_operator);
      const bool searching = st.schedule.skin || st.schedule.search != ir::SearchChoice::Auto ||
                             st.schedule.sharing != ir::Sharing::Auto;
      if (st.solve_operator && st.schedule.skin)
        errors.push_back({st.schedule.loc, "a solve takes no skin",
                          "its matrix is assembled once per solve; schedule its search instead"});
      else if (searching && !sums.found)
        errors.push_back({st.schedule.loc,
                          "statement '" + st.name + "' has no neighbourhood sum to schedule",
                          "search, sharing and skin apply to sums whose condition bounds |dx|, "
                          "like sum(j, |dx| < rc, ...)"});
      else if (st.schedule.arithmetic_loc.end != 0 && !sums.found)
        errors.push_back({st.schedule.arithmetic_loc,
                          "statement '" + st.name + "' has no neighbourhood sum for arithmetic",
                          "arithmetic chooses how the pair terms of sums like "
                          "sum(j, |dx| < rc, ...) are computed"});
      else if (st.schedule.skin && sums.over_other_set)
        errors.push_back({st.schedule.loc,
                          "a skin (Verlet lists) needs the sums of '" + st.name +
                              "' to run over its own particle set",
                          "lists are kept per particle of one set; schedule the search instead"});
      else if (st.schedule.skin && st.schedule.sharing != ir::Sharing::Auto)
        errors.push_back({st.schedule.loc,
                          "statement '" + st.name + "' has both a skin and a sharing",
                          "its Verlet lists are its own, shared with no search; drop one"});
      else if (st.schedule.skin && st.schedule.search != ir::SearchChoice::Auto)
        errors.push_back({st.schedule.loc,
                          "statement '" + st.name + "' has both a skin and a search",
                          "Verlet lists are built with the automatic search; drop one"});
    }
  if (!errors.empty()) throw CompileError(errors);
}

}  // namespace partc
