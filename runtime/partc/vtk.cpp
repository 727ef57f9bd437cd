// partc/vtk.cpp: the parts of VTK output that do not depend on a set's type.
#include "partc/vtk.hpp"

#include <cstdio>
#include <filesystem>

namespace partc {

namespace detail {

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

// The DataArray type of a variable stored as S: a Vec<D, T> is T's.

}  // namespace detail

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
          << detail::xml_escape(file) << "\"/>\n";
    }
    out << "  </Collection>\n"
        << "</VTKFile>\n";
  });
}

}  // namespace partc
