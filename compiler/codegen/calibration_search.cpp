// --profile: the searches a calibration variant walks instead of its
// statement's (see plan_calibration in codegen/kernel.cpp).
//
// A search is built at the largest radius of the sums it serves. Without an
// effect whose sums reach further than the rest (Coulomb at 4 beside LJ at
// 2.5), the --drop build asks its search for the smaller radius, and its
// walk examines (4 / 2.5)^3 = 4 times fewer candidates; a variant walking
// the step's search would time the walk at the larger radius and predict
// next to no saving. So such a variant walks a search of its own, which
// calibrate_profile builds before the timed rounds at the radius the --drop
// build would ask (the largest of the sums an effect left in still has),
// when that is nearer than the step's. It keeps the set's order
// (NeighbourSearch::Order::keep): the model's state stays as the run left
// it, and its output as a build without --profile writes it. The price is
// one index load per neighbour, and the arrays read out of the spatial
// order of the nearer cells: the variant can only be dearer than the --drop
// build's walk, so the predicted saving errs low.
//
// The --drop build also builds its search at the smaller radius, each time
// the positions change, and that can cost more or less than at the larger
// one: a cell list's build is linear in the particles and in its cells (one
// build, one thread, a loaded machine: 4000 atoms in a box of 16.8, 0.29 ms
// at 4.0 and 0.31 ms at 2.5; 1000 atoms in a box of 16, 0.06 ms at 4.0 (64
// cells) and 0.36 ms at 1.2 (1728 cells), a tenth of that model's step, e2e's
// profile_radii). So the builds are timed too,
// at either radius (Profile::calibrate_build), and their difference over the
// run's builds is added to the part's saving.
#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

#include "codegen/model_emitter.hpp"
#include "ir/terms.hpp"

namespace partc::codegen {

// The largest radius of some of a group's sums (indices into group.sums),
// each in its own statement's names outside its kernel (calibrate_profile's).
std::string ModelEmitter::group_radius(const SearchGroup& group,
                                       const std::vector<std::size_t>& sums) const {
  std::vector<std::string> radii;
  for (std::size_t k : sums) {
    const auto [g, s] = group.statements[k];
    const Statement& owner = m_.stages[g].statements[s];
    const std::string radius =
        radius_expression(facts_.neighbourhoods.at(group.sums[k]), owner, names_outside(owner));
    if (std::find(radii.begin(), radii.end(), radius) == radii.end()) radii.push_back(radius);
  }
  std::sort(radii.begin(), radii.end());  // the same radii, the same text
  std::string radius = radii.front();
  for (std::size_t k = 1; k < radii.size(); ++k)
    radius = "std::max(" + radius + ", " + radii[k] + ")";
  return radius;
}

// A variant of `whole` without its origins leaves_out: per search group it
// walks, the sums the --drop build of those effects would still have there
// (of this statement and of the others the group serves). Where those leave
// out some of the group's radii, the variant gets a calibration search (built
// only if their largest is smaller at run time).
void ModelEmitter::plan_calibration_searches(Kernel& variant, const Statement& whole,
                                             const std::vector<std::size_t>& leaves_out,
                                             Calibration& calibration) {
  // Verlet lists have no such search: a VerletList build reorders its set
  // (its half lists' parallel slabs are runs of the set's order), so lists
  // of its own at the smaller radius would permute the model's state. Their
  // variants walk the step's lists, built at the largest radius.
  if (whole.schedule.skin) return;
  std::vector<std::string> dropped;
  for (std::size_t o : leaves_out) dropped.push_back(whole.origins[o].effect);
  auto kept = [&](const Statement& owner, int sum) {
    if (owner.origins.empty()) return true;  // the scene's own statement
    for (std::size_t o : origins_of_sum(owner, sum))
      if (std::find(dropped.begin(), dropped.end(), owner.origins[o].effect) == dropped.end())
        return true;
    return false;
  };
  std::vector<int> groups;
  for (const Accumulate* acc : accumulations_in(variant.st->value)) {
    const auto group = facts_.searches.group_of.find(acc->id);
    if (facts_.neighbourhoods.at(acc->id).kind != SearchFact::Kind::Neighbours ||
        group == facts_.searches.group_of.end() ||
        std::find(groups.begin(), groups.end(), group->second) != groups.end())
      continue;
    groups.push_back(group->second);
  }
  for (int g : groups) {
    const SearchGroup& group = facts_.searches.groups[g];
    std::vector<std::size_t> all, left;
    for (std::size_t k = 0; k < group.sums.size(); ++k) {
      all.push_back(k);
      const auto [stage, s] = group.statements[k];
      if (kept(m_.stages[stage].statements[s], group.sums[k])) left.push_back(k);
    }
    // No sum there that an effect left in owns (origins_of_sum places none,
    // as in a fused statement's inlined sums): no radius to build at, so the
    // variant walks the step's search, as one without a calibration search.
    if (left.empty()) continue;
    const std::string radius = group_radius(group, left), whole_radius = group_radius(group, all);
    if (radius == whole_radius) continue;  // the same radii: the step's search is the variant's
    std::string member = "profile_" + searches_[group.search] + "without";
    for (const std::string& effect : dropped) member += "_" + cpp_name(effect);
    member = members_.fresh(member + "_");
    variant.calibration_searches[g] = member;
    calibration.searches.push_back(
        {member, g, calibration.leaves_out.size() - 1, variant.name, radius, whole_radius});
  }
}

// In calibrate_profile, before the timed rounds: each calibration search
// built at its variant's radius when that is nearer than the group's, else
// none (the variant walks the step's search); and its builds timed against
// builds at the group's radius, for what the --drop build's builds save.
void ModelEmitter::build_calibration_searches(const Calibration& calibration) {
  const std::string type = fmt::format("partc::NeighbourSearch<{}>", m_.dim);
  for (const CalibrationSearch& c : calibration.searches) {
    const SearchGroup& group = facts_.searches.groups[c.group];
    const PlannedSearch& plan = facts_.searches.searches[group.search];
    const std::string keep = fmt::format(
        "{}, {}::Order::keep",
        plan.structure == SearchChoice::Auto ? type + "::default_margin"
                                             : type + "::Kind::" + search_choice_name(plan.structure),
        type);
    const std::string& set = set_member_[plan.set];
    linef("{}.reset();", c.member);
    line("{");
    linef("const double radius = {};", c.radius);
    linef("const double whole = {};", c.whole);
    line("if (radius < whole) {");
    linef("{}.emplace({}).build(domain_, radius, {});", c.member, keep, set);
    linef("{} at_whole{{{}}};", type, keep);
    linef("profile_.calibrate_build({}, {}, {}, rounds, [&] {{ at_whole.build(domain_, whole, {}); }},",
          calibration.profiled, c.part, group.search, set);
    linef("[&] {{ {}->build(domain_, radius, {}); }});", c.member, set);
    line("}");
    line("}");
  }
}

void ModelEmitter::calibration_search_members() {
  for (const Calibration& calibration : calibrations_)
    for (const CalibrationSearch& c : calibration.searches)
      linef("std::optional<partc::NeighbourSearch<{}>> {};  // {} walks it (calibrate_profile)",
            m_.dim, c.member, c.variant);
}

}  // namespace partc::codegen
