// partc/vtk.hpp: ParaView-readable output of particle sets.
//
//   write_vtu(path, set)     one UnstructuredGrid (.vtu) of VTK_VERTEX cells
//   VtkSeries series(prefix) PREFIX_000042.vtu per written step, plus
//                            PREFIX.pvd listing them with their times
//   FrameSpec                which variables a set's frames hold, how often
//                            (a model's `output SET: ...`)
//
// Points and every point-data array are in id order, so that particle k of
// one file is particle k of the next even when the set reorders itself.
// Surprises:
// - VTK points are 3D: positions of a 1D or 2D set are padded with 0, and a
//   set of more than 3 dimensions shows its first 3 coordinates as points and
//   all of them as the point-data array "p". Vec variables likewise have 3
//   components up to 3D (padded), D above.
// - ASCII format: large but diffable, and exact (shortest round-trip numbers).
// - Each file goes through a ".tmp" file and a rename, and the .pvd is rewritten
//   after every step, so whatever is on disk is complete and readable even if
//   the run stops early.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "partc/csv.hpp"  // detail::id_order, append_number
#include "partc/finite.hpp"
#include "partc/output_file.hpp"

namespace partc {

namespace detail {

// text with & < > " written as XML entities.
std::string xml_escape(const std::string& text);

template <class S>
constexpr const char* vtk_type_name() {
  using Component = typename StorageTraits<S>::component_type;
  if constexpr (std::is_same_v<Component, std::int64_t>)
    return "Int64";
  else if constexpr (std::is_same_v<Component, std::uint8_t>)
    return "UInt8";
  else if constexpr (std::is_same_v<Component, float>)
    return "Float32";  // stored as float (a schedule's precision = float)
  else
    return "Float64";
}

// Appends `components` numbers for one value: its own, then zeros.
template <class S>
void append_vtk_value(std::string& line, const S& value, int components) {
  for (int k = 0; k < components; ++k) {
    if (k > 0) line += ' ';
    if (k < StorageTraits<S>::components)
      append_number(line, StorageTraits<S>::component(value, k));
    else
      line += '0';
  }
}

// A DataArray of `count` tuples; append_tuple(line, r) appends the r-th.
template <class AppendTuple>
void write_vtk_array(std::ostream& out, const char* type, const std::string& name, int components,
                     std::size_t count, AppendTuple&& append_tuple) {
  out << "        <DataArray type=\"" << type << "\" Name=\"" << xml_escape(name)
      << "\" NumberOfComponents=\"" << components << "\" format=\"ascii\">\n";
  std::string line;
  for (std::size_t r = 0; r < count; ++r) {
    line.clear();
    append_tuple(line, r);
    line += '\n';
    out << line;
  }
  out << "        </DataArray>\n";
}

}  // namespace detail

// `output F: v, rho every 100`: frames of set F hold id, the points, v and
// rho, every 100 steps.
struct FrameSpec {
  std::string set;
  std::vector<std::string> variables;
  std::int64_t every;
};

// Writes id, the points and `variables` (null: every variable).
template <class Set>
void write_vtu(const std::string& path, const Set& set,
               const std::vector<std::string>* variables = nullptr) {
  constexpr int dim = Set::dim;
  const auto order = detail::id_order(set);
  const std::size_t n = order.size();
  detail::write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
        << "      <PointData>\n";
    detail::write_vtk_array(out, "Int64", "id", 1, n, [&](std::string& line, std::size_t r) {
      detail::append_number(line, set.ids()[order[r]]);
    });
    set.for_each_variable([&](const char* name, const auto& values) {
      using S = typename std::decay_t<decltype(values)>::value_type;
      if (std::strcmp(name, "p") == 0 && dim <= 3) return;  // the points say it all
      if (variables && std::strcmp(name, "p") != 0 &&
          std::find(variables->begin(), variables->end(), name) == variables->end())
        return;
      const int components =
          StorageTraits<S>::is_vec ? std::max(StorageTraits<S>::components, 3) : 1;
      detail::write_vtk_array(out, detail::vtk_type_name<S>(), name, components, n,
                              [&](std::string& line, std::size_t r) {
                                detail::append_vtk_value(line, values[order[r]], components);
                              });
    });
    out << "      </PointData>\n"
        << "      <Points>\n";
    using Position = typename Set::position_type;
    detail::write_vtk_array(out, detail::vtk_type_name<Position>(), "Points", 3, n,
                            [&](std::string& line, std::size_t r) {
                              detail::append_vtk_value(line, set.positions()[order[r]], 3);
                            });
    out << "      </Points>\n"
        << "      <Cells>\n";
    // One VTK_VERTEX (type 1) cell per point: ParaView draws points only as cells.
    detail::write_vtk_array(out, "Int64", "connectivity", 1, n,
                            [](std::string& line, std::size_t r) {
                              detail::append_number(line, static_cast<std::int64_t>(r));
                            });
    detail::write_vtk_array(out, "Int64", "offsets", 1, n, [](std::string& line, std::size_t r) {
      detail::append_number(line, static_cast<std::int64_t>(r + 1));
    });
    detail::write_vtk_array(out, "UInt8", "types", 1, n,
                            [](std::string& line, std::size_t) { line += '1'; });
    out << "      </Cells>\n"
        << "    </Piece>\n"
        << "  </UnstructuredGrid>\n"
        << "</VTKFile>\n";
  });
}

class VtkSeries {
 public:
  explicit VtkSeries(std::string prefix) : prefix_(std::move(prefix)) {}

  template <class Set>
  void write(const Set& set, std::int64_t step, double time,
             const std::vector<std::string>* variables = nullptr) {
    write_vtu(frame_path(step), set, variables);
    add_frame(step, time);
  }

 private:
  std::string frame_path(std::int64_t step) const;
  // Lists the frame of `step` in prefix.pvd, after the earlier ones.
  void add_frame(std::int64_t step, double time);

  std::string prefix_;
  std::vector<std::pair<double, std::string>> frames_;  // (time, .vtu file name)
};

}  // namespace partc
