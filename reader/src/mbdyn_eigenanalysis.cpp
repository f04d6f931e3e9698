// MBDyn's eigenanalysis .m files (layout: mbdyn_eigenanalysis.hpp).
#include "mlce/reader/mbdyn_eigenanalysis.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <system_error>

#include "line_source.hpp"
#include "text_fields.hpp"
#include "triplets.hpp"
#include "mlce/reader/table.hpp"

namespace mlce::reader {
namespace {

using detail::LineSource;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

double finite_number(std::string_view t, const LineSource& src, std::string_view what) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);  // Octave reads "+1"; from_chars does not
  double v = 0.0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc{} || end != t.data() + t.size() || !std::isfinite(v))
    throw ReadError(src.where() + ": " + std::string(what) + ": expected a finite number, found '" + std::string(t) + "'");
  return v;
}

/// One `NAME = [ ... ];` being read. Rows end at ';' or at a line's end (Octave's rule); empty rows
/// (the newline after "a b c;") are none.
/// Rows of equal width, stored flat (a dense 4000 x 4000 matrix is 128 MB, not 4000 vectors' worth more).
struct ReadMatrix {
  std::vector<double> values;
  std::size_t width = 0, rows = 0;
  std::size_t line = 0;  ///< where `NAME = [` is
  const double* row(std::size_t r) const { return values.data() + r * width; }
};

struct OpenMatrix {
  std::string name;
  bool kept = false;  ///< alpha, Aplus, Aminus; the others (VL, VR, labels, idx, X0) are skipped
  ReadMatrix read;
  std::vector<double> row;
};

void end_row(OpenMatrix& m, const LineSource& src) {
  if (m.row.empty()) return;
  ReadMatrix& r = m.read;
  if (r.rows > 0 && r.width != m.row.size())
    throw ReadError(src.where() + ": " + m.name + ": a row of " + std::to_string(m.row.size()) + " values where the first row (line " +
                    std::to_string(r.line) + ") has " + std::to_string(r.width));
  if (m.name == "alpha" && m.row.size() != 3)
    throw ReadError(src.where() + ": alpha: a row of " + std::to_string(m.row.size()) +
                    " values; MBDyn writes alphar, alphai, beta (3) per eigenvalue");
  // Dense rows beyond the largest matrix held, or more triplets than its n^2 entries: refused as they come.
  const std::size_t most = m.row.size() == 3 ? kLargestEigenanalysisMatrix * kLargestEigenanalysisMatrix : kLargestEigenanalysisMatrix;
  if (m.row.size() > kLargestEigenanalysisMatrix || r.rows >= most)
    throw ReadError(src.where() + ": " + m.name + ": larger than the " + std::to_string(kLargestEigenanalysisMatrix) + " x " +
                    std::to_string(kLargestEigenanalysisMatrix) +
                    " this reader holds; ask MBDyn for its eigenvalues (`output eigenvectors` writes alpha)");
  r.width = m.row.size();
  r.values.insert(r.values.end(), m.row.begin(), m.row.end());
  ++r.rows;
  m.row.clear();
}

/// Reads `chunk` (a line's part inside the brackets); true when the closing ']' was met.
bool read_matrix_chunk(std::string_view chunk, OpenMatrix& m, const LineSource& src) {
  std::size_t i = 0;
  while (i < chunk.size()) {
    const char c = chunk[i];
    if (c == ']') {
      if (m.kept) end_row(m, src);
      return true;
    }
    if (c == ';') {
      if (m.kept) end_row(m, src);
      ++i;
      continue;
    }
    if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
      ++i;
      continue;
    }
    if (c == '%' || c == '#') break;  // a comment to the line's end
    std::size_t j = i;
    while (j < chunk.size() && chunk[j] != ' ' && chunk[j] != '\t' && chunk[j] != ',' && chunk[j] != ';' && chunk[j] != ']' &&
           chunk[j] != '\r')
      ++j;
    if (m.kept) m.row.push_back(finite_number(chunk.substr(i, j - i), src, m.name));
    i = j;
  }
  if (m.kept) end_row(m, src);  // a line's end ends a row
  return false;
}

/// Dense rows, or 1-based (i, j, value) triplets when `sparse`, as a row-major n x n matrix.
std::vector<double> square_matrix(const std::string& name, const ReadMatrix& m, bool sparse, const std::string& source,
                                  std::size_t& n) {
  const std::string where = source + ":" + std::to_string(m.line) + ": " + name;
  if (!sparse) {
    n = m.rows;
    if (n == 0) throw ReadError(where + ": an empty matrix");
    if (m.width != n)
      throw ReadError(where + ": " + std::to_string(n) + " rows of " + std::to_string(m.width) +
                      " values; the matrix is square (or written as triplets, then followed by spconvert)");
    detail::check_matrix_size(where, n);
    return m.values;
  }
  if (m.rows > 0 && m.width != 3) throw ReadError(where + ": a sparse matrix is rows of (row, column, value)");
  return detail::matrix_from_triplets(m.values.data(), m.rows, 0, where, n);
}

MbdynEigenanalysis parse(LineSource& src) {
  src.keep_unterminated_tail();  // the file ends "];" with or without a final newline
  MbdynEigenanalysis out;
  out.source = src.name();
  std::map<std::string, ReadMatrix, std::less<>> matrices;
  std::map<std::string, bool, std::less<>> sparse;
  std::optional<OpenMatrix> open;
  std::string_view line;
  while (src.next(line)) {
    if (open) {
      if (read_matrix_chunk(line, *open, src)) {
        if (open->kept) matrices[open->name] = std::move(open->read);
        open.reset();
      }
      continue;
    }
    const std::string_view t = trim(line);
    if (t.empty() || t.front() == '%' || t.front() == '#') continue;
    const auto eq = t.find('=');
    if (eq == std::string_view::npos) continue;  // no assignment: nothing this reader uses
    const std::string name(trim(t.substr(0, eq)));
    std::string_view rest = trim(t.substr(eq + 1));
    if (!rest.empty() && rest.front() == '[') {
      open = OpenMatrix{name, name == "alpha" || name == "Aplus" || name == "Aminus", {}, {}};
      open->read.line = src.line_number();
      if (read_matrix_chunk(rest.substr(1), *open, src)) {
        if (open->kept) matrices[open->name] = std::move(open->read);
        open.reset();
      }
      continue;
    }
    if (rest.starts_with("spconvert(")) {
      sparse[name] = true;
      continue;
    }
    if (name == "dTime" || name == "dCoef") {
      if (!rest.empty() && rest.back() == ';') rest.remove_suffix(1);
      const double v = finite_number(trim(rest), src, name);
      (name == "dTime" ? out.time : out.coefficient) = v;
    }
  }
  if (open)
    throw ReadError(out.source + ":" + std::to_string(open->read.line) + ": " + open->name +
                    ": the matrix is not closed by ']' (a file cut short?)");
  if (const auto a = matrices.find("alpha"); a != matrices.end())
    for (std::size_t i = 0; i < a->second.rows; ++i) {
      const double* r = a->second.row(i);
      out.alpha.push_back({r[0], r[1], r[2]});
    }
  const auto plus = matrices.find("Aplus"), minus = matrices.find("Aminus");
  if ((plus == matrices.end()) != (minus == matrices.end()))
    throw ReadError(out.source + ": holds " + (plus == matrices.end() ? "Aminus but not Aplus" : "Aplus but not Aminus") +
                    "; MBDyn writes both");
  if (plus != matrices.end()) {
    const bool is_sparse = sparse.contains("Aplus") || sparse.contains("Aminus");
    std::size_t n_plus = 0, n_minus = 0;
    out.aplus = square_matrix("Aplus", plus->second, is_sparse, out.source, n_plus);
    out.aminus = square_matrix("Aminus", minus->second, is_sparse, out.source, n_minus);
    if (n_plus != n_minus)
      throw ReadError(out.source + ": Aplus is " + std::to_string(n_plus) + " x " + std::to_string(n_plus) + ", Aminus " +
                      std::to_string(n_minus) + " x " + std::to_string(n_minus) + "; they are the same size");
    out.size = n_plus;
    out.sparse = is_sparse;
  }
  if (out.alpha.empty() && out.size == 0)
    throw ReadError(out.source + ": holds neither the eigenvalues (alpha: `output eigenvectors` in the eigenanalysis card) "
                                 "nor the matrices (Aplus, Aminus: `output matrices` or `output sparse matrices`)");
  if (!out.coefficient)
    throw ReadError(out.source + ": no dCoef (MBDyn writes it first, after dTime): the eigenvalues cannot be mapped to 1/s");
  if (!(*out.coefficient > 0.0))
    throw ReadError(out.source + ": dCoef = " + std::to_string(*out.coefficient) + ": expected a positive number (half a time step)");
  return out;
}

// ---- the .out's eigenvalue tables (layout: mbdyn_eigenanalysis.hpp) ----

/// "k:" with k a whole number: a table row's label.
std::optional<std::size_t> row_number(std::string_view t) {
  long k = 0;
  if (t.size() < 2 || t.back() != ':' || !detail::parse_long(t.substr(0, t.size() - 1), k) || k < 0) return std::nullopt;
  return static_cast<std::size_t>(k);
}

/// One row `k: REAL +|- IMAG j DAMP FREQ` of `e`'s table, the table's row `expected`.
void read_table_row(const std::vector<std::string_view>& w, std::size_t expected, MbdynEigenanalysis& e, const LineSource& src) {
  const std::string form = "expected 'k: REAL +|- IMAG j DAMP FREQ' (MBDyn's eigenvalue table)";
  if (*row_number(w[0]) != expected)
    throw ReadError(src.where() + ": row " + std::string(w[0]) + " where row " + std::to_string(expected) + ": was next; " + form);
  if (w.size() != 7) throw ReadError(src.where() + ": " + std::to_string(w.size()) + " fields where 7 were; " + form);
  if (w[2] != "+" && w[2] != "-")
    throw ReadError(src.where() + ": '" + std::string(w[2]) + "' where the imaginary part's sign (+ or -) was; " + form);
  if (w[4] != "j") throw ReadError(src.where() + ": '" + std::string(w[4]) + "' where 'j' was; " + form);
  const auto value = [&](std::size_t i, const char* what) -> std::optional<double> {
    if (w[i] == "PI") return std::nullopt;  // older MBDyn: Lambda = -1, omega = pi / h
    double v = 0.0;
    if (!detail::parse_double(w[i], v))
      throw ReadError(src.where() + ": " + what + ": expected a number, found '" + std::string(w[i]) + "'");
    return v;
  };
  const auto real = value(1, "real part"), imag = value(3, "imaginary part");
  value(5, "damping"), value(6, "frequency");  // checked, not kept: both follow from s
  if (!real || !imag || !std::isfinite(*real) || !std::isfinite(*imag)) {
    ++e.printed_at_infinity;  // (Lambda + 1) = 0 divides by zero in do_eig: a constraint's algebraic row
    return;
  }
  e.printed.emplace_back(*real, w[2] == "-" ? -*imag : *imag);  // older MBDyn: "+ -44.67" (omega with its sign)
}

MbdynOutEigenanalyses parse_out_tables(LineSource& src) {
  MbdynOutEigenanalyses out;
  std::optional<double> time;
  long last_step = -1;
  std::string status;  // the eigensolver's status line before a table, and where it is
  std::string status_where;
  MbdynEigenanalysis* table = nullptr;
  std::size_t rows = 0;
  std::string_view line;
  while (src.next(line)) {
    const std::string_view t = trim(line);
    if (table != nullptr) {
      const auto w = detail::tokens(t);
      if (!w.empty() && row_number(w[0])) {
        read_table_row(w, ++rows, *table, src);
        continue;
      }
      table = nullptr;  // any other line ends the table
    }
    if (t.starts_with("Step ")) {
      const auto w = detail::tokens(t);  // 7 fields before 2011, 8 or 9 since: the step and the time lead
      long step = 0;
      double at = 0.0;
      if (w.size() < 3 || !detail::parse_long(w[1], step) || !detail::parse_double(w[2], at) || !std::isfinite(at))
        throw ReadError(src.where() + ": expected 'Step STEP TIME TSTEP NITER RESERR SOLERR SOLCONV [OUT]'");
      if (step > last_step) time = at, last_step = step;  // debug builds repeat earlier steps out of sequence
    } else if (t.starts_with("Info: ") || t.starts_with("INFO: ")) {
      status = std::string(t), status_where = src.where();
    } else if (t.starts_with("Mode n.")) {
      MbdynEigenanalysis& e = out.analyses.emplace_back();
      e.source = src.where();
      e.time = time;
      const bool success = status.starts_with("Info: 0,") || status == "INFO: 0" || status.empty();
      if (!success)
        out.warnings.push_back(status_where + ": MBDyn's eigensolver reported '" + status +
                               "' before the table at line " + std::to_string(src.line_number()) + ": its eigenvalues may be incomplete");
      status.clear();
      table = &e, rows = 0;
    }
  }
  return out;
}

}  // namespace

namespace detail {

void check_matrix_size(const std::string& where, std::size_t n) {
  if (n > kLargestEigenanalysisMatrix)
    throw ReadError(where + ": " + std::to_string(n) + " x " + std::to_string(n) + ": more than the " +
                    std::to_string(kLargestEigenanalysisMatrix) +
                    " this reader holds dense; ask MBDyn for its eigenvalues (`output eigenvectors` writes alpha)");
}

std::vector<double> matrix_from_triplets(const double* t, std::size_t count, std::size_t size, const std::string& where,
                                         std::size_t& n) {
  check_matrix_size(where, size);  // a size the file names is refused before its indices are read against it
  const std::size_t largest = size > 0 ? size : kLargestEigenanalysisMatrix;
  n = size;
  for (std::size_t i = 0; i < count; ++i)
    for (int k = 0; k < 2; ++k) {
      const double index = t[3 * i + k];
      if (!(index >= 1.0) || index != std::floor(index) || index > static_cast<double>(largest))
        throw ReadError(where + ": index " + std::to_string(index) + " (triplet " + std::to_string(i + 1) +
                        "): expected a whole number from 1 to " + std::to_string(largest));
      if (size == 0) n = std::max(n, static_cast<std::size_t>(index));
    }
  if (count == 0) throw ReadError(where + ": an empty matrix");
  check_matrix_size(where, n);
  std::vector<double> a(n * n, 0.0);
  for (std::size_t i = 0; i < count; ++i)
    a[(static_cast<std::size_t>(t[3 * i]) - 1) * n + static_cast<std::size_t>(t[3 * i + 1]) - 1] += t[3 * i + 2];
  return a;
}

}  // namespace detail

MbdynEigenanalysis parse_mbdyn_eigenanalysis(std::string_view text, const std::string& source) {
  auto src = LineSource::from_memory(text, source);
  return parse(src);
}

MbdynEigenanalysis read_mbdyn_eigenanalysis(const std::string& path) {
  auto src = LineSource::open(path);
  return parse(src);
}

MbdynOutEigenanalyses parse_mbdyn_out_eigenanalyses(std::string_view text, const std::string& source) {
  auto src = LineSource::from_memory(text, source);
  return parse_out_tables(src);
}

MbdynOutEigenanalyses read_mbdyn_out_eigenanalyses(const std::string& path) {
  auto src = LineSource::open(path);
  return parse_out_tables(src);
}

std::vector<std::string> mbdyn_eigenanalysis_files(const std::string& prefix) {
  namespace fs = std::filesystem;
  const fs::path p(prefix);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  const std::string stem = p.filename().string();
  std::error_code ec;
  std::vector<std::pair<std::pair<int, long long>, std::string>> found;  // ((kind, number), path)
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.ends_with(".m") || !name.starts_with(stem)) continue;
    const std::string_view middle = std::string_view(name).substr(stem.size(), name.size() - stem.size() - 2);
    if (middle.empty()) {
      found.push_back({{0, 0}, p.has_parent_path() ? (dir / name).string() : name});
      continue;
    }
    // MBDyn's suffixes: "_<k>", zero-padded by `suffix width`, or "_" + `suffix format` of k
    if (middle.size() < 2 || middle.front() != '_' || middle.size() > 19 ||
        !std::all_of(middle.begin() + 1, middle.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    found.push_back({{1, std::stoll(std::string(middle.substr(1)))}, p.has_parent_path() ? (dir / name).string() : name});
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> paths;
  for (auto& f : found) paths.push_back(std::move(f.second));
  return paths;
}

}  // namespace mlce::reader
