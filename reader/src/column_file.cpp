#include "mlce/reader/column_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

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

std::string Table::where(std::size_t row) const {
  return row < rows_ ? source + ":" + std::to_string(line_of(row)) : source;
}

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }
bool is_separator(char c) { return is_blank(c) || c == ','; }

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

/// Where a '#' comment starts (npos: none); a '#' inside a quoted field is text.
std::size_t comment_start(std::string_view line) {
  for (std::size_t k = 0; k < line.size(); ++k) {
    if (line[k] == '#') return k;
    if (line[k] == '"') {
      const std::size_t close = closing_quote(line, k);
      if (close == std::string_view::npos) return line.find('#', k + 1);
      k = close;
    }
  }
  return std::string_view::npos;
}

/// The fields of a line into `out`. Blanks (spaces, tabs) separate fields, and so does one comma
/// with blanks around it; two commas with nothing between them enclose an empty field (a missing
/// value in a CSV), which is kept as "" so that it is refused, not skipped: skipping it would move
/// every later field one column to the left. A comma ending the line (some exporters write one on
/// every row) ends it and opens no field. A field in double quotes (RFC 4180: R's write.csv quotes
/// its header and row names, other exporters every text) is the text between them, separators
/// included (a doubled quote inside stays doubled); a quote that does not close before a separator or the line's end leaves the field as
/// it stands, quotes and all, to be refused as text. Returns whether the line separates some fields
/// by a comma and others by blanks only: "0,01<TAB>2,5", a spreadsheet's decimal commas, would
/// otherwise read as four numbers.
bool split_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size() && is_blank(line[i])) ++i;
  if (i >= line.size()) return false;
  bool by_comma = false, by_blank = false;
  while (true) {
    std::size_t j = i;
    const std::size_t close = line[i] == '"' ? closing_quote(line, i) : std::string_view::npos;
    if (close != std::string_view::npos && (close + 1 == line.size() || is_separator(line[close + 1]))) {
      out.push_back(line.substr(i + 1, close - i - 1));
      j = close + 1;
    } else {
      while (j < line.size() && !is_separator(line[j])) ++j;
      out.push_back(line.substr(i, j - i));
    }
    while (j < line.size() && is_blank(line[j])) ++j;
    bool comma = false;
    if (j < line.size() && line[j] == ',') {
      comma = true;
      ++j;
      while (j < line.size() && is_blank(line[j])) ++j;
    }
    if (j >= line.size()) return by_comma && by_blank;
    (comma ? by_comma : by_blank) = true;
    i = j;
  }
}

std::vector<std::string> split_fields(std::string_view line) {
  std::vector<std::string_view> views;
  split_fields(line, views);
  return {views.begin(), views.end()};
}

/// Every field of the line is a word that cannot be read as a number (so "1 abc" is a bad data row,
/// not a header, and "nan"/"inf" are values, refused later as non-finite).
bool is_header(std::string_view line) {
  bool named = false;
  for (const auto& f : split_fields(line)) {
    if (f.empty()) continue;  // an unnamed column (",,") keeps its place; a line of commas only is no header
    named = true;
    double v = 0.0;
    const char* first = f.data() + (f.front() == '+' ? 1 : 0);
    const auto [ptr, ec] = std::from_chars(first, f.data() + f.size(), v);
    if (ptr != first || ec == std::errc::result_out_of_range) return false;  // starts like a number
  }
  return named;
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
    // A header (the first line that is not blank or a comment, every field non-numeric, as
    // `mlce extract` and spreadsheets write it) names the columns; text anywhere else is an error.
    if (ncols == 0 && header.empty() && is_header(line)) {
      header = split_fields(line);
      header_line = line_no;
      continue;
    }
    if (split_fields(line, fields)) {
      std::string shown;
      for (char ch : shorten(line)) shown += ch == '\t' ? std::string("\\t") : std::string(1, ch);
      throw ReadError(source + ":" + std::to_string(line_no) + ": '" + shown +
                      "': fields separated by commas and by blanks alike (decimal commas?): write decimal points, "
                      "and one kind of separator");
    }
    for (std::size_t field = 1; field <= fields.size(); ++field) {
      const std::string_view tok = fields[field - 1];
      if (tok.empty())
        throw ReadError(source + ":" + std::to_string(line_no) + ": column " + std::to_string(field) +
                        ": empty field: expected a number");
      const char* first = tok.data();
      if (!tok.empty() && tok.front() == '+') ++first;  // from_chars rejects a leading '+'
      double v = 0.0;
      auto [ptr, ec] = std::from_chars(first, tok.data() + tok.size(), v);
      if (ec == std::errc() && ptr != tok.data() + tok.size() && (*ptr == 'D' || *ptr == 'd')) {
        // Fortran's double-precision exponent (1.0D+00): read as 1.0e+00.
        std::string e(first, tok.data() + tok.size());
        e[static_cast<std::size_t>(ptr - first)] = 'e';
        double w = 0.0;
        const auto [p2, ec2] = std::from_chars(e.data(), e.data() + e.size(), w);
        if (p2 == e.data() + e.size()) ptr = tok.data() + tok.size(), ec = ec2, v = w;  // ok or out of range
      }
      if (ec == std::errc::result_out_of_range)
        throw ReadError(source + ":" + std::to_string(line_no) + ": column " + std::to_string(field) + ": '" +
                        shorten(tok) + "' is out of the range of a double");
      if (ec != std::errc() || ptr != tok.data() + tok.size())
        throw ReadError(source + ":" + std::to_string(line_no) + ": column " + std::to_string(field) + ": '" +
                        shorten(tok) + "' is not a number" +
                        (tok.find(';') != std::string_view::npos ? " (fields are separated by spaces, tabs or commas)" : ""));
      if (!std::isfinite(v) && !options.keep_nonfinite)
        throw ReadError(source + ":" + std::to_string(line_no) + ": column " + std::to_string(field) + ": '" +
                        shorten(tok) + "': expected a finite number");
      row.push_back(v);
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
      if (header.empty() && is_header(last_comment) && split_fields(last_comment).size() == ncols) {
        header = split_fields(last_comment);
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
  return t;
}

}  // namespace

Table parse_column_text(std::string_view text, const std::string& source, const ColumnFileOptions& options) {
  auto src = detail::LineSource::from_memory(text, source);
  return parse_lines(src, source, options);
}

Table read_column_file(const std::string& path, const ColumnFileOptions& options) {
  auto src = detail::LineSource::open(path);
  return parse_lines(src, path, options);
}

}  // namespace mlce::reader
