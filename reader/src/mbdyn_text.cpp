// MBDyn text output (format doc ../shared/docs/mbdyn-output-format.md, sections 1-3, 5, 9, 12).
#include "mlce/reader/mbdyn_text.hpp"

#include "mlce/reader/mbdyn_eigenanalysis.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "line_source.hpp"
#include "mlce/reader/table.hpp"
#include "node_fields.hpp"
#include "text_fields.hpp"

namespace mlce::reader {
namespace {

using detail::LineSource;
using detail::is_blank;
using detail::next_token;
using detail::parse_double;
using detail::parse_long;
using detail::tokens;

/// File `ext` of the output set `prefix`: PREFIX.ext, or PREFIX.ext.gz when only that is there.
std::string set_file(const std::string& prefix, const std::string& ext) { return detail::stored_file(prefix + "." + ext); }

std::string shorten(std::string_view s) {
  std::string t(s.substr(0, 32));
  if (s.size() > 32) t += "...";
  return t;
}

MbdynLog parse_log(LineSource& src) {
  MbdynLog log;
  std::string_view line;
  while (src.next(line)) {
    if (line.empty() || is_blank(line.front())) continue;  // continuation lines, symbol table
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) continue;
    const std::string_view key = line.substr(0, colon);
    const std::string_view rest = line.substr(colon + 1);
    if (key == "output frequency") {
      long f = 0;
      const auto t = tokens(rest);
      if (!t.empty() && parse_long(t[0], f) && f > 0) log.output_frequency = static_cast<std::size_t>(f);
      continue;
    }
    if (key == "structural node" || key == "relative frame structural node") {
      const auto t = tokens(rest);
      MbdynLog::Node n;
      n.relative_frame = key != "structural node";
      if (t.size() < 4 || !parse_long(t[0], n.label))
        throw ReadError(src.where() + ": expected 'structural node: LABEL X Y Z [DESCRIPTION VALUES]'");
      for (int k = 0; k < 3; ++k)
        if (!parse_double(t[1 + static_cast<std::size_t>(k)], n.position[k]))
          throw ReadError(src.where() + ": node " + std::to_string(n.label) + ": position is not a number");
      if (t.size() == 4) {
        n.orientation = Orientation::none;  // displacement-only node: no description
      } else {
        const auto o = orientation_from_name(t[4]);
        if (!o || *o == Orientation::none)
          throw ReadError(src.where() + ": node " + std::to_string(n.label) + ": orientation description '" +
                          shorten(t[4]) + "', expected euler123, euler313, euler321, phi or mat");
        n.orientation = *o;
        const std::size_t need = orientation_size(*o);
        if (t.size() != 5 + need)
          throw ReadError(src.where() + ": node " + std::to_string(n.label) + ": " + std::to_string(t.size() - 5) +
                          " orientation numbers, expected " + std::to_string(need) + " for " + orientation_name(*o));
        for (std::size_t k = 0; k < need; ++k) {
          double v = 0.0;
          if (!parse_double(t[5 + k], v) || !std::isfinite(v))
            throw ReadError(src.where() + ": node " + std::to_string(n.label) + ": orientation number '" +
                            shorten(t[5 + k]) + "' is not a finite number");
          n.values.push_back(v);
        }
      }
      log.nodes.push_back(std::move(n));
      continue;
    }
    // Element lines `keyword: label ...` (joints, bodies, ...): remembered for listings.
    if (key.find(' ') == std::string_view::npos) {
      std::size_t pos = 0;
      long label = 0;
      if (parse_long(next_token(rest, pos), label)) log.elements.emplace(label, std::string(key));
    }
  }
  return log;
}

/// Significant digits of a printed number: the mantissa's digits from its first non-zero one
/// ('1000.01' 6, '0.01500000000000001' 16, '1e-08' 1; '1000' 1, as %g strips its zeros).
int printed_digits(std::string_view token) {
  int digits = 0;
  bool leading = true;
  for (const char ch : token) {
    if (ch == 'e' || ch == 'E') break;
    if (ch < '0' || ch > '9') continue;
    if (leading && ch == '0') continue;
    leading = false;
    ++digits;
  }
  return digits;
}

/// Late times printed with 6 significant digits (MBDyn's default `%g` for the .out, format doc
/// sections 1, 2 and 10) no longer resolve the output step: t = 1000.005 prints '1000', 1000.010
/// prints '1000.01', so block times repeat or jump. MBDyn advances its time by TStep each step, so
/// the times can be rebuilt as t_k = c + sum over the Step lines up to k of (step index increase) x
/// TStep (long double), with the constant c inside every printed time's rounding interval: half a
/// unit in its P-th significant digit, P the most digits any printed time has (6 for `%g`, more or
/// fewer with 'output precision'), widened by the accumulated rounding of the printed TSteps at the
/// same P. c is the first line's printed time when that fits (an initial time is an input number,
/// printed exactly), else the nearest value that does. Fed one Step line at a time, with the
/// interval kept for every P = 1..17 until P is known (O(output blocks) memory however many steps
/// the run took). The times are replaced only when the printed spacing of the blocks differs from
/// the rebuilt one by more than 1e-4 of it (full-precision files stay as printed) and one c fits
/// every line (otherwise they stay as printed, and the series check reports them).
class CoarseTimes {
 public:
  static constexpr int kMaxDigits = 17;
  void add(long step, double time, int time_digits, double tstep, bool out) {
    if (lines_ > 0) {
      if (!(tstep > 0.0) || !std::isfinite(tstep)) usable_ = false;
      const auto steps = static_cast<long double>(step - last_step_);
      rebuilt_ += steps * tstep;
      if (tstep != cached_tstep_) cached_tstep_ = tstep, cached_tstep_unit_ = unit_above(tstep);
      const double unit = cached_tstep_unit_ * static_cast<double>(steps);
      for (int p = 1; p <= kMaxDigits; ++p) slack_[p] += 0.5 * unit * kTenTo[p];
    } else {
      first_time_ = time;
    }
    ++lines_;
    last_step_ = step;
    digits_ = std::max(digits_, std::min(time_digits, kMaxDigits));
    if (!usable_) return;
    const double d = time - static_cast<double>(rebuilt_);
    // unit_above changes only when |time| crosses a power of ten: recomputed then (pow and log10
    // on every Step line of a million-step run would cost more than reading the line).
    if (const double a = std::abs(time); !(a >= time_unit_ / 10.0 && a < time_unit_)) time_unit_ = unit_above(time);
    const double unit = time_unit_;
    for (int p = 1; p <= kMaxDigits; ++p) {
      const double tol = 0.5 * unit * kTenTo[p] + slack_[p] + 1e-12 * std::abs(time);
      lo_[p] = std::max(lo_[p], d - tol), hi_[p] = std::min(hi_[p], d + tol);
    }
    if (out) rebuilt_out_.push_back(rebuilt_);
  }
  /// Replaces t.time when it has to and can; returns the warning, or "".
  std::string apply(MbdynTimes& t, const std::string& source) const {
    const int p = std::max(digits_, 1);
    if (!usable_ || !(lo_[p] <= hi_[p]) || t.time.size() < 2 || rebuilt_out_.size() != t.time.size()) return "";
    std::size_t coarse = 0;
    for (std::size_t k = 1; k < t.time.size() && coarse == 0; ++k) {
      const double dp = t.time[k] - t.time[k - 1], dr = static_cast<double>(rebuilt_out_[k] - rebuilt_out_[k - 1]);
      if (!(std::abs(dp - dr) <= 1e-4 * dr)) coarse = k;
    }
    if (coarse == 0) return "";
    std::ostringstream note;
    note.precision(10);
    note << source << ": times printed with " << p << " significant digits, too few to resolve the output step (blocks "
         << coarse - 1 << " and " << coarse << " print " << t.time[coarse - 1] << " and " << t.time[coarse]
         << "); rebuilt from the Step indices and time steps, which agree with every printed time to within its "
            "last digit (an 'output precision' of 10 or more in the input avoids this)";
    const long double c = std::clamp(first_time_, lo_[p], hi_[p]);
    for (std::size_t k = 0; k < t.time.size(); ++k) t.time[k] = static_cast<double>(c + rebuilt_out_[k]);
    return note.str();
  }

 private:
  /// 10^(floor(log10 |v|) + 1): a unit in the P-th significant digit of v is this x 10^-P.
  static double unit_above(double v) {
    const double a = std::abs(v);
    return a > 0.0 ? std::pow(10.0, std::floor(std::log10(a)) + 1.0) : 0.0;
  }
  static constexpr std::array<double, kMaxDigits + 1> kTenTo = [] {
    std::array<double, kMaxDigits + 1> t{};
    double v = 1.0;
    for (auto& x : t) x = v, v /= 10.0;
    return t;
  }();  // kTenTo[p] = 10^-p
  std::size_t lines_ = 0;
  long last_step_ = 0;
  double cached_tstep_ = std::numeric_limits<double>::quiet_NaN(), cached_tstep_unit_ = 0.0;
  double time_unit_ = 0.0;  // unit_above of the last time: 10^k with 10^(k-1) <= |time| < 10^k
  bool usable_ = true;
  int digits_ = 0;              // most significant digits of a printed time
  long double rebuilt_ = 0.0L;  // time since the first line, from steps x TStep
  std::array<double, kMaxDigits + 1> slack_{};  // accumulated rounding of the printed TSteps, per P
  double first_time_ = 0.0;
  std::array<double, kMaxDigits + 1> lo_ = filled(-std::numeric_limits<double>::infinity());
  std::array<double, kMaxDigits + 1> hi_ = filled(std::numeric_limits<double>::infinity());
  std::vector<long double> rebuilt_out_;  // rebuilt_ at every written block
  static std::array<double, kMaxDigits + 1> filled(double v) {
    std::array<double, kMaxDigits + 1> a;
    a.fill(v);
    return a;
  }
};

MbdynTimes parse_out(LineSource& src, std::size_t frequency) {
  MbdynTimes t;
  CoarseTimes coarse;
  std::string_view line;
  long last_step = -1;
  while (src.next(line)) {
    if (line.starts_with("Mode n.")) ++t.eigenvalue_tables;
    if (line.size() < 5 || line.substr(0, 5) != "Step ") continue;
    const auto f = tokens(line);
    long step = 0;
    double time = 0.0;
    if ((f.size() != 8 && f.size() != 9) || !parse_long(f[1], step) || !parse_double(f[2], time) || !std::isfinite(time))
      throw ReadError(src.where() + ": expected 'Step STEP TIME TSTEP NITER RESERR SOLERR SOLCONV [OUT]'");
    if (step <= last_step) continue;  // out-of-sequence lines of debug builds
    bool out = false;
    if (f.size() == 9) {
      long flag = 0;
      if (!parse_long(f[8], flag) || (flag != 0 && flag != 1))
        throw ReadError(src.where() + ": output flag '" + shorten(f[8]) + "', expected 0 or 1");
      out = flag == 1;
    } else {
      t.seven_fields = true;
      if (frequency == 0)
        throw ReadError(src.where() + ": 7-field Step line (MBDyn before 2011) and the .log states no numeric "
                        "output frequency: cannot tell which steps were written");
      out = step % static_cast<long>(frequency) == 0;
    }
    last_step = step;
    double tstep = std::numeric_limits<double>::quiet_NaN();
    if (!parse_double(f[3], tstep)) tstep = std::numeric_limits<double>::quiet_NaN();
    coarse.add(step, time, printed_digits(f[2]), tstep, out);
    ++t.step_lines;
    if (out) {
      t.time.push_back(time);
      t.step.push_back(step);
    }
  }
  t.rebuilt = coarse.apply(t, src.name());
  // A Step line cut mid-write (partial tail) is not returned by the source: its block, if any, is
  // left over and the block-count check reports it.
  return t;
}

BlockRead parse_blocks(LineSource& src, const std::vector<BlockRequest>& requests, const BlockOptions& options) {
  BlockRead r;
  r.source = src.name();
  r.values.assign(requests.size(), {});
  std::string_view line;
  // Per row position: which requests it serves (request index, column).
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> wants;
  std::vector<double> pending(requests.size(), 0.0);
  std::vector<std::string_view> fields;
  std::size_t row = 0;  // row index within the current block
  bool layout_done = false;
  // The first block fixes the layout (labels in order, columns per row); it is kept (a few rows)
  // until the first repeated label ends it, then served like every other block.
  std::vector<std::string> first_lines;
  std::vector<std::size_t> first_numbers;
  auto where = [&](std::size_t line_no) { return r.source + ":" + std::to_string(line_no); };
  auto label_of = [&](std::string_view l, std::size_t line_no) {
    std::size_t pos = 0;
    const std::string_view tok = next_token(l, pos);
    const auto label = parse_row_label(tok);
    if (!label)
      throw ReadError(where(line_no) + ": expected an integer label at the start of the row (or LABEL.MODE, LABEL@NODE, "
                      "LABEL#NODE), found '" + shorten(tok) + "'");
    return *label;
  };
  auto take_row = [&](std::size_t p, std::string_view l, std::size_t line_no) {
    fields.clear();
    std::size_t pos = 0;
    for (auto t = next_token(l, pos); !t.empty(); t = next_token(l, pos)) fields.push_back(t);
    if (fields.size() != r.columns[p])
      throw ReadError(where(line_no) + ": label " + row_label_text(r.labels[p]) + ": " + std::to_string(fields.size()) +
                      " columns, expected " + std::to_string(r.columns[p]) + " as in the first block");
    for (const auto& [q, col] : wants[p]) {
      double v = 0.0;
      const std::string_view tok = fields[col - 1];
      if (!parse_double(tok, v))
        throw ReadError(where(line_no) + ": column " + std::to_string(col) + ": '" + shorten(tok) + "' is not a number");
      if (!std::isfinite(v)) {
        // Say where the run stopped being finite: the steps before it can still be read (ReadOptions::until).
        char hint[200] = "";
        if (r.blocks < options.times.size() && r.blocks > 0)
          std::snprintf(hint, sizeof hint, " This block is at t = %.10g; the %zu before it, to t = %.10g, are finite",
                        options.times[r.blocks], r.blocks, options.times[r.blocks - 1]);
        throw ReadError(where(line_no) + ": column " + std::to_string(col) + ": '" + shorten(tok) +
                        "': expected a finite number (did the run diverge?" + hint + ")");
      }
      pending[q] = v;
    }
  };
  auto commit = [&]() {
    for (std::size_t q = 0; q < requests.size(); ++q) r.values[q].push_back(pending[q]);
    ++r.blocks;
  };
  auto finish_layout = [&]() {
    layout_done = true;
    wants.assign(r.labels.size(), {});
    for (std::size_t q = 0; q < requests.size(); ++q) {
      const auto it = std::find(r.labels.begin(), r.labels.end(), requests[q].label);
      if (it == r.labels.end()) {
        std::string have;
        for (std::size_t k = 0; k < r.labels.size() && k < 16; ++k) {
          if (k) have += ' ';
          have += row_label_text(r.labels[k]);
        }
        throw ReadError(r.source + ": no rows of label " + row_label_text(requests[q].label) + " (labels in a block: " +
                        have + (r.labels.size() > 16 ? " ..." : "") + ")");
      }
      const std::size_t p = static_cast<std::size_t>(it - r.labels.begin());
      if (requests[q].column < 2 || requests[q].column > r.columns[p])
        throw ReadError(where(first_numbers[p]) + ": label " + row_label_text(requests[q].label) + " has " +
                        std::to_string(r.columns[p]) + " columns, column " + std::to_string(requests[q].column) +
                        " requested");
      wants[p].emplace_back(q, requests[q].column);
    }
    for (std::size_t p = 0; p < first_lines.size(); ++p)
      if (!wants[p].empty()) take_row(p, first_lines[p], first_numbers[p]);
    commit();
    first_lines.clear();
  };

  while (!(layout_done && r.blocks >= options.max_blocks) && src.next(line)) {
    if (line.find_first_not_of(" \t") == std::string_view::npos)
      throw ReadError(src.where() + ": empty line inside the output blocks");
    const long label = label_of(line, src.line_number());
    if (!layout_done) {
      if (std::find(r.labels.begin(), r.labels.end(), label) == r.labels.end()) {
        r.labels.push_back(label);
        r.columns.push_back(tokens(line).size());
        first_lines.emplace_back(line);
        first_numbers.push_back(src.line_number());
        continue;
      }
      finish_layout();
      row = 0;
      if (r.blocks >= options.max_blocks) break;
    }
    if (label != r.labels[row]) {
      throw ReadError(src.where() + ": expected the row of label " + row_label_text(r.labels[row]) + " (row " +
                      std::to_string(row + 1) + " of " + std::to_string(r.labels.size()) + " in a block), found label " +
                      row_label_text(label));
    }
    if (!wants[row].empty()) take_row(row, line, src.line_number());
    if (++row == r.labels.size()) {
      commit();
      row = 0;
    }
  }
  // A file holding a single block: the layout ends with the file.
  if (!layout_done && !r.labels.empty()) finish_layout();
  if (src.partial_tail())
    r.warnings.push_back(r.source + ": the last line has no end of line (run interrupted mid-write): dropped");
  if (row != 0)
    r.warnings.push_back(r.source + ": the last block is incomplete (" + std::to_string(row) + " of " +
                         std::to_string(r.labels.size()) + " rows, run interrupted?): read " +
                         std::to_string(r.blocks) + " complete blocks");
  if (r.labels.empty()) throw ReadError(r.source + ": no rows (empty file)");
  return r;
}

}  // namespace

const MbdynLog::Node* MbdynLog::node(long label) const {
  for (const auto& n : nodes)
    if (n.label == label) return &n;
  return nullptr;
}

MbdynLog parse_mbdyn_log(std::string_view text, const std::string& source) {
  auto src = LineSource::from_memory(text, source);
  return parse_log(src);
}
MbdynLog read_mbdyn_log(const std::string& path) {
  auto src = LineSource::open(path);
  return parse_log(src);
}
namespace {

/// The set's .log, which the reader cannot do without: a copy of the entity files and the .out
/// alone is refused with what the .log holds, not just "cannot open".
MbdynLog read_set_log(const std::string& prefix) {
  const std::string path = set_file(prefix, "log");
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw ReadError(path + ": missing; MBDyn writes it beside " + prefix +
                    ".out and it gives each node's orientation description (how the .mov rows are laid out) and the "
                    "output frequency: copy it there too");
  return read_mbdyn_log(path);
}

}  // namespace

MbdynTimes parse_mbdyn_out(std::string_view text, const std::string& source, std::size_t frequency) {
  auto src = LineSource::from_memory(text, source);
  return parse_out(src, frequency);
}
MbdynTimes read_mbdyn_out(const std::string& path, std::size_t frequency) {
  auto src = LineSource::open(path);
  return parse_out(src, frequency);
}
BlockRead parse_mbdyn_blocks(std::string_view text, const std::string& source, const std::vector<BlockRequest>& req,
                             const BlockOptions& options) {
  auto src = LineSource::from_memory(text, source);
  return parse_blocks(src, req, options);
}
BlockRead read_mbdyn_blocks(const std::string& path, const std::vector<BlockRequest>& req, const BlockOptions& options) {
  auto src = LineSource::open(path);
  return parse_blocks(src, req, options);
}

std::string mbdyn_prefix(const std::string& compressed_or_not) {
  static const std::set<std::string> ext = {"out", "log", "mov", "jnt", "ine", "frc", "act", "aer", "prm",
                                            "drv", "abs", "ele", "prs", "hyd", "rot", "usr", "gen", "mod"};
  const std::string path = detail::without_gz(compressed_or_not);  // run.mov.gz names the set run
  const auto dot = path.rfind('.');
  const auto slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return compressed_or_not;
  return ext.count(path.substr(dot + 1)) ? path.substr(0, dot) : compressed_or_not;
}

namespace {
// Every per-entity text file (format doc sections 1, 3-8): .mod holds modal joints' rows, one per
// mode (label.mode), the scalar nodes' files one row per node.
constexpr const char* kEntityExtensions[] = {"mov", "jnt", "ine", "frc", "act", "aer", "prm", "drv",
                                             "mod", "abs", "ele", "prs", "hyd", "gen", "usr", "rot"};
}  // namespace

bool mbdyn_text_has_entity_rows(const std::string& prefix) {
  for (const char* ext : kEntityExtensions) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(set_file(prefix, ext), ec);
    if (!ec && size > 0) return true;
  }
  return false;
}

namespace {

/// Block count of every file read and of the .out must agree; an interrupted run may differ by
/// one (entity rows are written before the Step line; format doc section 12). `steps`: the output
/// steps wanted (all of the .out's, or those up to ReadOptions::until, to which the files were cut).
std::size_t common_blocks(const MbdynTimes& times, std::size_t steps, const std::string& out_path,
                          const std::vector<const BlockRead*>& files, std::vector<std::string>& warnings) {
  std::size_t n = steps;
  std::size_t lo = n, hi = n;
  for (const auto* f : files) lo = std::min(lo, f->blocks), hi = std::max(hi, f->blocks);
  if (times.step_lines == 0 && hi > 0)
    throw ReadError(out_path + ": no Step line, so the time of the " + std::to_string(hi) +
                    " output blocks is unknown (a problem block with 'output: none' writes none): keep its default "
                    "'output: messages', or read the run's .nc");
  if (hi - lo > 1) {
    std::string counts = out_path + ": " + std::to_string(times.time.size()) + " output steps";
    for (const auto* f : files) counts += ", " + f->source + ": " + std::to_string(f->blocks) + " blocks";
    // A file cut short (an interrupted copy, a full disk): the blocks every file holds can still be
    // read, up to a time (ReadOptions::until).
    char hint[160] = "";
    if (lo > 0 && lo - 1 < times.time.size())
      std::snprintf(hint, sizeof hint, "; every file holds the first %zu, to t = %.10g: read up to it (--to %.10g)", lo,
                    times.time[lo - 1], times.time[lo - 1]);
    throw ReadError("inconsistent output set: " + counts + " (expected equal counts, or one fewer for an interrupted run)" +
                    hint);
  }
  if (hi != lo) {
    std::string counts = out_path + ": " + std::to_string(times.time.size()) + " output steps";
    for (const auto* f : files) counts += ", " + f->source + ": " + std::to_string(f->blocks);
    warnings.push_back("block counts differ by one (" + counts + "): using the first " + std::to_string(lo));
  }
  if (lo == 0) throw ReadError(out_path + ": no output blocks (no Step line with the output flag set)");
  n = lo;
  return n;
}

bool file_exists(const std::string& p) {
  std::error_code ec;
  return std::filesystem::is_regular_file(p, ec);
}

/// An entity file of the set that can be read: it exists and is not empty. MBDyn run with
/// `output results: netcdf, no text` leaves its text files empty (or, built otherwise, does not
/// write them; format doc section 10), so when the run's .nc is beside them the error says to read it.
void require_entity_file(const std::string& path, const std::string& prefix) {
  const std::string nc = prefix + ".nc";
  const std::string hint = file_exists(nc) ? "; the run's NetCDF output is beside it: read " + nc : "";
  if (!file_exists(path)) throw ReadError(path + ": cannot open the file (missing or unreadable)" + hint);
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0 && !ec && !hint.empty())
    throw ReadError(path + ": no rows (empty file, as 'output results: netcdf, no text' leaves it)" + hint);
}

}  // namespace

ChannelSet read_mbdyn_text(const std::string& prefix_in, const std::vector<ChannelSpec>& channels,
                           const ReadOptions& options) {
  const std::string prefix = mbdyn_prefix(prefix_in);
  if (channels.empty()) throw ReadError(prefix + ": no channel requested (give --channel SPEC)");
  ChannelSet out;
  out.source = prefix;
  const std::string log_path = set_file(prefix, "log"), out_path = set_file(prefix, "out");
  const MbdynLog log = read_set_log(prefix);
  const MbdynTimes times = read_mbdyn_out(out_path, log.output_frequency);
  if (!times.rebuilt.empty()) out.warnings.push_back(times.rebuilt);
  const std::size_t steps = steps_until(times.time, options, out_path);
  BlockOptions block_options;
  if (steps < times.time.size()) block_options.max_blocks = steps;
  block_options.times = times.time;

  // Requests per file; each channel remembers where its numbers come from.
  std::map<std::string, std::vector<BlockRequest>> requests;
  auto request = [&](const std::string& ext, long label, std::size_t column) {
    auto& v = requests[ext];
    for (std::size_t k = 0; k < v.size(); ++k)
      if (v[k].label == label && v[k].column == column) return std::make_pair(ext, k);
    v.push_back({label, column});
    return std::make_pair(ext, v.size() - 1);
  };
  auto node_info = [&](const ChannelSpec& c, long label) -> const MbdynLog::Node& {
    const auto* n = log.node(label);
    if (!n) throw ReadError(log_path + ": channel '" + c.text + "': no structural node " + std::to_string(label));
    return *n;
  };
  struct Plan {
    std::vector<std::pair<std::string, std::size_t>> sources;  // (file, request index)
  };
  std::vector<Plan> plans(channels.size());
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const ChannelSpec& s = channels[c];
    switch (s.kind) {
      case ChannelSpec::Kind::node: {
        const auto& n = node_info(s, s.label);
        const auto f = *detail::parse_node_field(s.field);
        if (f.group == detail::NodeGroup::orientation && f.component >= orientation_size(n.orientation))
          throw ReadError(log_path + ": channel '" + s.text + "': node " + std::to_string(s.label) + " writes " +
                          std::to_string(orientation_size(n.orientation)) + " orientation numbers (" +
                          orientation_name(n.orientation) + ")");
        plans[c].sources.push_back(request("mov", s.label, detail::mov_column(f, n.orientation)));
        break;
      }
      case ChannelSpec::Kind::relative: {
        for (long l : {s.label, s.reference}) {
          const auto& n = node_info(s, l);
          if (n.orientation == Orientation::none)
            throw ReadError(log_path + ": channel '" + s.text + "': node " + std::to_string(l) +
                            " has no orientation (displacement-only node)");
          for (std::size_t k = 0; k < orientation_size(n.orientation); ++k)
            plans[c].sources.push_back(request("mov", l, 5 + k));
        }
        break;
      }
      case ChannelSpec::Kind::entity:
        plans[c].sources.push_back(request(s.extension, s.label, s.column));
        break;
      case ChannelSpec::Kind::column:
        throw ReadError(prefix + ": channel '" + s.text + "' addresses a column file; MBDyn output takes node:, joint:, rel: or EXT: channels");
      case ChannelSpec::Kind::variable:
        throw ReadError(prefix + ": channel '" + s.text + "' addresses a NetCDF variable; a text output set takes node:, "
                        "joint:, rel: or EXT: channels" + (file_exists(prefix + ".nc") ? " (or read " + prefix + ".nc)" : ""));
    }
  }
  std::map<std::string, BlockRead> read;
  std::vector<const BlockRead*> all;
  for (const auto& [ext, req] : requests) {
    const std::string path = set_file(prefix, ext);
    require_entity_file(path, prefix);
    const BlockRead& b = read.emplace(ext, read_mbdyn_blocks(path, req, block_options)).first->second;
    out.warnings.insert(out.warnings.end(), b.warnings.begin(), b.warnings.end());
    all.push_back(&b);
  }
  const std::size_t n = common_blocks(times, steps, out_path, all, out.warnings);
  out.time.assign(times.time.begin(), times.time.begin() + static_cast<std::ptrdiff_t>(n));

  for (std::size_t c = 0; c < channels.size(); ++c) {
    const ChannelSpec& s = channels[c];
    out.names.push_back(s.text);
    auto column = [&](std::size_t k) -> const std::vector<double>& {
      const auto& [ext, q] = plans[c].sources[k];
      return read.at(ext).values[q];
    };
    if (s.kind != ChannelSpec::Kind::relative) {
      const auto& v = column(0);
      out.values.emplace_back(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n));
      continue;
    }
    const auto& a = *log.node(s.label);
    const auto& b = *log.node(s.reference);
    const std::size_t na = orientation_size(a.orientation);
    std::vector<std::span<const double>> ca, cb;
    for (std::size_t i = 0; i < plans[c].sources.size(); ++i) (i < na ? ca : cb).emplace_back(column(i));
    out.values.push_back(relative_angle_series(a.orientation, ca, b.orientation, cb,
                                               rotation_matrix(a.orientation, a.values),
                                               rotation_matrix(b.orientation, b.values), s.axis, n));
  }
  return out;
}

Inventory describe_mbdyn_text(const std::string& prefix_in) {
  const std::string prefix = mbdyn_prefix(prefix_in);
  Inventory inv;
  inv.source = prefix;
  inv.format = "mbdyn-text";
  const MbdynLog log = read_set_log(prefix);
  const std::string out_path = set_file(prefix, "out");
  const MbdynTimes times = read_mbdyn_out(out_path, log.output_frequency);
  if (!times.rebuilt.empty()) inv.warnings.push_back(times.rebuilt);
  std::vector<BlockRead> all;
  std::set<long> dynamic;
  for (const char* ext : kEntityExtensions) {
    const std::string path = set_file(prefix, ext);
    if (!file_exists(path)) continue;
    require_entity_file(path, prefix);
    BlockRead b = read_mbdyn_blocks(path, {});
    inv.warnings.insert(inv.warnings.end(), b.warnings.begin(), b.warnings.end());
    if (std::string(ext) == "mov") {
      for (std::size_t k = 0; k < b.labels.size(); ++k) {
        if (b.labels[k] < 0)  // LABEL.MODE and the like belong to .mod and .frc rows
          throw ReadError(path + ": row label " + row_label_text(b.labels[k]) + ": structural nodes have integer labels");
        const auto* n = log.node(b.labels[k]);
        inv.nodes.push_back({b.labels[k], "", n ? orientation_name(n->orientation) : "unknown", b.columns[k]});
      }
    } else {
      if (std::string(ext) == "ine") dynamic.insert(b.labels.begin(), b.labels.end());
      for (std::size_t k = 0; k < b.labels.size(); ++k) {
        std::string type;
        for (auto [it, end] = log.elements.equal_range(b.labels[k]); it != end; ++it)
          if (it->second != "body") type = it->second;
        inv.entities.push_back({ext, b.labels[k], std::string(ext) == "ine" ? "inertia" : type, b.columns[k]});
      }
    }
    all.push_back(std::move(b));
  }
  if (all.empty() || !mbdyn_text_has_entity_rows(prefix))
    inv.warnings.push_back(prefix + ": no entity rows (.mov, .jnt, .ine, ... are missing or empty)" +
                           (file_exists(prefix + ".nc") ? "; the run's channels are in its NetCDF output: read " + prefix + ".nc"
                                                        : ": the set holds only its step times"));
  const bool have_ine = file_exists(set_file(prefix, "ine"));
  for (auto& n : inv.nodes) n.kind = dynamic.count(n.label) ? "dynamic" : have_ine ? "static/dummy" : "unknown";
  std::vector<const BlockRead*> files;
  for (const auto& b : all) files.push_back(&b);
  inv.blocks = common_blocks(times, times.time.size(), out_path, files, inv.warnings);
  inv.t_first = times.time.front();
  inv.t_last = times.time[inv.blocks - 1];
  inv.eigenanalyses = mbdyn_eigenanalysis_files(prefix).size();
  if (inv.eigenanalyses == 0) inv.eigenanalyses = times.eigenvalue_tables;  // as `mlce eigenanalysis SET` reads them
  return inv;
}

}  // namespace mlce::reader
