#include "series_input.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "mlce/mean_period.hpp"
#include "mlce/reader/column_file.hpp"
#include "mlce/reader/format.hpp"
#include "mlce/transient.hpp"
#include "cli_common.hpp"

namespace mlce::cli {

reader::ChannelSet load_channels(const std::string& file, const std::vector<std::string>& specs,
                                 const reader::ReadOptions& options) {
  std::vector<reader::ChannelSpec> parsed;
  for (const auto& s : specs) {
    try {
      parsed.push_back(reader::parse_channel_spec(s));
    } catch (const reader::ReadError& e) {
      throw OptionError(e.what());  // a command-line mistake, not bad data
    }
  }
  const auto& format = reader::default_registry().for_path(file);
  return format.read(file, parsed, options);
}

namespace {

/// The loaded samples checked as the command needs them: finite, equal lengths, no constant channel
/// (unless allowed), no isolated spike from the window's start on (--despike replaces them first).
/// A spike before a numeric --from is left to the window, which cuts it out.
void check_loaded(const SeriesInput& in, LoadedSeries& out) {
  validate_samples(out.series);
  if (in.despike) {
    auto replaced = replace_isolated_spikes(out.series);
    out.warnings.insert(out.warnings.end(), replaced.begin(), replaced.end());
  }
  if (!in.constant_channels_allowed) validate_series(out.series);  // a constant channel: named
  const auto from = in.start_is_automatic() ? std::nullopt : parse_finite(in.from);
  refuse_isolated_spikes(out.series, {}, from ? first_sample_from(out.series, *from) : 0);
}

/// A solver result set (MBDyn text or NetCDF): time comes with the channels.
LoadedSeries load_solver_channels(const SeriesInput& in) {
  using reader::ReadError;
  if (in.time_column || in.dt || !in.columns.empty())
    throw OptionError(in.file + " is a solver output set: select channels with --channel SPEC "
                      "(--column/--time-column/--dt are for column files)");
  if (in.channels.empty())
    throw OptionError(in.file + ": say which channel(s) to analyse with --channel SPEC "
                      "(e.g. rel:13:4:z, node:2:x, joint:33:14; 'mlce channels " + in.file + "' lists them)");
  reader::ReadOptions read_options;  // steps after --to are not read: a run may diverge after the window
  if (in.to) read_options.until = *in.to;
  reader::ChannelSet cs = load_channels(in.file, in.channels, read_options);
  LoadedSeries out;
  out.warnings = cs.warnings;
  try {
    SamplingOptions so;
    so.resample = in.resample;
    out.series = make_series_from_time(cs.time, std::move(cs.values), so, &out.warnings, in.time_unit);
    out.series.names = cs.names;
    check_loaded(in, out);
  } catch (const InputError& e) {
    if (e.index() != InputError::npos && e.index() < cs.time.size())
      throw ReadError(fmt::format("{}: output block {} (t = {}): {}", cs.source, e.index(), cs.time[e.index()], e.what()));
    throw ReadError(cs.source + ": " + e.what());
  }
  return out;
}

}  // namespace

LoadedSeries load_column_series(const SeriesInput& in);
LoadedSeries apply_window(const SeriesInput& in, LoadedSeries out);

void check_series_options(const SeriesInput& in) {
  for (const auto& spec : in.channels) {
    try {
      reader::parse_channel_spec(spec);
    } catch (const reader::ReadError& e) {
      throw OptionError(e.what());
    }
  }
  if (in.time_column && in.dt) throw OptionError("give either --time-column or --dt, not both");
  if (!in.start_is_automatic() && !parse_finite(in.from))
    throw OptionError("--from '" + in.from + "': expected a time or 'auto'");
}

LoadedSeries load_series(const SeriesInput& in_) {
  using reader::ReadError;
  check_series_options(in_);
  SeriesInput in = in_;
  LoadedSeries out;
  if (reader::default_registry().for_path(in.file).name() != "column") {
    out = load_solver_channels(in);
  } else {
    for (const auto& spec : in.channels) {
      reader::ChannelSpec c;
      try {
        c = reader::parse_channel_spec(spec);
      } catch (const reader::ReadError& e) {
        throw OptionError(e.what());
      }
      if (c.kind != reader::ChannelSpec::Kind::column)
        throw OptionError(in.file + " is a column file: channel '" + spec + "' does not apply (use col:K or --column K)" +
                          reader::missing_mbdyn_out_hint(in.file));
      in.columns.push_back(std::to_string(c.column));
    }
    out = load_column_series(in);
  }
  return apply_window(in, std::move(out));
}

/// A --column / --time-column value: a 1-based number, or a name from the file's header line (a
/// header has no numeric field, so the two never clash).
std::size_t resolve_column(const reader::Table& table, const std::string& file, const std::string& given, const char* option) {
  using reader::ReadError;
  const std::size_t ncols = table.columns.size();
  std::size_t number = 0;
  const auto [end, ec] = std::from_chars(given.data(), given.data() + given.size(), number);
  if (end == given.data() + given.size() && !given.empty()) {  // all digits (an overflow reads as too large)
    if (ec != std::errc() || number == 0 || number > ncols)
      throw ReadError(fmt::format("{}: {} {} requested, but the file has {} column(s), numbered from 1", file, option, given, ncols));
    return number;
  }
  if (!table.has_header)
    throw ReadError(fmt::format("{}: {} '{}': expected a 1-based column number (the file has no header line naming "
                                "its columns)", file, option, given));
  std::vector<std::size_t> named;  // 1-based
  for (std::size_t k = 0; k < ncols; ++k)
    if (table.names[k] == given) named.push_back(k + 1);
  if (named.size() > 1)
    throw ReadError(fmt::format("{}: {} '{}': {} columns are named so ({}): give the column's number", file, option,
                                given, named.size(), fmt::join(named, ", ")));
  if (named.size() == 1) return named.front();
  throw ReadError(fmt::format("{}: {} '{}': no such column; the header names {}", file, option, given,
                              fmt::join(table.names, ", ")));
}

namespace {

/// Time of row k: the time column's value, k * --dt, or k (per sample).
double row_time(const reader::Table& table, std::optional<std::size_t> time_column, const SeriesInput& in, std::size_t k) {
  if (time_column) return table.columns[*time_column - 1][k];
  return static_cast<double>(k) * in.dt.value_or(1.0);
}

/// The leading rows at times <= --to (all without it), by the rule solver sets are read with
/// (reader::steps_until): the rows after the window are not analysed, so a run that diverged (nan,
/// inf) after it is readable.
std::size_t rows_to_read(const reader::Table& table, std::optional<std::size_t> time_column, const SeriesInput& in) {
  if (!in.to) return table.rows();
  reader::ReadOptions until;
  until.until = *in.to;
  if (time_column) return reader::steps_until(table.columns[*time_column - 1], until, in.file);
  std::vector<double> t(table.rows());
  for (std::size_t k = 0; k < t.size(); ++k) t[k] = row_time(table, time_column, in, k);
  return reader::steps_until(t, until, in.file);
}

/// A nan or inf among the rows read of the columns used: one line naming the file line and column,
/// and, when earlier rows are finite (a run that diverged), the time up to which they can be analysed.
void refuse_nonfinite(const reader::Table& table, const std::vector<std::size_t>& used, std::size_t rows,
                      std::optional<std::size_t> time_column, const SeriesInput& in) {
  for (std::size_t k = 0; k < rows; ++k)
    for (std::size_t c : used) {
      const double v = table.columns[c - 1][k];
      if (std::isfinite(v)) continue;
      std::string hint;
      if (k > 0)
        hint = fmt::format(" (did the run diverge? the {} rows before it, to t = {}, are finite: --to {} analyses only "
                           "them)", k, row_time(table, time_column, in, k - 1), row_time(table, time_column, in, k - 1));
      throw reader::ReadError(fmt::format("{}: column {}: '{}': expected a finite number{}", table.where(k), c, v, hint));
    }
}

/// A header name that says "time": t, time, or either followed by a unit or an index ("time [s]",
/// "Time_s", "t (s)"); case aside. Not "temperature", "tip", "theta".
bool looks_like_time(const std::string& name) {
  std::string n;
  for (char c : name) n += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto word_ends = [&](std::size_t at) {
    return at >= n.size() || !std::isalnum(static_cast<unsigned char>(n[at]));
  };
  return (n.starts_with("time") && word_ends(4)) || (n.starts_with("t") && word_ends(1));
}

}  // namespace

LoadedSeries load_column_series(const SeriesInput& in) {
  using reader::ReadError;
  if (in.time_column && in.dt) throw OptionError("give either --time-column or --dt, not both");
  reader::ColumnFileOptions read_options;
  read_options.keep_nonfinite = true;  // refused below, in the rows analysed
  read_options.text_columns = true;    // text is refused below, in the columns analysed
  reader::Table table = reader::read_column_file(in.file, read_options);
  const std::size_t ncols = table.columns.size();
  std::optional<std::size_t> time_column;
  if (in.time_column) time_column = resolve_column(table, in.file, *in.time_column, "--time-column");
  std::vector<std::size_t> cols;
  for (const auto& c : in.columns) cols.push_back(resolve_column(table, in.file, c, "--column"));
  if (cols.empty()) {
    if (ncols == 1) {
      cols.push_back(1);
    } else if (ncols == 2 && time_column) {
      cols.push_back(*time_column == 1 ? 2 : 1);
    } else {
      throw ReadError(fmt::format("{}: the file has {} columns: say which to analyse with --column K "
                                  "(and --time-column K or --dt DT)", in.file, ncols));
    }
  }

  // Text is refused in the columns analysed only (a column of dates or labels beside them is no
  // error): in the time column anywhere, in the others up to the last row analysed (--to), as
  // non-finite values are (a diverged run's overflow, "*****" from Fortran, after it).
  if (time_column) table.require_numbers({*time_column - 1});
  const std::size_t rows = rows_to_read(table, time_column, in);
  std::vector<std::size_t> used = cols;
  if (time_column) used.push_back(*time_column);
  std::vector<std::size_t> used_index;  // 0-based
  for (const std::size_t c : used) used_index.push_back(c - 1);
  table.require_numbers(used_index, table.line_of(rows - 1));
  refuse_nonfinite(table, used, rows, time_column, in);

  LoadedSeries out;
  out.warnings = table.warnings;  // a partial last line left out
  std::vector<std::vector<double>> channels;
  auto leading = [&](std::size_t column) {
    const auto& v = table.columns[column - 1];
    return std::vector<double>(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(rows));
  };
  for (std::size_t k : cols) channels.push_back(leading(k));
  try {
    if (time_column) {
      SamplingOptions so;
      so.resample = in.resample;
      out.series = make_series_from_time(leading(*time_column), std::move(channels), so, &out.warnings, in.time_unit);
    } else if (in.dt) {
      out.series = make_series_with_step(std::move(channels), *in.dt, in.time_unit);
    } else {
      out.series = make_series_with_step(std::move(channels), 1.0, "");  // per sample
      // A column the header names as time, left out: the analyst most likely forgot --time-column,
      // and per-sample figures read as per-second ones are off by the sampling rate.
      for (std::size_t k = 1; k <= ncols; ++k)
        if (table.has_header && looks_like_time(table.names[k - 1]) &&
            std::find(cols.begin(), cols.end(), k) == cols.end()) {
          out.warnings.push_back(fmt::format("the results are per sample: column {} ('{}') looks like the time; "
                                             "--time-column {} (or --dt DT) gives them per time unit",
                                             k, table.names[k - 1], k));
          break;
        }
    }
    for (std::size_t k : cols) out.series.names.push_back(table.names[k - 1]);
    check_loaded(in, out);
  } catch (const InputError& e) {
    if (e.index() != InputError::npos) throw ReadError(table.where(e.index()) + ": " + e.what());
    throw ReadError(in.file + ": " + e.what());
  }
  return out;
}

namespace {
/// --from auto: the transient as skip_transient finds it, on the channels that move when a constant
/// one is allowed (it has no transient, and the rule refuses it); every channel cut at its end.
Series skip_transient_of_moving_channels(const SeriesInput& in, const Series& series, TransientResult& tr) {
  std::vector<std::size_t> moving_channels;
  for (std::size_t c = 0; c < series.channel_count(); ++c)
    if (!in.constant_channels_allowed || !is_constant(series, c)) moving_channels.push_back(c);
  if (moving_channels.size() == series.channel_count()) return skip_transient(series, &tr);
  const Series moving = channel_subset(series, moving_channels);
  try {
    if (moving.channels.empty()) validate_series(series);  // every channel constant: the file's error
  } catch (const InputError& e) {
    throw reader::ReadError(in.file + ": " + e.what());
  }
  skip_transient(moving, &tr);
  return time_window(series, tr.end_time, series.time(series.size() - 1));
}
}  // namespace

LoadedSeries apply_window(const SeriesInput& in, LoadedSeries out) {
  using reader::ReadError;
  if (!in.from.empty() || in.to) out.record_deviation = peak_deviations(out.series);

  if (in.from == "auto") {
    TransientResult tr;
    out.series = skip_transient_of_moving_channels(in, out.series, tr);
    out.transient_rule = tr.rule;
    if (in.to) out.series = time_window(out.series, out.series.time(0), *in.to);
  } else if (!in.from.empty() || in.to) {
    double from = out.series.time(0);
    if (!in.from.empty()) {
      const auto t = parse_finite(in.from);
      if (!t) throw OptionError("--from '" + in.from + "': expected a time or 'auto'");
      from = *t;
    }
    try {
      out.series = time_window(out.series, from, in.to.value_or(out.series.time(out.series.size() - 1)));
    } catch (const InputError& e) {
      throw ReadError(in.file + ": " + e.what());
    }
  }
  return out;
}

}  // namespace mlce::cli
