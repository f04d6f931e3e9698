#pragma once
// What every format reader produces: named numeric columns, with where each row came from.
#include <algorithm>
#include <cstddef>
#include <limits>
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
  /// A field that is no number, where it is in the file and what is wrong with it.
  struct TextField {
    std::size_t line = 0, column = 0;  ///< 1-based file line and column; line 0: none
    std::string message;               ///< "file:line: column K: 'abc' is not a number"
  };
  /// Per column, when a reader was asked to read on past fields that are no numbers (a column
  /// file's ColumnFileOptions::text_columns): the column's first such field (line 0 for a column of
  /// numbers). Empty when not asked.
  std::vector<TextField> text;
  /// Throws the message of the first field of text, in the file's order, among the 0-based columns
  /// `which` on lines up to `last_line`: the error a read that stopped there would have thrown.
  /// Nothing when they hold numbers there.
  void require_numbers(const std::vector<std::size_t>& which,
                       std::size_t last_line = std::numeric_limits<std::size_t>::max()) const;

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
