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

/// gnuplot lines for dashed vertical marks at x, each labelled at the top.
std::string vertical_marks(const std::vector<std::pair<double, std::string>>& marks) {
  std::string lines;
  for (const auto& [x, label] : marks)
    lines += fmt::format("set arrow from first {0:.10g}, graph 0 to first {0:.10g}, graph 1 nohead dashtype 2 lc 'gray40'\n"
                         "set label '{1}' at first {0:.10g}, graph 0.97 offset 0.5,0 tc 'gray40'\n",
                         x, quoted(label));
  return lines;
}

/// The colour maps of lambda: blue stable, white 0, red unstable (on a range symmetric about 0).
constexpr const char* kStabilityPalette = "set palette defined (0 'blue', 1 'white', 2 'red')\n";

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
  const std::string lines = vertical_marks(marks);
  render_png(png_path, csv, [&](const std::string& data) {
    return fmt::format(
        "set key outside right autotitle columnhead\nset grid\nset xlabel '{}'\nset ylabel '{}'\nset title '{}'\n{}"
        "plot for [c=2:{}] '{}' using 1:c with lines lw 2\n",
        quoted(xlabel), quoted(ylabel), quoted(title), lines, columns, data);
  });
}

namespace {
/// The class a stability plot draws a reading in: the Stability's (0..3), or 4 for the floor of a decay.
constexpr int kFloorClass = 4;
int reading_class(const PlottedReading& p) { return p.in_decay_floor ? kFloorClass : static_cast<int>(p.stability); }

/// A value for the plots' data: gnuplot reads "NaN" as undefined (a point not drawn, a gap in a line).
std::string data_value(double v) { return std::isfinite(v) ? fmt::format("{:.10g}", v) : std::string("NaN"); }

struct ClassStyle {
  const char* style;
  const char* title;
};
/// By reading_class: the colours of plot_exponents_png (blue decaying, red growing), neutral green.
constexpr std::array<ClassStyle, 4> kReadingStyles = {{
    {"pt 7 ps 1 lw 2 lc rgb '#1f77b4'", "stable"},
    {"pt 7 ps 1 lw 2 lc rgb '#2ca02c'", "neutral (the interval reaches the band around 0)"},
    {"pt 7 ps 1 lw 2 lc rgb '#d62728'", "unstable"},
    {"pt 6 ps 1 lw 1 lc rgb 'gray50'", "undetermined (lambda does not measure the divergence)"},
}};
constexpr const char* kFloorTitle = "stable: decayed to rest before the window (lambda, the solver's residue, not drawn)";
}  // namespace

void plot_readings_png(const std::vector<PlottedReading>& points, const std::string& title, const std::string& xlabel,
                       const std::string& ylabel, const std::string& png_path, bool join,
                       const std::vector<std::pair<double, std::string>>& marks) {
  // The y range holds 0 (the stability boundary) and every drawn value and interval; the floor's
  // marks go below them, where no lambda is.
  double lo = 0.0, hi = 0.0;
  bool floor = false, drawn = false;
  std::array<bool, kReadingStyles.size()> present{};
  for (const auto& p : points) {
    const int c = reading_class(p);
    if (c == kFloorClass) {
      floor = true;
      continue;
    }
    present[static_cast<std::size_t>(c)] = true;
    drawn = true;
    for (const double v : {p.lambda, p.low, p.high})
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  const double span = hi > lo ? hi - lo : 1.0;
  const double mark = lo - 0.08 * span;
  std::string csv = "x,lambda,low,high,class,mark\n";
  for (const auto& p : points)
    csv += fmt::format("{},{},{},{},{},{}\n", data_value(p.x), data_value(p.lambda), data_value(p.low), data_value(p.high),
                       reading_class(p), data_value(mark));
  render_png(png_path, csv, [&](const std::string& data) {
    std::string terms;
    const auto add = [&](const std::string& term) { terms += (terms.empty() ? "'" + data + "' " : ", '' ") + term; };
    if (join) add(fmt::format("every ::1 using 1:($5 < 3 ? $2 : 1/0) with lines lw 1 lc rgb 'gray70' notitle"));
    for (std::size_t c = 0; c < kReadingStyles.size(); ++c)
      if (present[c])
        add(fmt::format("every ::1 using 1:($5 == {} ? $2 : 1/0):3:4 with yerrorbars {} title '{}'", c,
                        kReadingStyles[c].style, quoted(kReadingStyles[c].title)));
    if (floor)
      add(fmt::format("every ::1 using 1:($5 == {} ? $6 : 1/0) with points pt 11 ps 1.6 lc rgb '#1f77b4' title '{}'",
                      kFloorClass, quoted(kFloorTitle)));
    return fmt::format(
        "set key below\nset grid\nset xlabel '{}'\nset ylabel '{}'\nset title '{}'\nset offsets graph 0.05, graph 0.05, 0, 0\n"
        "set yrange [{:.10g}:{:.10g}]\n{}{}set xzeroaxis lt -1 lc 'gray40'\nplot {}\n",
        quoted(xlabel), quoted(ylabel), quoted(title), (floor ? mark : lo) - 0.05 * span, hi + 0.05 * span,
        drawn ? "" : "set ytics ('0' 0)\n",  // only marks: no scale of values that are not there
        vertical_marks(marks), terms);
  });
}

void plot_reading_map_png(const std::vector<PlottedReading>& points, const std::string& title, const std::string& xlabel,
                          const std::string& ylabel, const std::string& zlabel, const std::string& png_path) {
  // White is 0: stable blue, unstable red, on a scale symmetric about 0; a point in the floor of a
  // decay takes the stable end (its lambda is a residue).
  double m = 0.0;
  bool floor = false, undetermined = false;
  for (const auto& p : points) {
    const int c = reading_class(p);
    floor = floor || c == kFloorClass;
    undetermined = undetermined || c == static_cast<int>(Stability::undetermined);
    if (c != kFloorClass && std::isfinite(p.lambda)) m = std::max(m, std::abs(p.lambda));
  }
  if (m == 0.0) m = 1.0;
  std::string csv = "x,y,lambda,class\n";
  for (const auto& p : points)
    csv += fmt::format("{},{},{},{}\n", data_value(p.x), data_value(p.y),
                       data_value(reading_class(p) == kFloorClass ? -m : p.lambda), reading_class(p));
  render_png(png_path, csv, [&](const std::string& data) {
    std::string marks;
    if (floor)
      marks += fmt::format(", '' every ::1 using 1:($4 == {} ? $2 : 1/0) with points pt 6 ps 2 lw 2 lc rgb 'black' title '{}'",
                           kFloorClass, quoted(kFloorTitle));
    if (undetermined)
      marks += fmt::format(", '' every ::1 using 1:($4 == {} ? $2 : 1/0) with points pt 2 ps 2 lw 2 lc rgb 'gray30' title '{}'",
                           static_cast<int>(Stability::undetermined), quoted(kReadingStyles[3].title));
    return fmt::format(
        "set title '{}'\nset xlabel '{}'\nset ylabel '{}'\nset cblabel '{}'\nset view map\n"
        "{}set key below\nset cbrange [{:.10g}:{:.10g}]\n"
        "plot '{}' every ::1 using 1:2:3 with image notitle{}\n",
        quoted(title), quoted(xlabel), quoted(ylabel), quoted(zlabel), kStabilityPalette, -m, m, data, marks);
  }, 700);
}

namespace {

/// The complex plane's axes for `data`, whose column `real_column` holds the real parts: grid, labels,
/// the stability boundary (real part 0) drawn bold, and the x range widened to keep it in sight.
std::string complex_plane(const std::string& xlabel, const std::string& ylabel, const std::string& title,
                          const std::string& data, int real_column) {
  return fmt::format(
      "set grid\nset xlabel '{}'\nset ylabel '{}'\nset title '{}'\n"
      "set offsets graph 0.1, graph 0.1, graph 0.1, graph 0.1\n"
      "set yzeroaxis lt -1 lw 2 lc 'gray40'\nset xzeroaxis lt 0 lc 'gray60'\n"
      "stats '{}' every ::1 using {} nooutput\n"
      "if (STATS_max < 0) set xrange [:-0.05 * STATS_min]\n"
      "if (STATS_min > 0) set xrange [-0.05 * STATS_max:]\n",
      quoted(xlabel), quoted(ylabel), quoted(title), data, real_column);
}

}  // namespace

void plot_exponents_png(const std::string& csv, const std::string& title, const std::string& unit,
                        const std::string& png_path) {
  render_png(png_path, csv, [&](const std::string& data) {
    return "set key below\n" +
           complex_plane("lambda, growth rate (1/" + unit + ")", "frequency (rad/" + unit + ")", title, data, 2) +
           fmt::format("plot '{0}' every ::1 using 2:($2 < 0 ? $3 : 1/0) with points pt 7 ps 1.3 lc rgb '#1f77b4' title "
                       "'decaying (lambda < 0)', '' every ::1 using 2:($2 >= 0 ? $3 : 1/0) with points pt 7 ps 1.6 lc rgb "
                       "'#d62728' title 'growing or neutral (lambda >= 0)'\n",
                       data);
  });
}

void plot_eigenvalues_by_time_png(const std::string& csv, const std::string& title, const std::string& png_path) {
  render_png(png_path, csv, [&](const std::string& data) {
    return "set key off\nset palette defined (0 '#1f77b4', 1 '#2ca02c', 2 '#ff7f0e', 3 '#d62728')\n"
           "set cblabel 'time of the analysis'\n" +
           fmt::format("stats '{}' every ::1 using 1 nooutput\n"  // one analysis: one colour, no colour box
                       "if (STATS_max > STATS_min) set cbrange [STATS_min:STATS_max]; "
                       "else set cbrange [STATS_min - 1:STATS_max + 1]; unset colorbox\n",
                       data) +
           complex_plane("real part, growth rate (1/time unit)", "imaginary part (rad/time unit)", title, data, 2) +
           fmt::format("plot '{}' every ::1 using 2:3:1 with points pt 7 ps 1.3 lc palette\n", data);
  });
}

void plot_map_png(const std::string& csv, const std::string& title, const std::string& xlabel, const std::string& ylabel,
                  const std::string& zlabel, const std::string& png_path) {
  render_png(png_path, csv, [&](const std::string& data) {
    return fmt::format(
        "set title '{}'\nset xlabel '{}'\nset ylabel '{}'\nset cblabel '{}'\nset view map\n"
        "{}set key off\n"
        "stats '{}' every ::1 using 3 nooutput\nm = abs(STATS_min) > abs(STATS_max) ? abs(STATS_min) : abs(STATS_max)\n"
        "if (m > 0) set cbrange [-m:m]\n"  // white is 0: stable blue, unstable red
        "plot '{}' every ::1 using 1:2:3 with image\n",
        quoted(title), quoted(xlabel), quoted(ylabel), quoted(zlabel), kStabilityPalette, data, data);
  }, 700);
}

}  // namespace mlce::cli
