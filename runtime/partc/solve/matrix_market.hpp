// partc/solve/matrix_market.hpp: a model's assembled system as Matrix Market
// files (math.nist.gov/MatrixMarket/formats.html), which scipy.io.mmread,
// Matlab's mmread and the example drivers of many solver libraries read: how
// an operator gets to AMG and other outside solvers.
//
//   partc::write_matrix_market("A.mtx", A);  // SparseMatrixCRS: coordinate real general
//   partc::write_matrix_market("K.mtx", K);  // Eigen::MatrixXd: array real general
//   partc::write_matrix_market("f.mtx", f, "right-hand side of solve w");  // a vector: n x 1 array
//
// Layouts: coordinate files have the line "rows cols entries" after the
// header and comments, then "i j value" per stored entry, i and j 1-based, in
// storage order (row by row for CRS); array files have "rows cols", then every
// value, column by column (a vector is one column).
// Surprises:
// - Values have 17 significant digits in scientific notation
//   ("1.0000000000000001e-01"): enough to read back the same double, and
//   never a locale's decimal comma (std::to_chars).
// - Stored zeros of a sparse matrix are written, as entries like any other.
// - The comment may have several lines; each becomes a "%" line.
// - Files go through a ".tmp" file and a rename (output_file.hpp): a failed
//   write leaves no half-written matrix behind.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <charconv>
#include <cstddef>
#include <ostream>
#include <string>

#include "partc/io/output_file.hpp"

namespace partc {

namespace detail {

inline void append_matrix_market_value(std::string& line, double x) {
  char buffer[32];
  line.append(
      buffer,
      std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::scientific, 16).ptr);
}

inline void write_matrix_market_header(std::ostream& out, const char* layout,
                                       const std::string& comment) {
  out << "%%MatrixMarket matrix " << layout << " real general\n";
  std::size_t start = 0;
  while (start < comment.size()) {
    const std::size_t end = std::min(comment.find('\n', start), comment.size());
    out << "% " << comment.substr(start, end - start) << '\n';
    start = end + 1;
  }
}

}  // namespace detail

inline void write_matrix_market(const std::string& path, const Eigen::Ref<const Eigen::MatrixXd>& A,
                                const std::string& comment = "") {
  detail::write_file_atomically(path, [&](std::ostream& out) {
    detail::write_matrix_market_header(out, "array", comment);
    out << A.rows() << ' ' << A.cols() << '\n';
    std::string line;
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      for (Eigen::Index i = 0; i < A.rows(); ++i) {
        line.clear();
        detail::append_matrix_market_value(line, A(i, j));
        line += '\n';
        out << line;
      }
  });
}

template <int Options, class StorageIndex>
void write_matrix_market(const std::string& path,
                         const Eigen::SparseMatrix<double, Options, StorageIndex>& A,
                         const std::string& comment = "") {
  using Matrix = Eigen::SparseMatrix<double, Options, StorageIndex>;
  detail::write_file_atomically(path, [&](std::ostream& out) {
    detail::write_matrix_market_header(out, "coordinate", comment);
    out << A.rows() << ' ' << A.cols() << ' ' << A.nonZeros() << '\n';
    std::string line;
    for (Eigen::Index k = 0; k < A.outerSize(); ++k)
      for (typename Matrix::InnerIterator entry(A, k); entry; ++entry) {
        line = std::to_string(entry.row() + 1) + ' ' + std::to_string(entry.col() + 1) + ' ';
        detail::append_matrix_market_value(line, entry.value());
        line += '\n';
        out << line;
      }
  });
}

}  // namespace partc
