#include "plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <stdexcept>

#include "report.hpp"

namespace mlce::cli {

namespace {
/// Text for a gnuplot single-quoted string: a quote is written twice (a path or a title holding
/// one, e.g. "blade's lag.png", would otherwise end the string and break the script).
std::string quoted(const std::string& text) {
  std::string out;
  for (char c : text) {
    out += c;
    if (c == '\'') out += c;
  }
  return out;
}

/// Line colours, none black or grey (the fit lines are black, marks grey): gnuplot's default cycle
/// has 8 and its 8th is black, so the 8th channel of a plot looked like a fit and the 9th took the
/// 1st one's colour. Every plot's linetypes 1..15 take these (a `plot for` over columns too).
constexpr std::array<const char*, 15> kCurveColours = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                        "#8c564b", "#e377c2", "#bcbd22", "#17becf", "#0b3d91",
                                                        "#b35806", "#1b5e20", "#7f0000", "#4a148c", "#4e342e"};

std::string curve_linetypes() {
  std::string out;
  for (std::size_t k = 0; k < kCurveColours.size(); ++k)
    out += fmt::format("set linetype {} lc rgb '{}' lw 1 dt solid\n", k + 1, kCurveColours[k]);
  // Past the list the colours come round again, dash-dotted.
  for (std::size_t k = 0; k < kCurveColours.size(); ++k)
    out += fmt::format("set linetype {} lc rgb '{}' lw 1 dt 4\n", kCurveColours.size() + k + 1, kCurveColours[k]);
  return out + fmt::format("set linetype cycle {}\n", 2 * kCurveColours.size());
}
}  // namespace

void render_png(const std::string& png_path, const std::string& csv,
                const std::function<std::string(const std::string&)>& script, int height) {
  namespace fs = std::filesystem;
  const OutputTarget target = output_target(png_path);
  const fs::path tmp_png = target.scratch(".tmp-mlce.png");
  const fs::path data = target.scratch(".tmp-mlce.csv");
  // gnuplot's own output (and the shell's "not found") goes to a log beside the plot, never to
  // stdout (which carries the result only: one JSON object with --json): a plot that is drawn
  // needs no word from gnuplot ("empty x range" for a one-row record), one that is not is one
  // error with gnuplot's first line.
  const fs::path log = target.scratch(".tmp-mlce.log");
  const ScratchGuard scratch({tmp_png.string(), data.string(), log.string()});  // before any exists
  try {
    write_file_atomically(data.string(), csv);
  } catch (const std::runtime_error&) {  // name the file asked for, not the scratch file beside it
    throw std::runtime_error(png_path + ": cannot write the file");
  }
  std::string shell_log = "'";
  for (char c : log.string()) shell_log += c == '\'' ? std::string("'\\''") : std::string(1, c);
  shell_log += "'";
  // A gnuplot that is missing or quits early closes the pipe: the write must fail, not raise SIGPIPE
  // (which would kill mlce with no message).
  struct IgnoreSigpipe {
    void (*previous)(int) = std::signal(SIGPIPE, SIG_IGN);
    ~IgnoreSigpipe() { std::signal(SIGPIPE, previous); }
  } ignore_sigpipe;
  FILE* gp = popen(("gnuplot >" + shell_log + " 2>&1").c_str(), "w");
  if (!gp) throw std::runtime_error(png_path + ": cannot start gnuplot (install gnuplot-nox)");
  // Every plot: a PNG 900 pixels wide, the CSV's commas, no enhanced text (a '_' in a channel name is a '_').
  const std::string preamble = fmt::format(
      "set terminal pngcairo size 900,{} noenhanced\nset output '{}'\nset datafile separator ','\n", height,
      quoted(tmp_png.string()));
  std::fputs((preamble + curve_linetypes() + script(quoted(data.string()))).c_str(), gp);
  const int rc = pclose(gp);
  std::error_code ec;
  fs::remove(data, ec);
  std::string said;
  if (rc != 0 || !fs::exists(tmp_png)) {
    std::ifstream in(log);
    for (std::string line; said.empty() && std::getline(in, line);)
      if (line.find_first_not_of(" \t\r^") != std::string::npos) said = line.substr(line.find_first_not_of(" \t"));
  }
  fs::remove(log, ec);
  if (rc != 0 || !fs::exists(tmp_png)) {
    fs::remove(tmp_png, ec);
    throw std::runtime_error(png_path + ": gnuplot failed to draw the plot (is gnuplot installed?)" +
                             (said.empty() ? std::string() : ": " + said));
  }
  if (target.in_place) {  // a device or a pipe: the finished image's bytes, copied in
    {
      std::ifstream in(tmp_png, std::ios::binary);
      std::ofstream out(target.path, std::ios::binary | std::ios::trunc);
      out << in.rdbuf();
      if (!out) ec = std::make_error_code(std::errc::io_error);
    }
    fs::remove(tmp_png);
  } else {
    fs::rename(tmp_png, target.path, ec);
  }
  if (ec) throw std::runtime_error(png_path + ": cannot write the file");
}

void plot_curve_png(const MlceResult& r, const std::string& png_path) {
  const std::string u = r.time_unit.empty() ? "sample" : r.time_unit;
  // The local slope (the table's local_slope column) on the right axis with lambda as a level:
  // where the curve is straight the slope lies flat on it. Its range is held around lambda (the
  // start-up and the plateau would otherwise flatten it); a curve with lambda ~ 0 (limit cycle)
  // keeps gnuplot's. A curve shorter than a mean period has no local slope: not drawn.
  const CurveTable table = curve_table(r);
  const double a = std::abs(r.lambda);
  const std::string y2range =
      a > 0.0 && std::isfinite(a)
          ? fmt::format("set y2range [{:.6g}:{:.6g}]\n", r.lambda > 0 ? -0.5 * a : -2.5 * a, r.lambda > 0 ? 2.5 * a : 0.5 * a)
          : "";
  render_png(png_path, table.csv, [&](const std::string& data) {
    return fmt::format(
        "set key below\nset grid\nset xlabel 'time ({})'\nset ylabel '<ln d_j(i)>'\n"
        "set y2label 'local slope over one mean period (1/{})'\nset y2tics\nset ytics nomirror\n{}"
        "set title 'Rosenstein divergence: lambda = {:.5g} 1/{} (fit steps {}..{}, R2 {:.4f})'\n"
        "plot '{}' every ::1 using 2:3 with lines lw 2 title '{}', "
        "'' every ::1 using 2:($5 > 0 ? $6 : 1/0) with lines lw 3 dt 2 lc rgb 'black' title 'least-squares fit'{}{}"
        "{:.10g} axes x1y2 with lines lw 1 dt 3 lc rgb 'dark-orange' title 'lambda (right axis)'\n",
        quoted(u), quoted(u), y2range, r.lambda, quoted(u), r.fit.first, r.fit.last, r.r2, data,
        r.curve.phase_aligned ? "mean log divergence, neighbours phase-aligned"
        : r.noise_compensated ? "ln <d^2> / 2, noise-compensated"
                              : "mean log divergence",
        table.plain_column
            ? fmt::format(", '' every ::1 using 2:{} with lines lw 1 lc rgb 'gray50' title 'plain curve (lambda {:.5g})'",
                          table.plain_column, r.noise_compensated ? r.uncompensated_lambda : r.unaligned_lambda)
            : "",
        table.any_slope ? fmt::format(", '' every ::1 using 2:{} axes x1y2 with lines lw 1 lc rgb 'dark-orange' title "
                                      "'local slope (right axis)', ",
                                      table.slope_column)
                        : ", ",
        r.lambda);
  });
}

void plot_each_channel_png(const EachChannelResult& r, const std::string& png_path) {
  const std::string time_unit = [&] {  // the channels share the series' time axis
    for (const auto& c : r.channels)
      if (c.result) return c.result->time_unit.empty() ? std::string("sample") : c.result->time_unit;
    return std::string("sample");
  }();
  render_png(png_path, each_channel_curves_csv(r), [&](const std::string& data) {
    // Columns: 1 channel, 2 index, 3 step, 4 time, 5 mean_log_distance, 6 terms, 7 in_fit, 8 fit_line.
    std::string terms;
    for (std::size_t k = 0; k < r.channels.size(); ++k) {
      const auto& c = r.channels[k];
      if (!c.result) continue;
      // The fit lines in black over the coloured curves (in a curve's own colour it hides in it);
      // the curves in linetypes k + 1 (curve_linetypes: none black).
      terms += fmt::format("{}'{}' every ::1 using 4:($2 == {} ? $5 : 1/0) with lines lt {} lw 2 title '{}: {:.5g}', "
                           "'' every ::1 using 4:($2 == {} && $7 > 0 ? $8 : 1/0) with lines lw 1.5 dt 2 lc rgb 'black' {}",
                           terms.empty() ? "" : ", ", data, k, k + 1, quoted(c.name), c.result->lambda, k,
                           terms.empty() ? "title 'least-squares fits'" : "notitle");
    }
    return fmt::format(
        "set key below\nset grid\nset xlabel 'time ({})'\nset ylabel '<ln d_j(i)> (channel standard deviations)'\n"
        "set title 'Rosenstein divergence of each channel, lambda in 1/{}; {}'\nplot {}\n",
        quoted(time_unit), quoted(time_unit),
        r.estimated < 2   ? "one channel estimated"
        : r.compared < 2  ? "fewer than two channels measure a divergence"
        : r.verdict.agree ? "the channels agree"
                          : "the channels do NOT agree",
        terms);
  });
}

void plot_columns_png(const std::string& csv, const std::string& title, const std::string& xlabel,
                      const std::string& ylabel, const std::string& png_path,
                      const std::vector<std::pair<double, std::string>>& marks) {
  const std::string header = csv.substr(0, csv.find('\n'));
  const auto columns = static_cast<int>(std::count(header.begin(), header.end(), ',')) + 1;
  std::string lines;
  for (const auto& [x, label] : marks)
    lines += fmt::format("set arrow from first {0:.10g}, graph 0 to first {0:.10g}, graph 1 nohead dashtype 2 lc 'gray40'\n"
                         "set label '{1}' at first {0:.10g}, graph 0.97 offset 0.5,0 tc 'gray40'\n",
                         x, quoted(label));
  render_png(png_path, csv, [&](const std::string& data) {
    return fmt::format(
        "set key outside right autotitle columnhead\nset grid\nset xlabel '{}'\nset ylabel '{}'\nset title '{}'\n{}"
        "plot for [c=2:{}] '{}' using 1:c with lines lw 2\n",
        quoted(xlabel), quoted(ylabel), quoted(title), lines, columns, data);
  });
}

void plot_estimates_png(const std::string& csv, const std::string& title, const std::string& xlabel,
                        const std::string& ylabel, const std::string& png_path) {
  render_png(png_path, csv, [&](const std::string& data) {
    return fmt::format(
        "set key below\nset grid\nset xlabel '{}'\nset ylabel '{}'\nset title '{}'\nset offsets graph 0.05, graph 0.05, 0, 0\n"
        "set xzeroaxis lt -1 lc 'gray40'\n"
        "plot '{}' every ::1 using 1:2:3:4 with yerrorbars pt 7 ps 1 lw 2 title 'lambda and its 95 % interval'\n",
        quoted(xlabel), quoted(ylabel), quoted(title), data);
  });
}

void plot_exponents_png(const std::string& csv, const std::string& title, const std::string& unit,
                        const std::string& png_path) {
  render_png(png_path, csv, [&](const std::string& data) {
    return fmt::format(
        "set key below\nset grid\nset xlabel 'lambda, growth rate (1/{0})'\nset ylabel 'frequency (rad/{0})'\n"
        "set title '{1}'\nset offsets graph 0.1, graph 0.1, graph 0.1, graph 0.1\n"
        "set yzeroaxis lt -1 lw 2 lc 'gray40'\nset xzeroaxis lt 0 lc 'gray60'\n"
        "stats '{2}' every ::1 using 2 nooutput\n"
        "if (STATS_max < 0) set xrange [:-0.05 * STATS_min]\n"  // keep the boundary in sight
        "if (STATS_min > 0) set xrange [-0.05 * STATS_max:]\n"
        "plot '{2}' every ::1 using 2:($2 < 0 ? $3 : 1/0) with points pt 7 ps 1.3 lc rgb '#1f77b4' title 'decaying (lambda < 0)', "
        "'' every ::1 using 2:($2 >= 0 ? $3 : 1/0) with points pt 7 ps 1.6 lc rgb '#d62728' title 'growing or neutral (lambda >= 0)'\n",
        quoted(unit), quoted(title), data);
  });
}

void plot_map_png(const std::string& csv, const std::string& title, const std::string& xlabel, const std::string& ylabel,
                  const std::string& zlabel, const std::string& png_path) {
  render_png(png_path, csv, [&](const std::string& data) {
    return fmt::format(
        "set title '{}'\nset xlabel '{}'\nset ylabel '{}'\nset cblabel '{}'\nset view map\n"
        "set palette defined (0 'blue', 1 'white', 2 'red')\nset key off\n"
        "stats '{}' every ::1 using 3 nooutput\nm = abs(STATS_min) > abs(STATS_max) ? abs(STATS_min) : abs(STATS_max)\n"
        "if (m > 0) set cbrange [-m:m]\n"  // white is 0: stable blue, unstable red
        "plot '{}' every ::1 using 1:2:3 with image\n",
        quoted(title), quoted(xlabel), quoted(ylabel), quoted(zlabel), data, data);
  }, 700);
}

}  // namespace mlce::cli
