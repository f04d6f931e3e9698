#pragma once
// What every format reader produces: named numeric columns, with where each row came from.
#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace mlce::reader {

/// A malformed or unreadable file. The message names the file, the line when there is one, and
/// what was expected.
class ReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Table {
  std::string source;                     ///< file name, for messages
  std::vector<std::string> names;         ///< one per column ("column 1", ... when the file has none)
  bool has_header = false;                ///< names come from a header line of the file
  std::vector<std::vector<double>> columns;
  std::vector<std::string> warnings;

  std::size_t rows() const { return rows_; }
  /// Appends the file line of the next row (lines increase). Kept as runs of consecutive lines, so
  /// the map costs memory per blank or comment line between rows, not per row.
  void add_row_line(std::size_t line);
  /// The 1-based file line of row `row` (< rows()).
  std::size_t line_of(std::size_t row) const;
  /// "file:line" for row `row` (or "file" when out of range).
  std::string where(std::size_t row) const;

 private:
  struct LineRun {
    std::size_t first_row, first_line;  ///< rows first_row, first_row + 1, ... on consecutive lines
  };
  std::vector<LineRun> line_runs_;
  std::size_t rows_ = 0;
  std::size_t last_line_ = 0;
};

}  // namespace mlce::reader
