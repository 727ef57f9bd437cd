// A generated seed velocity update (md_velocity.part.in, in any of its
// schedules) driven from C++: the seed's points loaded as its particles, ids
// 0..N-1 in input order, and v read back by id, so that builds whose
// searches sort the particles differently can be compared point by point.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "partc/io/csv.hpp"
#include "partc/vec.hpp"

namespace bench {

template <class Model>
void load_seed_points(Model& model, const std::vector<partc::Vec<2>>& points, double rc, double c) {
  model.params().N = static_cast<std::int64_t>(points.size());
  model.params().c = c;
  model.params().rc = rc;
  partc::CsvTable table;
  table.header = {"id", "p_0", "p_1"};
  table.rows.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    table.rows.push_back({static_cast<double>(i), points[i][0], points[i][1]});
  model.load({{"P", table}});
}

// v by particle id, widened to double whatever its storage.
template <class Model>
std::vector<partc::Vec<2>> seed_velocities(const Model& model) {
  const auto& set = model.P();
  const auto& v = set.template get<typename Model::P_v>();
  std::vector<partc::Vec<2>> by_id(set.size());
  for (std::size_t k = 0; k < set.size(); ++k)
    by_id[static_cast<std::size_t>(set.ids()[k])] = partc::Vec<2>{{v[k][0], v[k][1]}};
  return by_id;
}

}  // namespace bench
