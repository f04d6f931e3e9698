#pragma once
// Plain column files: whitespace- or comma-separated numbers, '#' starts a comment, one row per
// line, every row with the same number of columns. One comma with blanks around it is one
// separator; two commas with nothing between them enclose an empty field, which is an error (a
// missing value; skipping it would shift the later columns); a comma ending a line is dropped.
// A data line separating some fields by commas and others by blanks only is an error (decimal
// commas: "0,01<TAB>2,5" would read as four numbers).
// An optional header line (the first line that is not blank or a comment, with no field that
// reads as a number; an empty cell is an unnamed column) names the columns. Without one, the last
// comment line before the data names them when it holds exactly one such word per column
// (`# time x_h`, numpy.savetxt's header).
#include <string>
#include <vector>

#include "mlce/reader/table.hpp"

namespace mlce::reader {

struct ColumnFileOptions {
  /// 1-based columns to keep; empty = all. Parsing still checks every field of every row.
  std::vector<std::size_t> keep;
  /// Keep nan/inf fields as they are instead of refusing them: for a caller that reads only part
  /// of the rows (a time window before a run diverged) and checks that part itself.
  bool keep_nonfinite = false;
};

/// Reads the whole file. Throws ReadError for a missing or unreadable file, a file without data,
/// a field that is empty or not a number, a non-finite value (nan, inf; unless keep_nonfinite), and a row with a different number
/// of columns than the first.
Table read_column_file(const std::string& path, const ColumnFileOptions& options = {});

/// Same, from text already in memory (`source` names it in messages).
Table parse_column_text(std::string_view text, const std::string& source, const ColumnFileOptions& options = {});

}  // namespace mlce::reader
