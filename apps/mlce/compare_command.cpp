#include "compare_command.hpp"

#include <fmt/format.h>

#include <boost/program_options.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "mlce/compare.hpp"
#include "mlce/each_channel.hpp"
#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"
#include "plot.hpp"
#include "report.hpp"
#include "series_input.hpp"

namespace po = boost::program_options;

namespace mlce::cli {
namespace {

/// (c) of the MBDyn-versus-ad-hoc comparison: the MLCE of one channel from both runs, every
/// parameter automatic, on the same time window. Without --from the window starts where A's
/// transient ends (`--from auto` on A), so both runs are read on the same stretch of motion.
struct MlcePair {
  MlceResult a, b;
  double from = 0.0, to = 0.0;
  std::string window_rule;
};

struct MlceWindow {
  double from = 0.0, to = 0.0;
  std::string rule;
  /// The channel whose transient set the window, and its estimate on A over that very window (the
  /// series `--from auto` left, which starts at `from`): mlce_of_both takes it instead of
  /// estimating the same samples again.
  std::string channel;
  std::optional<MlceResult> a;
};

/// The window every channel's MLCE is read on: [--from, --to], or from the latest end of A's
/// transient over the compared channels, each detected on its own (its own mean period and RMS
/// windows): the system settles as a whole, and a hub driven by a blade's limit cycle may look
/// steady while the blade still grows. A channel whose exponent on its own settled part does not
/// measure a divergence (MlceResult::unreliable: a constrained coordinate's rounding noise, whose
/// RMS wanders) has no transient to wait for and does not move the window, unless every channel is
/// such.
MlceWindow mlce_window(const std::string& file_a, const std::vector<std::string>& channels, const HistoryComparisonOptions& o) {
  SeriesInput in;
  in.file = file_a;
  in.from = std::isfinite(o.from) ? fmt::format("{}", o.from) : "auto";
  if (std::isfinite(o.to)) in.to = o.to;
  struct Candidate {
    MlceWindow window;
    Series series;
    std::string channel;
    std::vector<double> record_deviation;
  };
  std::vector<Candidate> candidates;
  for (const auto& ch : channels) {
    in.channels = {ch};
    LoadedSeries a = load_series(in);
    const std::string rule =
        std::isfinite(o.from) ? "given window" : "end of A's transient, latest over the channels (" + ch + ": " + a.transient_rule + ")";
    candidates.push_back({{a.series.time(0), a.series.time(a.series.size() - 1), rule, {}, std::nullopt}, std::move(a.series), ch,
                          std::move(a.record_deviation)});
  }
  // Latest first; the first whose exponent measures a divergence sets the window, so only the
  // channels that would otherwise set it are estimated here.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.window.from > y.window.from; });
  if (std::isfinite(o.from)) return candidates.front().window;
  std::string left_out;
  for (const auto& c : candidates) {
    MlceOptions eo;
    eo.skip_nonrecurrent_start = false;
    eo.record_deviation = c.record_deviation;
    std::optional<MlceResult> a;
    try {
      a = estimate_mlce(c.series, eo);
    } catch (const InputError&) {  // too short on its own: mlce_of_both says so on the window
    }
    if (a && a->unreliable.empty()) {
      MlceWindow w = c.window;
      if (!left_out.empty()) w.rule += "; not waited for: " + left_out + " (its exponent does not measure a divergence)";
      w.channel = c.channel;
      w.a = std::move(a);
      return w;
    }
    left_out += (left_out.empty() ? "" : ", ") + c.channel;
  }
  return candidates.front().window;  // no channel measures a divergence: the latest of all
}

MlcePair mlce_of_both(const std::string& file_a, const std::string& file_b, const std::string& channel,
                      const MlceWindow& window) {
  SeriesInput in;
  in.channels = {channel};
  in.from = fmt::format("{}", window.from);
  in.to = window.to;
  MlcePair p;
  p.from = window.from;
  p.to = window.to;
  p.window_rule = window.rule;
  // Both runs on the very same stretch of motion: neither leaves its start out on its own.
  MlceOptions o;
  o.skip_nonrecurrent_start = false;
  in.file = file_a;
  if (window.a && window.channel == channel) {
    p.a = *window.a;  // estimated with the same options on the same samples when the window was set
  } else {
    const LoadedSeries a = load_series(in);
    o.record_deviation = a.record_deviation;
    p.a = on_file(in, [&] { return estimate_mlce(a.series, o); });
  }
  in.file = file_b;
  const LoadedSeries b = load_series(in);
  o.record_deviation = b.record_deviation;
  p.b = on_file(in, [&] { return estimate_mlce(b.series, o); });
  return p;
}

/// Strictly: the two 95 % intervals overlap.
bool intervals_overlap(const MlceResult& a, const MlceResult& b) {
  return a.ci95_low <= b.ci95_high && b.ci95_low <= a.ci95_high;
}

/// The verdict of mlce estimate --each (and the resolution of mlce convergence) on the two runs;
/// none when either lambda does not measure a divergence (MlceResult::unreliable), which --each
/// leaves out of its verdict too.
std::optional<Agreement> agreement(const MlcePair& e) {
  if (!e.a.unreliable.empty() || !e.b.unreliable.empty()) return std::nullopt;
  return judge_agreement({&e.a, &e.b});
}

nlohmann::json mlce_json(const MlceResult& r) {
  return {{"lambda", r.lambda}, {"ci95", {r.ci95_low, r.ci95_high}}, {"curve_end", to_string(r.fit.end)},
          {"delay", r.delay}, {"dim", r.dim}, {"n_points", r.n_points}, {"reading", reading_json(r)},
          {"warnings", r.warnings}};
}

}  // namespace

int cmd_compare(const std::vector<std::string>& args) {
  std::vector<std::string> channels, files;
  std::string plot_path, csv_path;
  bool json = false, mlce = false;
  HistoryComparisonOptions o;
  po::options_description d("mlce compare A B --channel SPEC... [options]");
  d.add_options()
      ("channel", channel_specs(&channels), "channel spec present in both runs (repeatable; FIRST..LAST in a number: a channel each)")
      ("from", po::value(&o.from), "start of the compared window (time units)")
      ("to", po::value(&o.to), "end of the compared window (time units)")
      ("mlce", po::bool_switch(&mlce), "also the MLCE (Rosenstein, automatic) of every channel from both runs, on "
                                         "[--from, --to] or, without --from, from the end of A's transient")
      ("json", po::bool_switch(&json), "print one JSON object")
      ("csv", po::value(&csv_path), "write time, A and B (B interpolated onto A's times) per channel")
      ("plot", po::value(&plot_path), "PNG of both histories per channel");
  d.add_options()("help", "this help");
  po::options_description all = d;
  all.add_options()("files", po::value(&files)->composing(), "A and B");
  po::positional_options_description pos;
  pos.add("files", 2);
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(all).positional(pos).run(), vm);
  if (vm.count("help")) {
    std::cout << d;
    return 0;
  }
  po::notify(vm);
  if (files.size() != 2) throw po::error("give two runs: mlce compare A B --channel SPEC");
  if (channels.empty()) throw po::error("give at least one --channel SPEC");
  if (std::isnan(o.from) || std::isnan(o.to))
    throw po::error(std::string(std::isnan(o.from) ? "--from" : "--to") + " 'nan': expected a time");
  // Steps after --to are not read (a run may diverge after the window); the histories are then
  // compared up to the earlier of the two runs' last steps at or before it.
  reader::ReadOptions read_options;
  read_options.until = o.to;
  const reader::ChannelSet a = load_channels(files[0], channels, read_options);
  const reader::ChannelSet b = load_channels(files[1], channels, read_options);
  if (a.time.empty() || b.time.empty()) throw std::runtime_error("compare needs runs with a time axis (MBDyn sets)");
  std::vector<HistoryComparison> results;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    try {
      results.push_back(compare_histories(a.time, a.values[c], b.time, b.values[c], o));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(channels[c] + ": " + e.what());
    }
  }
  std::vector<MlcePair> exponents;
  const MlceWindow window = mlce ? mlce_window(files[0], channels, o) : MlceWindow{};
  for (std::size_t c = 0; mlce && c < channels.size(); ++c) {
    try {
      exponents.push_back(mlce_of_both(files[0], files[1], channels[c], window));
    } catch (const std::exception& e) {
      throw std::runtime_error(channels[c] + ": MLCE: " + e.what());
    }
  }
  if (!csv_path.empty() || !plot_path.empty()) {
    std::string csv = "time";
    for (const auto& ch : channels) csv += fmt::format(",A {},B {}", ch, ch);
    csv += "\n";
    std::size_t j = 0;
    for (std::size_t k = 0; k < a.time.size(); ++k) {
      const double t = a.time[k];
      if (t < results[0].t_first || t > results[0].t_last) continue;
      while (j + 2 < b.time.size() && b.time[j + 1] < t) ++j;
      const double w = std::clamp((t - b.time[j]) / (b.time[j + 1] - b.time[j]), 0.0, 1.0);
      csv += fmt::format("{}", t);
      for (std::size_t c = 0; c < channels.size(); ++c)
        csv += fmt::format(",{},{}", a.values[c][k], b.values[c][j] + w * (b.values[c][j + 1] - b.values[c][j]));
      csv += "\n";
    }
    if (!csv_path.empty()) write_file_atomically(csv_path, csv);
    if (!plot_path.empty()) plot_columns_png(csv, "A: " + files[0] + "   B: " + files[1], "time (s)", "value", plot_path);
  }
  std::vector<std::string> warnings = a.warnings;
  warnings.insert(warnings.end(), b.warnings.begin(), b.warnings.end());
  for (std::size_t c = 0; c < channels.size(); ++c)
    for (const auto& w : results[c].warnings) warnings.push_back(channels[c] + ": " + w);
  for (std::size_t c = 0; c < exponents.size(); ++c) {
    for (const auto& w : exponents[c].a.warnings) warnings.push_back(channels[c] + ": MLCE of A: " + w);
    for (const auto& w : exponents[c].b.warnings) warnings.push_back(channels[c] + ": MLCE of B: " + w);
    if (!agreement(exponents[c]))  // which run, and why
      warnings.push_back(channels[c] + ": the two exponents are not compared: the MLCE of " +
                         (exponents[c].a.unreliable.empty() ? "B" : "A") + " does not measure a divergence: " +
                         (exponents[c].a.unreliable.empty() ? exponents[c].b.unreliable : exponents[c].a.unreliable));
  }
  if (json) {
    nlohmann::json j;
    j["a"] = files[0];
    j["b"] = files[1];
    j["channels"] = nlohmann::json::array();
    for (std::size_t c = 0; c < channels.size(); ++c) {
      const auto& r = results[c];
      j["channels"].push_back({{"channel", channels[c]}, {"points", r.points}, {"time", {r.t_first, r.t_last}},
                               {"max_abs_difference", r.max_abs_difference}, {"time_of_max", r.time_of_max},
                               {"rms_difference", r.rms_difference}, {"range_a", {r.min_a, r.max_a}},
                               {"range_b", {r.min_b, r.max_b}}, {"range_relative_difference", r.range_relative_difference}});
      if (c < exponents.size()) {
        const auto& e = exponents[c];
        const std::optional<Agreement> ag = agreement(e);
        j["channels"].back()["mlce"] = {{"window", {e.from, e.to}}, {"window_rule", e.window_rule},
                                        {"a", mlce_json(e.a)}, {"b", mlce_json(e.b)},
                                        {"difference", e.b.lambda - e.a.lambda},
                                        {"intervals_overlap", intervals_overlap(e.a, e.b)},
                                        {"agreement", ag ? to_json(*ag) : nlohmann::json(nullptr)}};
      }
    }
    j["warnings"] = warnings;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << fmt::format("# A = {}\n# B = {} (interpolated onto A's samples)\n", files[0], files[1]);
    std::cout << fmt::format("{:<16} {:>8} {:>17} {:>12} {:>12} {:>23} {:>23} {:>10}\n", "channel", "points", "time", "max |A-B|",
                             "rms |A-B|", "range A", "range B", "d range");
    for (std::size_t c = 0; c < channels.size(); ++c) {
      const auto& r = results[c];
      std::cout << fmt::format("{:<16} {:>8} {:>8.4g}..{:<8.4g} {:>12.4e} {:>12.4e} {:>11.5g}..{:<11.5g} {:>11.5g}..{:<11.5g} {:>9.3g}%\n",
                               channels[c], r.points, r.t_first, r.t_last, r.max_abs_difference, r.rms_difference, r.min_a,
                               r.max_a, r.min_b, r.max_b, 100.0 * r.range_relative_difference);
    }
    if (!exponents.empty()) {
      std::cout << fmt::format("\nMLCE (Rosenstein, every parameter automatic), 1/{}\n", "s");
      std::cout << fmt::format("{:<16} {:>17} {:>34} {:>34} {:>10} {:>8}  {}\n", "channel", "window", "A [95 % CI]",
                               "B [95 % CI]", "B - A", "agree", "reading A / B");
      for (std::size_t c = 0; c < exponents.size(); ++c) {
        const auto& e = exponents[c];
        auto cell = [](const MlceResult& r) { return fmt::format("{:.5g} [{:.4g}, {:.4g}]", r.lambda, r.ci95_low, r.ci95_high); };
        // What each run says about the motion (reading.hpp): do the two runs reach one verdict?
        const Reading ra = read_stability(e.a), rb = read_stability(e.b);
        const std::optional<Agreement> ag = agreement(e);
        std::cout << fmt::format("{:<16} {:>8.4g}..{:<8.4g} {:>34} {:>34} {:>10.3g} {:>8}  {} ({}) / {} ({})\n", channels[c],
                                 e.from, e.to, cell(e.a), cell(e.b), e.b.lambda - e.a.lambda,
                                 !ag ? "n/a" : ag->agree ? "yes" : "NO", to_string(ra.stability), ra.motion,
                                 to_string(rb.stability), rb.motion);
      }
      for (std::size_t c = 0; c < exponents.size(); ++c)
        std::cout << fmt::format("# {}: window: {}; curve end A: {}, B: {}\n", channels[c], exponents[c].window_rule,
                                 to_string(exponents[c].a.fit.end), to_string(exponents[c].b.fit.end));
    }
  }
  print_warnings(warnings);
  return 0;
}

}  // namespace mlce::cli
