// partc/thermo_log.hpp: the time series of a model's logged observables, as
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
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "partc/csv.hpp"

namespace partc {

class ThermoLog {
 public:
  // columns: the names of a row's values, the step first. terminal: where
  // progress rows go (null: nowhere). csv_path: "" for no file; csv_every >= 1.
  ThermoLog(std::vector<std::string> columns, std::ostream* terminal, std::int64_t every,
            const std::string& csv_path, std::int64_t csv_every = 1)
      : columns_(std::move(columns)),
        terminal_(terminal),
        every_(every),
        path_(csv_path),
        csv_every_(csv_every) {
    for (const std::string& c : columns_)
      widths_.push_back(std::max<int>(12, static_cast<int>(c.size()) + 2));
    if (path_.empty()) return;
    csv_.open(path_, std::ios::binary | std::ios::trunc);
    if (!csv_) throw std::runtime_error("cannot open '" + path_ + "': " + std::strerror(errno));
    for (std::size_t k = 0; k < columns_.size(); ++k) csv_ << (k ? "," : "") << columns_[k];
    csv_ << "\n";
    check_csv();
  }

  bool uses(std::int64_t step) const { return writes(step) || shows(step); }

  void row(std::int64_t step, const std::vector<double>& values) {
    if (writes(step)) {
      write(values);
      written_ = step;
    }
    if (shows(step)) {
      show(values);
      shown_ = step;
    }
    last_ = values;
    last_step_ = step;
    first_ = false;
  }

  void close() {
    if (last_ && shown_ != last_step_) show(*last_);
    if (last_ && csv_.is_open() && written_ != last_step_) write(*last_);
    last_.reset();
    if (csv_.is_open()) {
      csv_.close();
      if (!csv_) throw std::runtime_error("cannot write '" + path_ + "'");
    }
  }

 private:
  bool writes(std::int64_t step) const {
    return csv_.is_open() && (first_ || step % csv_every_ == 0);
  }
  bool shows(std::int64_t step) const {
    return terminal_ && every_ > 0 && (first_ || step % every_ == 0);
  }

  void write(const std::vector<double>& values) {
    std::string line;
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (k) line += ',';
      detail::append_number(line, values[k]);
    }
    csv_ << line << "\n" << std::flush;
    check_csv();
  }

  void show(const std::vector<double>& values) {
    if (!terminal_ || every_ == 0) return;
    std::ostringstream text;
    if (!header_shown_) {
      for (std::size_t k = 0; k < columns_.size(); ++k)
        text << std::setw(widths_[k]) << columns_[k];
      text << "\n";
      header_shown_ = true;
    }
    text << std::setprecision(6);
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (k == 0)
        text << std::setw(widths_[k]) << static_cast<std::int64_t>(values[k]);
      else
        text << std::setw(widths_[k]) << values[k];
    }
    *terminal_ << text.str() << "\n" << std::flush;
  }

  void check_csv() {
    if (!csv_) throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
  }

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
