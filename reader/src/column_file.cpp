#include "mlce/reader/column_file.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>

#include "line_source.hpp"

namespace mlce::reader {

void Table::add_row_line(std::size_t line) {
  if (rows_ == 0 || line != last_line_ + 1) line_runs_.push_back({rows_, line});
  last_line_ = line;
  ++rows_;
}

std::size_t Table::line_of(std::size_t row) const {
  const auto run = std::upper_bound(line_runs_.begin(), line_runs_.end(), row,
                                    [](std::size_t r, const LineRun& l) { return r < l.first_row; });
  if (row >= rows_ || run == line_runs_.begin()) throw std::out_of_range("Table::line_of: no row " + std::to_string(row));
  return std::prev(run)->first_line + (row - std::prev(run)->first_row);
}

void Table::require_numbers(const std::vector<std::size_t>& which, std::size_t last_line) const {
  const TextField* first = nullptr;
  for (const std::size_t c : which) {
    if (c >= text.size() || text[c].line == 0 || text[c].line > last_line) continue;
    const TextField& f = text[c];
    if (!first || f.line < first->line || (f.line == first->line && f.column < first->column)) first = &f;
  }
  if (first) throw ReadError(first->message);
}

std::string Table::where(std::size_t row) const {
  return row < rows_ ? source + ":" + std::to_string(line_of(row)) : source;
}

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string shorten(std::string_view s) {
  std::string t(s.substr(0, 40));
  if (s.size() > 40) t += "...";
  return t;
}

/// Where the quoted field that opens at line[open] (a double quote) closes: the index of its closing
/// quote, "" inside it being a quote of its text (RFC 4180); npos when the line ends first.
std::size_t closing_quote(std::string_view line, std::size_t open) {
  for (std::size_t k = open + 1; k < line.size(); ++k)
    if (line[k] == '"') {
      if (k + 1 < line.size() && line[k + 1] == '"') ++k;
      else return k;
    }
  return std::string_view::npos;
}

/// Where the first `c` outside quoted fields is (npos: none). A quote that never closes quotes
/// nothing. (This runs on every line of a file: a line without quotes costs two memchr.)
std::size_t find_unquoted(std::string_view line, char c) {
  std::size_t at = line.find(c);
  for (std::size_t quote = line.find('"'); quote < at; quote = line.find('"', quote + 1)) {
    const std::size_t close = closing_quote(line, quote);
    if (close == std::string_view::npos) return at;
    if (close > at) at = line.find(c, close + 1);  // that one was quoted
    quote = close;
  }
  return at;
}

/// Where a '#' comment starts (npos: none); a '#' inside a quoted field is text.
std::size_t comment_start(std::string_view line) { return find_unquoted(line, '#'); }

/// 'tok' (shortened), for messages.
std::string quoted(std::string_view tok) {
  std::string q = "'";
  q += shorten(tok);
  q += '\'';
  return q;
}

/// The number a field holds into v; "" when it is one, else what is wrong with it (the message
/// after "file:line: column K: ").
std::string read_number(std::string_view tok, const ColumnFileOptions& options, double& v, bool decimal_comma = false) {
  if (tok.empty()) return "empty field: expected a number";
  if (decimal_comma && tok.find(',') != std::string_view::npos) {
    // A semicolon-separated file's decimal comma (a spreadsheet in a European locale: "-2,5E-03").
    // One comma and no point: a point beside it would be a thousands separator, which a number
    // written for reading back never holds, and guessing which is which could misread by 1000.
    if (tok.find('.') != std::string_view::npos || tok.find(',') != tok.rfind(','))
      return quoted(tok) + " is not a number (a semicolon-separated file's numbers have one decimal comma or point, "
                           "no thousands separators)";
    std::array<char, 64> buffer{};  // every field of a large file passes here: no allocation
    std::string long_field;
    char* copy = buffer.data();
    if (tok.size() > buffer.size()) long_field.assign(tok), copy = long_field.data();
    else std::copy(tok.begin(), tok.end(), copy);
    copy[tok.find(',')] = '.';
    const std::string_view point(copy, tok.size());
    std::string error = read_number(point, options, v);
    return error.empty() ? error : quoted(tok) + error.substr(quoted(point).size());
  }
  const char* first = tok.data();
  if (tok.front() == '+') ++first;  // from_chars rejects a leading '+'
  auto [ptr, ec] = std::from_chars(first, tok.data() + tok.size(), v);
  if (ec == std::errc() && ptr != tok.data() + tok.size() && (*ptr == 'D' || *ptr == 'd')) {
    // Fortran's double-precision exponent (1.0D+00): read as 1.0e+00.
    std::string e(first, tok.data() + tok.size());
    e[static_cast<std::size_t>(ptr - first)] = 'e';
    double w = 0.0;
    const auto [p2, ec2] = std::from_chars(e.data(), e.data() + e.size(), w);
    if (p2 == e.data() + e.size()) ptr = tok.data() + tok.size(), ec = ec2, v = w;  // ok or out of range
  }
  if (ec == std::errc::result_out_of_range) return quoted(tok) + " is out of the range of a double";
  if (ec != std::errc() || ptr != tok.data() + tok.size())
    return quoted(tok) + " is not a number" +
           (tok.find(';') != std::string_view::npos
                ? " (fields are separated by spaces, tabs or commas; by semicolons when the file's first line is)"
                : "");
  if (!std::isfinite(v) && !options.keep_nonfinite) return quoted(tok) + ": expected a finite number";
  return "";
}

/// How a line splits: `ambiguous` when a comma-separated field holds numbers separated by blanks
/// ("0,01<TAB>2,5", a spreadsheet's decimal commas, would otherwise read as three or four numbers);
/// `semicolon_field` (1-based, 0 = none) the first field of numbers separated by semicolons (a
/// European CSV, "0,01;2,5", in a file not read as semicolon-separated: its first column would read
/// as the integer parts); `trailing_separator` when the separator (a comma, a semicolon) ends the line.
struct Split {
  bool ambiguous = false, trailing_separator = false;
  std::size_t semicolon_field = 0;
};

/// Every piece of a field between blanks (and semicolons, with `semicolons`) is a number: the field
/// is numbers in another separator, not one text.
bool only_numbers(std::string_view field, bool semicolons = false) {
  ColumnFileOptions any;
  any.keep_nonfinite = true;  // a piece that is nan or inf is a number here
  auto splits = [&](char c) { return is_blank(c) || (semicolons && c == ';'); };
  bool pieces = false;
  for (std::size_t i = 0; i < field.size();) {
    while (i < field.size() && splits(field[i])) ++i;
    std::size_t j = i;
    while (j < field.size() && !splits(field[j])) ++j;
    if (j > i) {
      double v = 0.0;
      if (!read_number(field.substr(i, j - i), any, v).empty()) return false;
      pieces = true;
    }
    i = j;
  }
  return pieces;
}

/// Whether the line has a comma outside quoted fields: then it is comma-separated.
bool has_comma(std::string_view line) { return find_unquoted(line, ',') != std::string_view::npos; }

/// How a line's fields are separated: by commas, by semicolons (a European CSV, whose numbers may
/// carry decimal commas), by tabs (blanks inside a field are its text), or by blanks (spaces and tabs
/// alike).
enum class Separator { comma, semicolon, tab, blank };

/// The fields of a line into `out`, separated as `by` says; with Separator::tab, `tab_fallback` is
/// set (and the fields are not complete) when a field holds numbers between spaces: the line then
/// separates by blanks.
Split split_fields_by(std::string_view line, std::vector<std::string_view>& out, Separator by, bool& tab_fallback) {
  out.clear();
  Split split;
  std::size_t i = 0;
  while (i < line.size() && is_blank(line[i])) ++i;
  if (i >= line.size()) return split;
  const char sep = by == Separator::comma ? ',' : by == Separator::semicolon ? ';' : '\t';
  const bool delimited = by == Separator::comma || by == Separator::semicolon;  // empty fields count
  auto ends_field = [&](char c) { return by == Separator::blank ? is_blank(c) : c == sep; };
  while (true) {
    std::size_t j = i;
    const std::size_t close = line[i] == '"' ? closing_quote(line, i) : std::string_view::npos;
    std::size_t after = close == std::string_view::npos ? close : close + 1;
    if (by != Separator::blank)
      while (after < line.size() && line[after] != sep && is_blank(line[after])) ++after;
    if (close != std::string_view::npos && (after >= line.size() || ends_field(line[after]))) {
      out.push_back(line.substr(i + 1, close - i - 1));
      j = after;
    } else {
      bool blank = false, semicolon = false;  // seen in the field: the rare cases looked at below
      if (by == Separator::blank)  // one loop per kind of line, not a question at every character
        for (; j < line.size() && !is_blank(line[j]); ++j) semicolon |= line[j] == ';';
      else
        for (; j < line.size() && line[j] != sep; ++j) blank |= is_blank(line[j]), semicolon |= line[j] == ';';
      std::size_t e = j;
      while (e > i && is_blank(line[e - 1])) --e;
      const std::string_view field = line.substr(i, e - i);
      if (blank && field.find_first_of(" \t\r") != std::string_view::npos && only_numbers(field)) {
        if (by == Separator::tab) {
          tab_fallback = true;
          return split;
        }
        split.ambiguous = true;
      }
      if (semicolon && by != Separator::semicolon && split.semicolon_field == 0 && only_numbers(field, true))
        split.semicolon_field = out.size() + 1;
      out.push_back(field);
    }
    while (j < line.size() && is_blank(line[j])) ++j;  // a run of tabs is one separator, as a run of blanks
    if (delimited && j < line.size() && line[j] == sep) {
      ++j;
      while (j < line.size() && is_blank(line[j])) ++j;
      if (j >= line.size()) split.trailing_separator = true;
    }
    if (j >= line.size()) return split;
    i = j;
  }
}

/// The fields of a line into `out`. A line with a comma (outside quotes) is comma-separated: each
/// field is what lies between commas, blanks around it dropped, so text with blanks inside ("2026-11-27
/// 01:00:00", a datetime as pandas writes it) is one field; two commas with nothing between them
/// enclose an empty field (a missing value), kept as "" so that it is refused, not skipped: skipping
/// it would move every later field one column to the left. A comma ending the line (some exporters
/// write one on every row) opens no field (the caller decides when it ends a row whose last value is
/// missing). A line with a tab and no comma is tab-separated (a run of tabs is one separator) when
/// no field between its tabs holds numbers between spaces ("27-Nov-2026 01:00:00" as MATLAB and
/// spreadsheets write dates is one field; "1 2<TAB>3" is three numbers aligned by blanks and tabs);
/// any other line is blank-separated (spaces, tabs). A field in double quotes (RFC 4180: R's
/// write.csv quotes its header and row names, other exporters every text) is the text between them,
/// separators included (a doubled quote inside stays doubled); a quote that does not close before a
/// separator or the line's end leaves the field as it stands, quotes and all, to be refused as text.
Split split_fields(std::string_view line, std::vector<std::string_view>& out, bool semicolons = false) {
  bool tab_fallback = false;
  if (semicolons) return split_fields_by(line, out, Separator::semicolon, tab_fallback);
  if (has_comma(line)) return split_fields_by(line, out, Separator::comma, tab_fallback);
  if (find_unquoted(line, '\t') != std::string_view::npos) {
    const Split split = split_fields_by(line, out, Separator::tab, tab_fallback);
    if (!tab_fallback) return split;
  }
  return split_fields_by(line, out, Separator::blank, tab_fallback);
}

std::vector<std::string> split_fields(std::string_view line, bool semicolons = false) {
  std::vector<std::string_view> views;
  split_fields(line, views, semicolons);
  return {views.begin(), views.end()};
}

/// Every field of the line is a word that cannot be read as a number (so "1 abc" is a bad data row,
/// not a header, and "nan"/"inf" are values, refused later as non-finite).
bool is_header(std::string_view line, bool semicolons = false) {
  bool named = false;
  for (const auto& f : split_fields(line, semicolons)) {
    if (f.empty()) continue;  // an unnamed column (",,") keeps its place; a line of commas only is no header
    named = true;
    double v = 0.0;
    const char* first = f.data() + (f.front() == '+' ? 1 : 0);
    const auto [ptr, ec] = std::from_chars(first, f.data() + f.size(), v);
    if (ptr != first || ec == std::errc::result_out_of_range) return false;  // starts like a number
  }
  return named;
}

/// Whether a file whose first line that is not blank or a comment is `line` separates its fields by
/// semicolons, as spreadsheets write CSV in locales whose decimal mark is a comma ("time;x",
/// "0,01;-2,5"): the line has a semicolon outside quotes, and split at its semicolons it is a header
/// (every field a name) or a row of numbers (each with a decimal comma or point). Decided once per
/// file, so a note with a semicolon in a comma-separated file ("0,1,a;b") stays one text field, and
/// a row written otherwise later in the file is an error, not numbers read another way.
bool separates_by_semicolons(std::string_view line) {
  if (find_unquoted(line, ';') == std::string_view::npos) return false;
  if (is_header(line, true)) return true;
  std::vector<std::string_view> fields;
  split_fields(line, fields, true);
  ColumnFileOptions any;
  any.keep_nonfinite = true;
  double v = 0.0;
  return std::all_of(fields.begin(), fields.end(),
                     [&](std::string_view f) { return read_number(f, any, v, true).empty(); });
}

/// One pass over the lines: memory is the table, never a copy of the file's text.
Table parse_lines(detail::LineSource& src, const std::string& source, const ColumnFileOptions& options) {
  Table t;
  t.source = source;
  std::size_t ncols = 0;
  std::size_t line_no = 0, header_line = 0, comment_line = 0;
  std::vector<std::string> header;
  std::string last_comment;  // the last comment-only line before the first data row
  std::vector<double> row;
  std::vector<std::string_view> fields;
  std::vector<Table::TextField> field_text;  // text_columns: each file column's first field that is no number
  bool dialect_known = false, semicolons = false;  // separates_by_semicolons of the first line with content
  // The source drops a UTF-8 byte-order mark (spreadsheets' "CSV UTF-8") and a CR before the
  // newline, and returns a last line that has no newline: such a file is complete.
  src.keep_unterminated_tail();
  std::string_view line;
  while (src.next(line)) {
    line_no = src.line_number();
    std::string_view comment;
    if (const auto hash = comment_start(line); hash != std::string_view::npos) {
      comment = line.substr(hash + 1);
      line = line.substr(0, hash);
    }
    row.clear();
    if (!dialect_known && line.find_first_not_of(" \t\r") != std::string_view::npos) {
      semicolons = separates_by_semicolons(line);
      dialect_known = true;
    }
    // A header (the first line that is not blank or a comment, every field non-numeric, as
    // `mlce extract` and spreadsheets write it) names the columns; text anywhere else is an error.
    if (ncols == 0 && header.empty() && is_header(line, semicolons)) {
      header = split_fields(line, semicolons);
      header_line = line_no;
      continue;
    }
    const Split split = split_fields(line, fields, semicolons);
    if (split.ambiguous) {
      std::string shown;
      for (char ch : shorten(line)) shown += ch == '\t' ? std::string("\\t") : std::string(1, ch);
      throw ReadError(source + ":" + std::to_string(line_no) + ": '" + shown +
                      "': fields separated by commas and by blanks alike (decimal commas?): write decimal points, "
                      "and one kind of separator");
    }
    if (split.semicolon_field != 0)  // never read on past it: the columns before it would be wrong numbers
      throw ReadError(source + ":" + std::to_string(line_no) + ": column " + std::to_string(split.semicolon_field) + ": " +
                      quoted(fields[split.semicolon_field - 1]) +
                      " is not a number (fields are separated by spaces, tabs or commas; by semicolons when the "
                      "file's first line is)");
    // A comma ending a row one field short of the columns is its last value, missing (pandas writes
    // "1,2," for a row whose last column is empty); on every row of a file it opens no column.
    const std::size_t expected = ncols != 0 ? ncols : header.size();
    if (split.trailing_separator && fields.size() + 1 == expected) fields.push_back(line.substr(line.size()));  // empty
    // The last line of a file still being written (a run in progress, copied or read while the
    // solver writes), or cut short: no line end, and fewer fields than the rows before it or a field
    // that is no number ("-13.9" cut to "-1" still reads; "1e" does not). Left out with a warning,
    // as the MBDyn readers leave out a partial last block: the rest of the file is complete.
    const bool open_tail = src.line_unterminated() && ncols != 0;
    bool tail_broken = false;
    for (std::size_t field = 1; field <= fields.size(); ++field) {
      double v = std::numeric_limits<double>::quiet_NaN();
      if (options.keep.empty() || std::find(options.keep.begin(), options.keep.end(), field) != options.keep.end()) {
        if (std::string error = read_number(fields[field - 1], options, v, semicolons); !error.empty()) {
          if (open_tail) {
            tail_broken = true;
            break;
          }
          error = source + ":" + std::to_string(line_no) + ": column " + std::to_string(field) + ": " + error;
          if (!options.text_columns) throw ReadError(error);
          if (field_text.size() < field) field_text.resize(field);
          if (field_text[field - 1].line == 0) field_text[field - 1] = {line_no, field, std::move(error)};
        }
      }
      row.push_back(v);
    }
    if (open_tail && !row.empty() && (tail_broken || row.size() != ncols)) {
      t.warnings.push_back(source + ":" + std::to_string(line_no) + ": the last line has no line end and " +
                           (tail_broken ? std::string("a field that is no number")
                                        : std::to_string(row.size()) + " of the " + std::to_string(ncols) + " fields") +
                           ": a file still being written, or cut short? It is left out");
      continue;
    }
    if (row.empty()) {  // blank or comment-only line
      if (ncols == 0 && header.empty() && !comment.empty()) last_comment = comment, comment_line = line_no;
      continue;
    }
    if (ncols == 0) {
      ncols = row.size();
      // Names in a comment: the last comment line before the data, when it names exactly the
      // columns the data has, every field a word (`# time x y`, as `mlce simulate --format columns`,
      // make_series and numpy.savetxt(header=...) write it; numpy's genfromtxt(names=True) reads it
      // so). A comment of other text, or of another count, stays a comment.
      if (header.empty() && is_header(last_comment, semicolons) && split_fields(last_comment, semicolons).size() == ncols) {
        header = split_fields(last_comment, semicolons);
        header_line = comment_line;
      }
      if (!header.empty() && header.size() != ncols)
        throw ReadError(source + ":" + std::to_string(line_no) + ": " + std::to_string(ncols) +
                        " column(s), but the header on line " + std::to_string(header_line) + " names " +
                        std::to_string(header.size()));
      for (std::size_t k : options.keep)
        if (k == 0 || k > ncols)
          throw ReadError(source + ":" + std::to_string(line_no) + ": column " + std::to_string(k) +
                          " requested, but the file has " + std::to_string(ncols) + " column(s)");
      const std::size_t kept = options.keep.empty() ? ncols : options.keep.size();
      t.columns.assign(kept, {});
      auto name = [&](std::size_t k) { return header.empty() ? "column " + std::to_string(k) : header[k - 1]; };
      t.has_header = !header.empty();
      if (options.keep.empty())
        for (std::size_t k = 1; k <= ncols; ++k) t.names.push_back(name(k));
      else
        for (std::size_t k : options.keep) t.names.push_back(name(k));
    } else if (row.size() != ncols) {
      throw ReadError(source + ":" + std::to_string(line_no) + ": " + std::to_string(row.size()) +
                      " column(s), expected " + std::to_string(ncols) + " as on the first data line");
    }
    if (options.keep.empty())
      for (std::size_t k = 0; k < ncols; ++k) t.columns[k].push_back(row[k]);
    else
      for (std::size_t k = 0; k < options.keep.size(); ++k) t.columns[k].push_back(row[options.keep[k] - 1]);
    t.add_row_line(line_no);
  }
  if (t.rows() == 0) throw ReadError(source + ": no data (the file is empty or holds only comments)");
  if (options.text_columns) {
    field_text.resize(ncols);
    for (std::size_t k = 0; k < t.columns.size(); ++k) t.text.push_back(field_text[options.keep.empty() ? k : options.keep[k] - 1]);
  }
  return t;
}

}  // namespace

Table parse_column_text(std::string_view text, const std::string& source, const ColumnFileOptions& options) {
  auto src = detail::LineSource::from_memory(text, source);
  return parse_lines(src, source, options);
}

Table read_column_file(const std::string& path, const ColumnFileOptions& options) {
  auto src = detail::LineSource::open(path);
  return parse_lines(src, src.name(), options);  // "stdin" for "-"
}

}  // namespace mlce::reader
