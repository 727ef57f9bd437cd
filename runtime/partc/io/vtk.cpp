// partc/io/vtk.cpp: VTK output of a SetView, compiled once for every set type.
#include "partc/io/vtk.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ostream>

#include "partc/io/csv.hpp"  // detail::id_order, append_number
#include "partc/io/output_file.hpp"

namespace partc {

namespace {

// text with & < > " written as XML entities.
std::string xml_escape(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

// The DataArray type of a column: a Vec<D, T>'s is T's.
const char* vtk_type_name(Element element) {
  switch (element) {
    case Element::i64: return "Int64";
    case Element::u8: return "UInt8";
    case Element::f32: return "Float32";  // stored as float (a schedule's precision = float)
    case Element::f64: break;
  }
  return "Float64";
}

// Appends `components` numbers for one value: its own, then zeros.
template <class S>
void append_vtk_value(std::string& line, const S& value, int components) {
  for (int k = 0; k < components; ++k) {
    if (k > 0) line += ' ';
    if (k < StorageTraits<S>::components)
      detail::append_number(line, StorageTraits<S>::component(value, k));
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

// The column's values in `order`, `components` numbers each.
void write_vtk_column(std::ostream& out, const char* name, const ColumnView& column,
                      int components, const std::vector<std::size_t>& order) {
  visit_column(column, [&](const auto* values) {
    write_vtk_array(out, vtk_type_name(column.element), name, components, order.size(),
                    [&](std::string& line, std::size_t r) {
                      append_vtk_value(line, values[order[r]], components);
                    });
  });
}

}  // namespace

void write_vtu(const std::string& path, const SetView& set,
               const std::vector<std::string>* variables) {
  const auto order = detail::id_order(set.ids, set.size);
  const std::size_t n = order.size();
  detail::write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
        << "      <PointData>\n";
    write_vtk_array(out, "Int64", "id", 1, n, [&](std::string& line, std::size_t r) {
      detail::append_number(line, set.ids[order[r]]);
    });
    for (const ColumnView& column : set.columns) {
      const bool positions = std::strcmp(column.name, "p") == 0;
      if (positions && set.dim <= 3) continue;  // the points say it all
      if (variables && !positions &&
          std::find(variables->begin(), variables->end(), column.name) == variables->end())
        continue;
      write_vtk_column(out, column.name, column, column.is_vec ? std::max(column.components, 3) : 1,
                       order);
    }
    out << "      </PointData>\n"
        << "      <Points>\n";
    write_vtk_column(out, "Points", set.columns.front(), 3, order);
    out << "      </Points>\n"
        << "      <Cells>\n";
    // One VTK_VERTEX (type 1) cell per point: ParaView draws points only as cells.
    write_vtk_array(out, "Int64", "connectivity", 1, n, [](std::string& line, std::size_t r) {
      detail::append_number(line, static_cast<std::int64_t>(r));
    });
    write_vtk_array(out, "Int64", "offsets", 1, n, [](std::string& line, std::size_t r) {
      detail::append_number(line, static_cast<std::int64_t>(r + 1));
    });
    write_vtk_array(out, "UInt8", "types", 1, n,
                    [](std::string& line, std::size_t) { line += '1'; });
    out << "      </Cells>\n"
        << "    </Piece>\n"
        << "  </UnstructuredGrid>\n"
        << "</VTKFile>\n";
  });
}

std::string VtkSeries::frame_path(std::int64_t step) const {
  char number[24];
  std::snprintf(number, sizeof number, "%06lld", static_cast<long long>(step));
  return prefix_ + "_" + number + ".vtu";
}

void VtkSeries::add_frame(std::int64_t step, double time) {
  // ParaView resolves the file names of a .pvd relative to the .pvd itself.
  frames_.emplace_back(time, std::filesystem::path(frame_path(step)).filename().string());
  detail::write_file_atomically(prefix_ + ".pvd", [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <Collection>\n";
    for (const auto& [frame_time, file] : frames_) {
      std::string timestep;
      detail::append_number(timestep, frame_time);
      out << "    <DataSet timestep=\"" << timestep << "\" part=\"0\" file=\""
          << xml_escape(file) << "\"/>\n";
    }
    out << "  </Collection>\n"
        << "</VTKFile>\n";
  });
}

}  // namespace partc
