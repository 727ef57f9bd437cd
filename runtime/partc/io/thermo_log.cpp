// partc/io/thermo_log.cpp: ThermoLog (thermo_log.hpp says what it shows and writes).
#include "partc/io/thermo_log.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "partc/io/csv.hpp"  // detail::append_number

namespace partc {

ThermoLog::ThermoLog(std::vector<std::string> columns, std::ostream* terminal, std::int64_t every,
                     const std::string& csv_path, std::int64_t csv_every)
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

void ThermoLog::row(std::int64_t step, const std::vector<double>& values) {
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

void ThermoLog::close() {
  if (last_ && shown_ != last_step_) show(*last_);
  if (last_ && csv_.is_open() && written_ != last_step_) write(*last_);
  last_.reset();
  if (csv_.is_open()) {
    csv_.close();
    if (!csv_) throw std::runtime_error("cannot write '" + path_ + "'");
  }
}

void ThermoLog::write(const std::vector<double>& values) {
  std::string line;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k) line += ',';
    detail::append_number(line, values[k]);
  }
  csv_ << line << "\n" << std::flush;
  check_csv();
}

void ThermoLog::show(const std::vector<double>& values) {
  if (!terminal_ || every_ == 0) return;
  std::ostringstream text;
  if (!header_shown_) {
    for (std::size_t k = 0; k < columns_.size(); ++k) text << std::setw(widths_[k]) << columns_[k];
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

void ThermoLog::check_csv() {
  if (!csv_) throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
}

}  // namespace partc
