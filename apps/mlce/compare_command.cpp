#include "compare_command.hpp"

#include <fmt/format.h>

#include <boost/program_options.hpp>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "mlce/compare.hpp"
#include "plot.hpp"
#include "report.hpp"
#include "series_input.hpp"

namespace po = boost::program_options;

namespace mlce::cli {

int cmd_compare(const std::vector<std::string>& args) {
  std::vector<std::string> channels, files;
  std::string plot_path, csv_path;
  bool json = false;
  HistoryComparisonOptions o;
  po::options_description d("mlce compare A B --channel SPEC... [options]");
  d.add_options()
      ("channel", po::value(&channels)->composing(), "channel spec present in both runs (repeatable)")
      ("from", po::value(&o.from), "start of the compared window (time units)")
      ("to", po::value(&o.to), "end of the compared window (time units)")
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
  const reader::ChannelSet a = load_channels(files[0], channels);
  const reader::ChannelSet b = load_channels(files[1], channels);
  if (a.time.empty() || b.time.empty()) throw std::runtime_error("compare needs runs with a time axis (MBDyn sets)");
  std::vector<HistoryComparison> results;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    try {
      results.push_back(compare_histories(a.time, a.values[c], b.time, b.values[c], o));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(channels[c] + ": " + e.what());
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
  }
  print_warnings(warnings);
  return 0;
}

}  // namespace mlce::cli
