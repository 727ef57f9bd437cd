// partc/io/csv_write.cpp: a set written as CSV, through its SetView, compiled
// once for every model's set types (csv.hpp says what the file holds).
#include <algorithm>
#include <numeric>

#include "partc/io/csv.hpp"

namespace partc {

namespace detail {

std::vector<std::string> csv_column_names(const std::string& name, bool is_vec, int components) {
  if (!is_vec) return {name};
  std::vector<std::string> names;
  for (int k = 0; k < components; ++k) names.push_back(name + "_" + std::to_string(k));
  return names;
}

std::vector<std::string> csv_columns_of(const SetView& set) {
  std::vector<std::string> columns = {"id"};
  for (const ColumnView& column : set.columns)
    for (auto& name : csv_column_names(column.name, column.is_vec, column.components))
      columns.push_back(std::move(name));
  return columns;
}

std::vector<std::size_t> id_order(const std::int64_t* ids, std::size_t n) {
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return ids[a] < ids[b]; });
  return order;
}

}  // namespace detail

void write_csv(const std::string& path, const SetView& set) {
  const auto order = detail::id_order(set.ids, set.size);
  detail::write_file_atomically(path, [&](std::ostream& out) {
    std::string line;
    for (const auto& column : detail::csv_columns_of(set))
      line += (line.empty() ? "" : ",") + column;
    out << line << '\n';
    for (const std::size_t i : order) {
      line.clear();
      detail::append_number(line, set.ids[i]);
      for (const ColumnView& column : set.columns)
        visit_column(column, [&](const auto* values) {
          using S = std::remove_const_t<std::remove_pointer_t<decltype(values)>>;
          for (int k = 0; k < StorageTraits<S>::components; ++k) {
            line += ',';
            detail::append_number(line, StorageTraits<S>::component(values[i], k));
          }
        });
      line += '\n';
      out << line;
    }
  });
}

}  // namespace partc
