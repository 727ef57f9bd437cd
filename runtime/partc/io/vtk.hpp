// partc/io/vtk.hpp: ParaView-readable output of particle sets.
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
// - Written from a SetView, in the runtime library (vtk.cpp): compiled once
//   whatever the set's types.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "partc/io/set_view.hpp"

namespace partc {

// `output F: v, rho every 100`: frames of set F hold id, the points, v and
// rho, every 100 steps.
struct FrameSpec {
  std::string set;
  std::vector<std::string> variables;
  std::int64_t every;
};

// Writes id, the points and `variables` (null: every variable).
void write_vtu(const std::string& path, const SetView& set,
               const std::vector<std::string>* variables = nullptr);

template <class Set>
void write_vtu(const std::string& path, const Set& set,
               const std::vector<std::string>* variables = nullptr) {
  write_vtu(path, view_of("", set), variables);
}

class VtkSeries {
 public:
  explicit VtkSeries(std::string prefix) : prefix_(std::move(prefix)) {}

  void write(const SetView& set, std::int64_t step, double time,
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
