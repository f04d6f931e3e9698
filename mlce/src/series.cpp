#include "mlce/series.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mlce {
namespace {

std::string fmt_double(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

void check_finite(const std::vector<std::vector<double>>& channels) {
  for (std::size_t c = 0; c < channels.size(); ++c)
    for (std::size_t i = 0; i < channels[c].size(); ++i)
      if (!std::isfinite(channels[c][i]))
        throw InputError("sample " + std::to_string(i) + " of channel " + std::to_string(c + 1) + " is " +
                             fmt_double(channels[c][i]) + ": expected a finite number",
                         i);
}

void check_lengths(const std::vector<std::vector<double>>& channels, std::size_t n) {
  if (channels.empty()) throw InputError("the series has no channel");
  for (std::size_t c = 0; c < channels.size(); ++c)
    if (channels[c].size() != n)
      throw InputError("channel " + std::to_string(c + 1) + " has " + std::to_string(channels[c].size()) +
                       " samples, expected " + std::to_string(n));
}

}  // namespace

Series make_series_from_time(const std::vector<double>& time, std::vector<std::vector<double>> channels,
                             const SamplingOptions& options, std::vector<std::string>* warnings,
                             std::string time_unit) {
  const std::size_t n = time.size();
  check_lengths(channels, n);
  if (n < 2) throw InputError("the series has " + std::to_string(n) + " sample(s): expected at least 2");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(time[i]))
      throw InputError("time at sample " + std::to_string(i) + " is not finite", i);
  for (std::size_t i = 1; i < n; ++i)
    if (!(time[i] > time[i - 1]))
      throw InputError("time does not increase at sample " + std::to_string(i) + " (" + fmt_double(time[i - 1]) +
                           " then " + fmt_double(time[i]) + "): expected strictly increasing time",
                       i);
  check_finite(channels);

  const double dt = (time[n - 1] - time[0]) / static_cast<double>(n - 1);
  std::size_t worst = 0;
  double worst_dev = 0.0;
  for (std::size_t i = 1; i < n; ++i) {
    const double dev = std::abs((time[i] - time[i - 1]) - dt) / dt;
    if (dev > worst_dev) worst_dev = dev, worst = i;
  }
  Series s;
  s.time_unit = std::move(time_unit);
  s.t0 = time[0];
  if (worst_dev <= options.uniformity_tolerance) {
    s.dt = dt;
    s.channels = std::move(channels);
    return s;
  }
  if (!options.resample)
    throw InputError("non-uniform time step at sample " + std::to_string(worst) + ": step " +
                         fmt_double(time[worst] - time[worst - 1]) + " vs mean " + fmt_double(dt) +
                         " (tolerance " + fmt_double(options.uniformity_tolerance * 100) +
                         " %); resample explicitly (--resample) or select a uniform part",
                     worst);

  // Explicit resampling: linear interpolation onto the grid of the median step.
  std::vector<double> steps(n - 1);
  for (std::size_t i = 1; i < n; ++i) steps[i - 1] = time[i] - time[i - 1];
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  const double h = steps[steps.size() / 2];
  const auto m = static_cast<std::size_t>(std::floor((time[n - 1] - time[0]) / h)) + 1;
  s.dt = h;
  s.channels.assign(channels.size(), std::vector<double>(m));
  std::size_t k = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const double t = time[0] + h * static_cast<double>(i);
    while (k + 2 < n && time[k + 1] < t) ++k;
    const double a = std::clamp((t - time[k]) / (time[k + 1] - time[k]), 0.0, 1.0);
    for (std::size_t c = 0; c < channels.size(); ++c)
      s.channels[c][i] = (1.0 - a) * channels[c][k] + a * channels[c][k + 1];
  }
  if (warnings)
    warnings->push_back("non-uniform time (largest step deviation " + fmt_double(worst_dev * 100) +
                        " % at sample " + std::to_string(worst) + ") resampled linearly to step " +
                        fmt_double(h) + ", " + std::to_string(m) + " samples");
  return s;
}

Series make_series_with_step(std::vector<std::vector<double>> channels, double dt, std::string time_unit) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw OptionError("dt = " + fmt_double(dt) + ": expected dt > 0");
  Series s;
  check_lengths(channels, channels.empty() ? 0 : channels.front().size());
  s.channels = std::move(channels);
  s.dt = dt;
  s.time_unit = std::move(time_unit);
  return s;
}

void validate_series(const Series& series) {
  check_lengths(series.channels, series.size());
  if (!(series.dt > 0.0) || !std::isfinite(series.dt))
    throw InputError("sampling step " + fmt_double(series.dt) + ": expected dt > 0");
  check_finite(series.channels);
  for (std::size_t c = 0; c < series.channels.size(); ++c) {
    const auto& x = series.channels[c];
    if (x.empty()) throw InputError("the series is empty");
    const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
    if (*lo == *hi)
      throw InputError("channel " + std::to_string(c + 1) + " is constant (all " + std::to_string(x.size()) +
                       " samples equal " + fmt_double(*lo) + "): no dynamics to analyse");
  }
}

Series time_window(const Series& series, double from, double to) {
  if (!(to >= from)) throw OptionError("time window [" + fmt_double(from) + ", " + fmt_double(to) + "] is empty");
  const std::size_t n = series.size();
  const double tol = 1e-9 * series.dt;
  std::size_t a = 0, b = n;
  while (a < n && series.time(a) < from - tol) ++a;
  while (b > a && series.time(b - 1) > to + tol) --b;
  if (b - a < 2)
    throw InputError("time window [" + fmt_double(from) + ", " + fmt_double(to) + "] holds " + std::to_string(b - a) +
                     " sample(s) of a series spanning [" + fmt_double(series.time(0)) + ", " +
                     fmt_double(series.time(n ? n - 1 : 0)) + "]: expected at least 2");
  Series w;
  w.dt = series.dt;
  w.t0 = series.time(a);
  w.time_unit = series.time_unit;
  w.names = series.names;
  for (const auto& ch : series.channels)
    w.channels.emplace_back(ch.begin() + static_cast<std::ptrdiff_t>(a), ch.begin() + static_cast<std::ptrdiff_t>(b));
  return w;
}

namespace {
Series normalised(const Series& series, bool shift_to_zero_mean) {
  Series s = series;
  for (auto& x : s.channels) {
    double peak = 0.0;
    for (double v : x) peak = std::max(peak, std::abs(v));
    if (peak == 0.0) continue;
    // Divide by the peak first: squares of 1e200 overflow, squares of 1e-200 underflow.
    double mean = 0.0;
    for (double& v : x) v /= peak;
    for (double v : x) mean += v;
    mean /= static_cast<double>(x.size());
    double var = 0.0;
    for (double v : x) var += (v - mean) * (v - mean);
    const double sd = std::sqrt(var / static_cast<double>(x.size()));
    if (sd == 0.0) continue;
    if (shift_to_zero_mean)
      for (double& v : x) v = (v - mean) / sd;
    else
      for (double& v : x) v /= sd;
  }
  return s;
}
}  // namespace

Series standardized(const Series& series) { return normalised(series, true); }

Series scaled_to_unit_deviation(const Series& series) { return normalised(series, false); }

}  // namespace mlce
