#include "mlce/series.hpp"

#include "mlce/numerics.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

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

/// Significant digits of the shortest decimal that reads back as v (to_chars' shortest form):
/// 1000.01 -> 6, 0.01500000000000001 -> 16.
int shortest_digits(double v) {
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific);
  int digits = 0;
  for (const char* p = buf; p != r.ptr && *p != 'e'; ++p) digits += (*p >= '0' && *p <= '9') ? 1 : 0;
  return digits;
}

/// A unit in the `digits`-th significant digit of a number of magnitude a > 0.
double printed_unit(double a, int digits) { return std::pow(10.0, std::floor(std::log10(a)) - digits + 1); }

struct Grid {
  double t0, dt;
  int digits;
};

/// Times printed with too few significant digits to resolve their step (a `%g` export at late
/// times: 1000.005 prints '1000.01', 1000.010 too) repeat or jump although the sampling is
/// uniform. They are taken as the grid t0 + k dt (least squares of t over k) when they never
/// decrease (rounding keeps the order) and every printed time lies within one unit of its last
/// printed digit of the grid (printed_unit of max(|t|, dt), P the most significant digits any
/// printed time needs), and only when the step is not a whole number of printed units (then every
/// sample prints exactly, and a deviation is the clock's). Only for P >= 6 (C's `%g`, the coarsest
/// print of a time that has outgrown its digits): short times such as sample indices 100, 101, 103
/// could hide a missing sample within one unit. Times printed at full precision (P ~ 16) leave no
/// room, so a genuinely uneven sampling is never taken for a grid.
std::optional<Grid> grid_within_print(const std::vector<double>& time) {
  const std::size_t n = time.size();
  if (n < 3 || !(time[n - 1] > time[0])) return std::nullopt;
  for (std::size_t i = 1; i < n; ++i)
    if (time[i] < time[i - 1]) return std::nullopt;
  int digits = 1;
  for (double t : time) digits = std::max(digits, shortest_digits(t));
  if (digits < 6) return std::nullopt;
  // Least squares over the centred index (long double: n may be 10^7).
  const long double kc = 0.5L * static_cast<long double>(n - 1);
  long double st = 0, skt = 0, skk = 0;
  for (std::size_t i = 0; i < n; ++i) st += time[i];
  const long double mean = st / static_cast<long double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const long double k = static_cast<long double>(i) - kc;
    skt += k * (time[i] - mean), skk += k * k;
  }
  const long double slope = skt / skk;
  if (!(slope > 0)) return std::nullopt;
  const double dt = static_cast<double>(slope);
  // A step that is a whole number of the coarsest printed unit is printed exactly at every sample:
  // then a deviation is the clock's (a skipped or repeated sample), not rounding (1000 + 0.001 k
  // printed with 7 digits and one sample missing must stay an error).
  const double coarsest = printed_unit(std::max({std::abs(time[0]), std::abs(time[n - 1]), dt}), digits);
  if (const double ratio = dt / coarsest; ratio >= 0.5 && std::abs(ratio - std::round(ratio)) <= 1e-3 * ratio)
    return std::nullopt;
  for (std::size_t i = 0; i < n; ++i) {
    const long double grid = mean + slope * (static_cast<long double>(i) - kc);
    const double unit = printed_unit(std::max(std::abs(time[i]), dt), digits);
    if (!(std::abs(static_cast<long double>(time[i]) - grid) <= unit)) return std::nullopt;
  }
  return Grid{static_cast<double>(mean - slope * kc), dt, digits};
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
  check_finite(channels);
  bool increasing = true;
  for (std::size_t i = 1; i < n && increasing; ++i) increasing = time[i] > time[i - 1];
  const double dt = (time[n - 1] - time[0]) / static_cast<double>(n - 1);
  std::size_t worst = 0;
  double worst_dev = 0.0;
  for (std::size_t i = 1; i < n && increasing; ++i) {
    const double dev = std::abs((time[i] - time[i - 1]) - dt) / dt;
    if (dev > worst_dev) worst_dev = dev, worst = i;
  }
  Series s;
  s.time_unit = std::move(time_unit);
  s.t0 = time[0];
  if (increasing && worst_dev <= options.uniformity_tolerance) {
    s.dt = dt;
    s.channels = std::move(channels);
    return s;
  }
  if (const auto grid = grid_within_print(time)) {
    s.t0 = grid->t0;
    s.dt = grid->dt;
    s.channels = std::move(channels);
    if (warnings) {
      std::size_t at = 1;
      while (at + 1 < n && time[at] > time[at - 1] &&
             std::abs((time[at] - time[at - 1]) - grid->dt) <= options.uniformity_tolerance * grid->dt)
        ++at;
      warnings->push_back("time printed with " + std::to_string(grid->digits) +
                          " significant digits, too few to resolve the step (samples " + std::to_string(at - 1) +
                          " and " + std::to_string(at) + " read " + fmt_double(time[at - 1]) + " and " +
                          fmt_double(time[at]) + "); every time is within one unit of its last digit of a uniform "
                          "step " + fmt_double(grid->dt) + " from " + fmt_double(grid->t0) + ", which is used");
    }
    return s;
  }
  for (std::size_t i = 1; i < n; ++i)
    if (!(time[i] > time[i - 1])) {
      // Time that goes back: a run restarted from an earlier time, or two runs' output joined.
      const std::string hint = time[i] < time[i - 1] ? "; a restarted run, or two runs joined? --to " +
                                                           fmt_double(time[i - 1]) + " analyses the samples before"
                                                     : "";
      throw InputError("time does not increase at sample " + std::to_string(i) + " (" + fmt_double(time[i - 1]) +
                           " then " + fmt_double(time[i]) + "): expected strictly increasing time" + hint,
                       i);
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
  // A subnormal step (below 2.2e-308) would turn an exponent per sample into inf per unit time.
  if (!(dt > 0.0) || !std::isnormal(dt))
    throw OptionError("dt = " + fmt_double(dt) + ": expected dt > 0 (a normal double, at least 2.2e-308)");
  Series s;
  check_lengths(channels, channels.empty() ? 0 : channels.front().size());
  s.channels = std::move(channels);
  s.dt = dt;
  s.time_unit = std::move(time_unit);
  return s;
}

std::string channel_name(const Series& series, std::size_t c) {
  if (c < series.names.size() && !series.names[c].empty()) return series.names[c];
  return "channel " + std::to_string(c + 1);
}

void validate_samples(const Series& series) {
  check_lengths(series.channels, series.size());
  if (!(series.dt > 0.0) || !std::isnormal(series.dt))
    throw InputError("sampling step " + fmt_double(series.dt) + ": expected dt > 0 (a normal double, at least 2.2e-308)");
  check_finite(series.channels);
  for (const auto& x : series.channels) {
    if (x.empty()) throw InputError("the series is empty");
    if (x.size() == 1) throw InputError("the series has a single sample: expected a time history");
  }
}

bool is_constant(const Series& series, std::size_t c) {
  const auto& x = series.channels.at(c);
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  return lo == x.end() || *lo == *hi;
}

void validate_series(const Series& series) {
  validate_samples(series);
  for (std::size_t c = 0; c < series.channels.size(); ++c)
    if (is_constant(series, c))
      throw InputError(channel_name(series, c) + " is constant (all " + std::to_string(series.channels[c].size()) +
                       " samples equal " + fmt_double(series.channels[c].front()) + "): no dynamics to analyse");
}

namespace {

void check_spike_options(const SpikeOptions& o) {
  if (!(o.jump_ratio > 1.0) || !std::isfinite(o.jump_ratio)) throw OptionError("spikes.jump_ratio: expected a finite ratio > 1");
  if (o.max_length < 1) throw OptionError("spikes.max_length: expected >= 1");
  if (o.max_count < 1) throw OptionError("spikes.max_count: expected >= 1");
}

/// find_isolated_spikes for one channel. The r largest jumps are the spikes' when the r-th exceeds
/// jump_ratio times the (r+1)-th (the largest ordinary one) and they pair up into spikes: runs of
/// consecutive large jumps at most max_length apart, each entered and left inside the record and
/// returning near where it left. The largest such r is taken (every spike at once).
std::vector<IsolatedSpike> spikes_of_channel(const std::vector<double>& x, std::size_t channel, const SpikeOptions& o) {
  const std::size_t n = x.size();
  const std::size_t margin = o.max_length + 1;
  if (n < 2 * margin + 1) return {};
  double largest = 0.0;
  for (const double v : x) largest = std::max(largest, std::abs(v));
  if (!(largest > 0.0)) return {};
  const auto at = [&](std::size_t i) { return x[i] / largest; };  // in [-1, 1]: a jump is at most 2
  std::vector<double> jump(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) jump[i] = std::abs(at(i + 1) - at(i));
  const std::size_t ranked = std::min(n - 1, o.max_count * (o.max_length + 1) + 1);
  std::vector<std::size_t> order(n - 1);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(ranked), order.end(),
                    [&](std::size_t a, std::size_t b) { return jump[a] > jump[b] || (jump[a] == jump[b] && a < b); });
  for (std::size_t r = ranked - 1; r > 0; --r) {
    const double ordinary = jump[order[r]];
    if (!(jump[order[r - 1]] > o.jump_ratio * ordinary)) continue;
    std::vector<std::size_t> large(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(r));
    std::sort(large.begin(), large.end());
    std::vector<IsolatedSpike> found;
    bool pairs_up = true;
    for (std::size_t g = 0; g < large.size() && pairs_up;) {
      std::size_t h = g;
      while (h + 1 < large.size() && large[h + 1] - large[h] <= o.max_length) ++h;
      const std::size_t in = large[g], out = large[h];  // jumps x[in] -> x[in + 1], x[out] -> x[out + 1]
      const std::size_t length = out - in;               // samples in + 1 .. out
      const bool entered_and_left = h > g;               // two large jumps at least
      g = h + 1;
      // Within max_length + 1 samples of an end: the record's start-up or end, not a glitch (an
      // MBDyn run's joint reactions ring through samples 1..3 as the solver starts: -6036, +1649,
      // -276, then the motion at ~35).
      if (in + 1 < margin || out + margin > n - 1) continue;
      pairs_up = entered_and_left && length <= o.max_length &&
                 std::abs(at(out + 1) - at(in)) <= static_cast<double>(length + 1) * ordinary;
      if (pairs_up) {
        IsolatedSpike s;
        s.channel = channel, s.first = in + 1, s.last = out, s.before = x[in], s.after = x[out + 1];
        double farthest = -1.0;
        for (std::size_t i = s.first; i <= s.last; ++i) {
          const double along = static_cast<double>(i - in) / static_cast<double>(length + 1);
          const double off = std::abs(at(i) - (at(in) + along * (at(out + 1) - at(in))));
          if (off > farthest) farthest = off, s.peak = x[i];
        }
        s.jump_ratio = ordinary > 0.0 ? std::min(jump[in], jump[out]) / ordinary : std::numeric_limits<double>::infinity();
        found.push_back(s);
      }
    }
    if (pairs_up && !found.empty() && found.size() <= o.max_count) return found;
  }
  return {};
}

std::string spike_place(const Series& series, const IsolatedSpike& s) {
  const std::string unit = series.time_unit.empty() ? "" : " " + series.time_unit;
  if (s.first == s.last) return fmt::format("sample {} (t = {:.10g}{})", s.first, series.time(s.first), unit);
  return fmt::format("samples {}..{} (t = {:.10g} .. {:.10g}{})", s.first, s.last, series.time(s.first),
                     series.time(s.last), unit);
}

std::string spike_shape(const IsolatedSpike& s) {
  return fmt::format("{:.6g} between {:.6g} and {:.6g}, its jumps in and out {} times any other jump of the record",
                     s.peak, s.before, s.after,
                     std::isfinite(s.jump_ratio) ? fmt::format("{:.3g}", s.jump_ratio) : std::string("infinitely many"));
}

}  // namespace

std::vector<IsolatedSpike> find_isolated_spikes(const Series& series, const SpikeOptions& options) {
  check_spike_options(options);
  check_finite(series.channels);  // a nan would leave the jumps' ranking without an order
  std::vector<IsolatedSpike> all;
  for (std::size_t c = 0; c < series.channels.size(); ++c) {
    auto found = spikes_of_channel(series.channels[c], c, options);
    all.insert(all.end(), found.begin(), found.end());
  }
  return all;
}

void refuse_isolated_spikes(const Series& series, const SpikeOptions& options, std::size_t first_analysed) {
  auto spikes = find_isolated_spikes(series, options);
  std::erase_if(spikes, [&](const IsolatedSpike& s) { return s.first < first_analysed; });
  if (spikes.empty()) return;
  const IsolatedSpike& s = spikes.front();
  std::string more;
  if (spikes.size() > 1) {
    std::vector<std::string> places;
    for (std::size_t k = 1; k < spikes.size(); ++k)
      places.push_back(channel_name(series, spikes[k].channel) + " " + spike_place(series, spikes[k]));
    more = fmt::format("; {} more: {}", spikes.size() - 1, fmt::join(places, ", "));
  }
  throw InputError(fmt::format("{}: {} is an isolated spike: {} (a corrupt line, an unconverged solver step?){}; "
                               "a glitch moves the exponent far: correct it, cut it out with --from/--to, or "
                               "--despike (the straight line between its neighbours)",
                               channel_name(series, s.channel), spike_place(series, s), spike_shape(s), more),
                   s.first);
}

std::vector<std::string> replace_isolated_spikes(Series& series, const SpikeOptions& options) {
  std::vector<std::string> messages;
  for (const IsolatedSpike& s : find_isolated_spikes(series, options)) {
    auto& x = series.channels[s.channel];
    const double steps = static_cast<double>(s.last - s.first + 2);
    for (std::size_t i = s.first; i <= s.last; ++i) {
      const double w = static_cast<double>(i - s.first + 1) / steps;
      x[i] = (1.0 - w) * s.before + w * s.after;  // no difference of samples: finite for any finite pair
    }
    messages.push_back(fmt::format("{}: {} was an isolated spike ({}): replaced by the straight line between its "
                                   "neighbours (--despike)",
                                   channel_name(series, s.channel), spike_place(series, s), spike_shape(s)));
  }
  return messages;
}

std::size_t first_sample_from(const Series& series, double from) {
  const double tol = 1e-9 * series.dt;
  std::size_t a = 0;
  while (a < series.size() && series.time(a) < from - tol) ++a;
  return a;
}

Series time_window(const Series& series, double from, double to) {
  if (!(to >= from)) throw OptionError("time window [" + fmt_double(from) + ", " + fmt_double(to) + "] is empty");
  const std::size_t n = series.size();
  const double tol = 1e-9 * series.dt;
  const std::size_t a = first_sample_from(series, from);
  std::size_t b = n;
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

Series leading_samples(const Series& series, std::size_t count) {
  Series part;
  part.dt = series.dt, part.t0 = series.t0, part.time_unit = series.time_unit, part.names = series.names;
  for (const auto& c : series.channels) part.channels.emplace_back(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(count));
  return part;
}

Series channel_subset(const Series& series, const std::vector<std::size_t>& channels) {
  Series s;
  s.dt = series.dt, s.t0 = series.t0, s.time_unit = series.time_unit;
  for (const std::size_t c : channels) {
    s.channels.push_back(series.channels.at(c));
    s.names.push_back(channel_name(series, c));
  }
  return s;
}

namespace {
/// A channel's largest magnitude, and the mean and standard deviation of the channel divided by it
/// (no square of 1e200 overflows, none of 1e-200 underflows).
struct PeakMoments {
  double peak = 0.0, mean = 0.0, sd = 0.0;
};
PeakMoments peak_moments(const std::vector<double>& x) {
  PeakMoments m;
  m.peak = max_abs(x);
  if (m.peak == 0.0) return m;
  for (double v : x) m.mean += v / m.peak;
  m.mean /= static_cast<double>(x.size());
  double var = 0.0;
  for (double v : x) var += (v / m.peak - m.mean) * (v / m.peak - m.mean);
  m.sd = std::sqrt(var / static_cast<double>(x.size()));
  return m;
}

Series normalised(const Series& series, bool shift_to_zero_mean) {
  Series s = series;
  for (auto& x : s.channels) {
    const auto [peak, mean, sd] = peak_moments(x);
    if (peak == 0.0) continue;
    // Divide by the peak first: squares of 1e200 overflow, squares of 1e-200 underflow.
    for (double& v : x) v /= peak;
    if (sd == 0.0) continue;
    if (shift_to_zero_mean)
      for (double& v : x) v = (v - mean) / sd;
    else
      for (double& v : x) v /= sd;
  }
  return s;
}
}  // namespace

std::vector<double> unit_deviation_divisors(const Series& series) {
  std::vector<double> divisors;
  for (const auto& x : series.channels) {
    const auto [peak, mean, sd] = peak_moments(x);
    divisors.push_back(peak == 0.0 ? 1.0 : sd == 0.0 ? peak : peak * sd);
  }
  return divisors;
}

std::vector<double> peak_deviations(const Series& series) {
  std::vector<double> out;
  for (const auto& x : series.channels) {
    const auto [peak, mean, sd] = peak_moments(x);
    double largest = 0.0;
    if (peak > 0.0)
      for (double v : x) largest = std::max(largest, std::abs(v / peak - mean));
    out.push_back(peak * largest);
  }
  return out;
}

std::vector<double> rms_deviations(const Series& series) {
  std::vector<double> out;
  for (const auto& x : series.channels) {
    const auto [peak, mean, sd] = peak_moments(x);
    out.push_back(peak * sd);
  }
  return out;
}

Series standardized(const Series& series) { return normalised(series, true); }

Series scaled_to_unit_deviation(const Series& series) { return normalised(series, false); }

}  // namespace mlce
