#pragma once
// Plain column files: whitespace- or comma-separated numbers, '#' starts a comment, one row per
// line, every row with the same number of columns. A line with a comma is comma-separated (blanks
// around a field dropped, text with blanks inside one field: a datetime "2026-11-27 01:00:00");
// two commas with nothing between them enclose an empty field, which is an error (a missing value;
// skipping it would shift the later columns); a comma ending a line is dropped, unless it ends a
// row one field short (its last value missing). A comma-separated field of numbers separated by
// blanks is an error (decimal commas: "0,01<TAB>2,5" would read as three numbers). A line with a
// tab and no comma is tab-separated unless a field between its tabs holds numbers between spaces
// (then blanks and tabs alike separate). A field in double quotes is the text between them (RFC 4180).
// A file whose first line with content splits at its semicolons into names or numbers is
// semicolon-separated throughout, as spreadsheets write CSV where the decimal mark is a comma
// ("time;x" / "0,01;-2,5E-03"): each field holds one decimal comma or point (a field with both, or
// with two commas, is an error: thousands separators are not guessed at), and the comma rules above
// (empty fields, a separator ending the line, blanks) hold for its semicolons.
// An optional header line (the first line that is not blank or a comment, with no field that
// reads as a number; an empty cell is an unnamed column) names the columns. Without one, the last
// comment line before the data names them when it holds exactly one such word per column
// (`# time x_h`, numpy.savetxt's header).
#include <string>
#include <vector>

#include "mlce/reader/table.hpp"

namespace mlce::reader {

struct ColumnFileOptions {
  /// 1-based columns to keep; empty = all. Only the kept columns' fields are read as numbers (a
  /// column of text beside them is no error); every row must still have the first row's count.
  std::vector<std::size_t> keep;
  /// A field of a kept column that is not a number (text, empty, out of range) does not stop the
  /// read: the field reads as NaN and its column carries the message (Table::text_error, the first
  /// such field's), for a caller that picks columns after reading the names and refuses text only
  /// in those (a spreadsheet's date or label column beside the numbers analysed).
  bool text_columns = false;
  /// Keep nan/inf fields as they are instead of refusing them: for a caller that reads only part
  /// of the rows (a time window before a run diverged) and checks that part itself.
  bool keep_nonfinite = false;
};

/// Reads the whole file. Throws ReadError for a missing or unreadable file, a file without data,
/// a field of a kept column that is empty or not a number (unless text_columns), a non-finite value
/// (nan, inf; unless keep_nonfinite), and a row with a different number of columns than the first.
Table read_column_file(const std::string& path, const ColumnFileOptions& options = {});

/// Same, from text already in memory (`source` names it in messages).
Table parse_column_text(std::string_view text, const std::string& source, const ColumnFileOptions& options = {});

}  // namespace mlce::reader
