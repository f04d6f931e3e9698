#include "estimate_runs.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "cli_common.hpp"
#include "mlce/reading.hpp"
#include "plot.hpp"
#include "report.hpp"
#include "sweep_runner.hpp"

namespace mlce::cli {

RunParameter parse_run_parameter(const std::string& spec, std::size_t runs) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    throw std::invalid_argument("--param " + spec + ": expected NAME=v1,v2,... (one value per run) or NAME=first:last:step");
  RunParameter p;
  p.name = spec.substr(0, eq);
  const std::string values = spec.substr(eq + 1);
  if (values.find(':') != std::string::npos) {
    p.values = parse_sweep_axis(spec).values();
  } else {
    std::stringstream in(values);
    for (std::string v; std::getline(in, v, ',');) {
      const auto x = parse_finite(v);
      if (!x) throw std::invalid_argument("--param " + spec + ": '" + v + "' is not a finite number");
      p.values.push_back(*x);
    }
  }
  if (p.values.size() != runs)
    throw std::invalid_argument(fmt::format("--param {}: {} value{} for {} runs (one value per run, in the order the runs are given)",
                                            spec, p.values.size(), p.values.size() == 1 ? "" : "s", runs));
  return p;
}

namespace {

/// An estimator's OptionError on its way out of the loop over the runs (which keeps every other
/// error as the run's own).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RunRow {
  std::string file;
  std::optional<MlceResult> result;  ///< empty when the run could not be estimated
  std::string error;
  double from = 0.0;           ///< time of the first analysed sample
  std::string transient_rule;  ///< how --from auto decided, when used
  Reading reading;
};

/// Where the stability read from one run to the next differs (in the order the runs are given),
/// and, with a parameter, from stable to unstable or back, where the straight line between the two
/// lambdas crosses 0 (a first guess at the stability boundary, to be refined by runs between them).
struct StabilityChange {
  std::size_t first = 0;  ///< rows first and first + 1
  std::optional<double> zero_at;
};

std::vector<StabilityChange> stability_changes(const std::vector<RunRow>& rows, const std::optional<RunParameter>& p) {
  std::vector<StabilityChange> out;
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
    const RunRow &a = rows[k], &b = rows[k + 1];
    if (!a.result || !b.result || a.reading.stability == b.reading.stability) continue;
    StabilityChange c{k, std::nullopt};
    const double la = a.result->lambda, lb = b.result->lambda;
    // Only between a stable and an unstable reading: a neutral one's lambda is the estimate's residue
    // about 0 (a limit cycle), not a rate a straight line could be drawn through.
    const auto decided = [](Stability s) { return s == Stability::stable || s == Stability::unstable; };
    if (p && decided(a.reading.stability) && decided(b.reading.stability) && std::isfinite(la) && std::isfinite(lb) &&
        (la < 0) != (lb < 0))
      c.zero_at = p->values[k] + (p->values[k + 1] - p->values[k]) * la / (la - lb);
    out.push_back(c);
  }
  return out;
}

std::string run_name(const std::optional<RunParameter>& p, std::size_t k) {
  return p ? fmt::format("{} = {:g}", p->name, p->values[k]) : fmt::format("run {}", k + 1);
}

std::string table_csv(const std::vector<RunRow>& rows, const std::optional<RunParameter>& p) {
  std::string s = "run,file,";
  if (p) s += csv_field(p->name) + ",";
  s += "lambda,ci95_low,ci95_high,unit,lambda_per_sample,delay,dim,theiler,fit_first,fit_last,from,stability,motion,in_decay_floor,warnings,error\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const RunRow& row = rows[k];
    s += fmt::format("{},{},", k + 1, csv_field(row.file));
    if (p) s += fmt::format("{:.10g},", p->values[k]);
    if (const auto& r = row.result)
      s += fmt::format("{:.10g},{:.10g},{:.10g},{},{:.10g},{},{},{},{},{},{:.10g},{},{},{},{},\n", r->lambda, r->ci95_low,
                       r->ci95_high, r->time_unit.empty() ? "1/sample" : "1/" + r->time_unit, r->lambda_per_sample, r->delay,
                       r->dim, r->theiler, r->fit.first, r->fit.last, row.from, to_string(row.reading.stability),
                       csv_field(row.reading.motion), r->in_decay_floor ? 1 : 0, r->warnings.size());
    else
      s += ",,,,,,,,,,,,,,," + csv_field(row.error) + "\n";
  }
  return s;
}

}  // namespace

int estimate_runs(const std::vector<std::string>& files, const SeriesInput& input, const MlceOptions& options,
                  const std::optional<RunParameter>& parameter, const RunsOutput& output) {
  check_series_options(input);  // a mistake in the options is one usage error, not one per run
  const auto start = std::chrono::steady_clock::now();
  std::vector<RunRow> rows;
  for (std::size_t k = 0; k < files.size(); ++k) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!output.quiet && elapsed > 1.0)
      std::fprintf(stderr, "mlce: %.1f s: run %zu of %zu: %s\n", elapsed, k + 1, files.size(), files[k].c_str());
    SeriesInput in = input;
    in.file = files[k];
    RunRow row;
    row.file = files[k];
    try {
      LoadedSeries loaded = load_series(in);
      MlceOptions run_options = options;
      run_options.record_deviation = loaded.record_deviation;
      MlceResult r = on_file(in, [&] {
        try {
          return estimate_mlce(loaded.series, run_options);
        } catch (const OptionError& e) {  // the estimator checks its options first: wrong for every run
          throw UsageError(e.what());
        }
      });
      r.warnings.insert(r.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
      row.from = loaded.series.time(r.skipped_start);
      row.transient_rule = loaded.transient_rule;
      row.reading = read_stability(r);
      row.result = std::move(r);
    } catch (const UsageError& e) {
      throw OptionError(e.what());
    } catch (const std::exception& e) {  // the run's own: a channel its set lacks, a column file among MBDyn sets, ...
      row.error = e.what();
    }
    rows.push_back(std::move(row));
  }

  if (!output.csv_path.empty()) write_file_atomically(output.csv_path, table_csv(rows, parameter));
  std::vector<std::string> failed;
  for (const auto& row : rows)
    if (!row.result) failed.push_back(row.file);
  // No estimate, no plot (gnuplot would refuse an empty one): the error line below says why.
  if (!output.plot_path.empty() && failed.size() < rows.size()) {
    std::string unit;
    std::vector<PlottedReading> points;
    for (std::size_t k = 0; k < rows.size(); ++k)
      if (const auto& r = rows[k].result) {
        if (unit.empty()) unit = r->time_unit.empty() ? "1/sample" : "1/" + r->time_unit;
        points.push_back({.x = parameter ? parameter->values[k] : static_cast<double>(k + 1),
                          .lambda = r->lambda,
                          .low = r->ci95_low,
                          .high = r->ci95_high,
                          .stability = rows[k].reading.stability,
                          .in_decay_floor = r->in_decay_floor});
      }
    plot_readings_png(points, fmt::format("MLCE of {} runs", rows.size()),
                      parameter ? parameter->name : "run (as numbered in the table)", "lambda (" + unit + ")",
                      output.plot_path, false);
  }
  const auto changes = stability_changes(rows, parameter);
  if (output.json) {
    nlohmann::json j;
    j["runs"] = nlohmann::json::array();
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const RunRow& row = rows[k];
      nlohmann::json r = row.result ? to_json(*row.result) : nlohmann::json::object();
      r["file"] = row.file;
      // The value under a fixed key (its name is the object's "parameter"): a name such as "lambda"
      // would otherwise overwrite the estimate's own field.
      if (parameter) r["parameter"] = parameter->values[k];
      if (row.result) {
        r["from"] = row.from;
        if (!row.transient_rule.empty()) r["transient_rule"] = row.transient_rule;
      } else {
        r["error"] = row.error;
      }
      j["runs"].push_back(std::move(r));
    }
    if (parameter) j["parameter"] = parameter->name;
    j["estimated"] = rows.size() - failed.size();
    j["stability_changes"] = nlohmann::json::array();
    for (const auto& c : changes)
      j["stability_changes"].push_back({{"runs", {c.first + 1, c.first + 2}},
                                        {"from", to_string(rows[c.first].reading.stability)},
                                        {"to", to_string(rows[c.first + 1].reading.stability)},
                                        {"lambda_zero_at", c.zero_at ? nlohmann::json(*c.zero_at) : nlohmann::json(nullptr)}});
    std::cout << j.dump() << "\n";
  } else {
    std::string s = fmt::format("# MLCE of {} runs, every parameter automatic unless given; the same options for each\n", rows.size());
    s += fmt::format("{:>4} {}{:>12} {:>10} {:>27} {:>12} {:<20} {:>10} {:>3} {:>4}  {}\n", "run",
                     parameter ? fmt::format("{:>12} ", parameter->name) : "", "lambda", "unit", "95 % interval", "stability",
                     "motion", "from", "m", "J", "file");
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const RunRow& row = rows[k];
      s += fmt::format("{:>4} {}", k + 1, parameter ? fmt::format("{:>12.6g} ", parameter->values[k]) : "");
      if (const auto& r = row.result)
        s += fmt::format("{:>12.6g} {:>10} {:>12.6g} .. {:<12.6g} {:>12} {:<20} {:>10.6g} {:>3} {:>4}  {}\n", r->lambda,
                         r->time_unit.empty() ? "1/sample" : "1/" + r->time_unit, r->ci95_low, r->ci95_high,
                         to_string(row.reading.stability), row.reading.motion, row.from, r->dim, r->delay, row.file);
      else  // the reader's and the estimator's messages name the file already
        s += fmt::format("{:>12} {:>10} {:>27} {:>12} {:<20} {:>10} {:>3} {:>4}  error: {}\n", "-", "", "", "", "", "", "", "",
                         row.error.rfind(row.file, 0) == 0 ? row.error : row.file + ": " + row.error);
    }
    for (const auto& c : changes)
      s += fmt::format("stability changes between {} ({}) and {} ({}){}\n", run_name(parameter, c.first),
                       to_string(rows[c.first].reading.stability), run_name(parameter, c.first + 1),
                       to_string(rows[c.first + 1].reading.stability),
                       c.zero_at ? fmt::format(": lambda = 0 at {} = {:.6g} on the straight line between them", parameter->name,
                                               *c.zero_at)
                                 : "");
    // Each run's warnings, named by its file (with --json they are in each run's entry).
    for (const auto& row : rows)
      if (row.result)
        for (const auto& w : row.result->warnings) s += "warning: " + row.file + ": " + w + "\n";
    std::cout << s;
  }
  if (failed.empty()) return 0;
  const std::string which = fmt::format("{}", fmt::join(failed, ", "));
  if (failed.size() == rows.size())
    std::fprintf(stderr, "mlce estimate: error: none of the %zu runs could be estimated (%s): see each run's error above\n",
                 rows.size(), which.c_str());
  else
    std::fprintf(stderr, "mlce estimate: error: %zu of %zu runs could not be estimated (%s); the others are above\n",
                 failed.size(), rows.size(), which.c_str());
  return kExitData;
}

}  // namespace mlce::cli
