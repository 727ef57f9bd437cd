// lammps_log.hpp: what the benchmarks read from a LAMMPS log (.ci/bench runs
// lmp and hands the logs over as arguments): the pair_style and neigh_modify
// lines it echoes, its thermo table, the loop time and the timing breakdown.
// Shared by bench_lj and bench_compose.
//
//   std::optional<LammpsLog> log = read_lammps_log(path);
//
// Surprises: a column the thermo table lacks reads as 0 (E_vdwl and E_coul
// are there only when the input asks for them); a line repeated in the log
// (pair_style, a second run) counts as its last occurrence, except that the
// thermo rows of every run are kept, in order.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace bench {

// One row of the thermo table; energies per atom, as LAMMPS prints them in LJ
// units. The benchmarks keep their own thermo (computed by hand) in it too.
struct Thermo {
  int step;
  double temperature, e_pair, e_vdwl, e_coul, total;  // Temp, E_pair, E_vdwl, E_coul, TotEng
};

// The row of `step`, or nullptr.
inline const Thermo* at_step(const std::vector<Thermo>& thermo, int step) {
  for (const Thermo& t : thermo)
    if (t.step == step) return &t;
  return nullptr;
}

struct LammpsLog {
  std::string pair_style;    // the arguments of its pair_style line
  std::string neigh_modify;  // the arguments of its neigh_modify line
  double loop_seconds = -1.0;
  double pair_seconds = -1.0, neigh_seconds = -1.0;  // of the loop, from its timing breakdown
  int builds = -1;                                   // "Neighbor list builds"
  std::vector<Thermo> thermo;
};

// The log at path, or nothing if it cannot be read or has no loop time or no thermo table.
inline std::optional<LammpsLog> read_lammps_log(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  LammpsLog log;
  std::vector<std::string> columns;  // of the thermo table being read, else empty
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string first;
    words >> first;
    if (first == "pair_style") {
      std::getline(words >> std::ws, log.pair_style);
    } else if (first == "neigh_modify") {
      std::getline(words >> std::ws, log.neigh_modify);
    } else if (first == "Step") {
      columns = {first};
      for (std::string c; words >> c;) columns.push_back(c);
    } else if (first == "Loop") {  // Loop time of X on 1 procs for 100 steps with 32000 atoms
      std::sscanf(line.c_str(), "Loop time of %lf", &log.loop_seconds);
      columns.clear();
    } else if ((first == "Pair" || first == "Neigh") && line.find('|') != std::string::npos) {
      // Section |  min time  |  avg time  |  max time  |%varavg| %total
      double min_time = -1.0;
      std::sscanf(line.c_str() + line.find('|') + 1, "%lf", &min_time);
      (first == "Pair" ? log.pair_seconds : log.neigh_seconds) =
          min_time;  // one process: min = avg
    } else if (line.rfind("Neighbor list builds = ", 0) == 0) {
      log.builds = std::atoi(line.c_str() + 23);
    } else if (!columns.empty()) {
      std::map<std::string, double> row;
      std::istringstream values(line);
      for (const std::string& c : columns) values >> row[c];
      if (!values) continue;
      log.thermo.push_back({static_cast<int>(row["Step"]), row["Temp"], row["E_pair"],
                            row["E_vdwl"], row["E_coul"], row["TotEng"]});
    }
  }
  if (log.loop_seconds < 0 || log.thermo.empty()) return std::nullopt;
  return log;
}

}  // namespace bench
