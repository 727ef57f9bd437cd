// partc/io/thermo_log.hpp: the time series of a model's logged observables, as
// LAMMPS's thermo output shows them: a header and a row every few steps on
// the terminal, and every row in a CSV file that plotting tools load.
//
//   partc::ThermoLog log({"step", "t", "e_kin"}, &std::cout, 10, "run.csv");
//   if (log.uses(step)) log.row(step, {double(step), t, e_kin});  // it picks which to show
//   log.close();
//
// Surprises:
// - The CSV file gets every row it is given (every csv_every-th step, and the
//   first and the last, when csv_every > 1), flushed as it goes, so a run
//   that stops early (a blow-up, a signal) keeps its series up to that
//   point: the file is a record of the run, not its result, and is written
//   in place rather than through a temporary.
// - uses(step) says whether a row of that step would be written or shown; a
//   caller may compute rows only for those steps and the last one, whose row
//   close() shows and writes if no interval did.
// - The terminal shows a row when step % every == 0, and always the first
//   and the last row (close() prints a last row not yet shown); every = 0
//   shows none.
// - Numbers in the CSV round-trip exactly (shortest form); the terminal
//   shows 6 significant digits in columns wide enough for each name.
// - Compiled once, in the runtime library (thermo_log.cpp).
#pragma once

#include <cstdint>
#include <fstream>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace partc {

class ThermoLog {
 public:
  // columns: the names of a row's values, the step first. terminal: where
  // progress rows go (null: nowhere). csv_path: "" for no file; csv_every >= 1.
  ThermoLog(std::vector<std::string> columns, std::ostream* terminal, std::int64_t every,
            const std::string& csv_path, std::int64_t csv_every = 1);

  bool uses(std::int64_t step) const { return writes(step) || shows(step); }

  void row(std::int64_t step, const std::vector<double>& values);

  void close();

 private:
  bool writes(std::int64_t step) const {
    return csv_.is_open() && (first_ || step % csv_every_ == 0);
  }
  bool shows(std::int64_t step) const {
    return terminal_ && every_ > 0 && (first_ || step % every_ == 0);
  }

  void write(const std::vector<double>& values);

  void show(const std::vector<double>& values);

  void check_csv();

  std::vector<std::string> columns_;
  std::vector<int> widths_;
  std::ostream* terminal_;
  std::int64_t every_;
  std::string path_;
  std::int64_t csv_every_;
  std::ofstream csv_;
  bool first_ = true, header_shown_ = false;
  std::int64_t shown_ = -1, written_ = -1, last_step_ = -1;
  std::optional<std::vector<double>> last_;  // the latest row, for close()
};

}  // namespace partc
