#include "mlce/ami.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "mlce/numerics.hpp"

namespace mlce {
namespace {

/// The narrowest moving average (lags), and the reach of the coarse-sampling search below, which
/// looks for a minimum that this average lost within its first 2 x 3 lags, whatever width the
/// ripple spacing gives the average itself (a coarse flow's period is short, and its width 3 anyway).
constexpr std::size_t kNarrowestSmoothing = 3;

/// Equal-width bins over the range; `shift` moves every edge by that fraction of a width (the
/// first and last bins then hold the ends: `bins` + 1 bins when shift > 0).
std::vector<std::uint16_t> bin_indices(const std::vector<double>& x, std::size_t bins, double shift = 0.0) {
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  const double width = (*hi - *lo) / static_cast<double>(bins);
  const std::size_t last = shift > 0.0 ? bins : bins - 1;
  std::vector<std::uint16_t> b(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    auto k = static_cast<std::size_t>((x[i] - *lo) / width + shift);
    b[i] = static_cast<std::uint16_t>(std::min(k, last));
  }
  return b;
}

/// Histogram estimate of I(x_t; x_{t+tau}) in nats, marginals taken over the overlapping samples.
double mutual_information(const std::vector<std::uint16_t>& b, std::size_t bins, std::size_t tau,
                          std::vector<std::uint32_t>& joint) {
  const std::size_t n = b.size() - tau;
  std::fill(joint.begin(), joint.end(), 0u);
  for (std::size_t t = 0; t < n; ++t) ++joint[b[t] * bins + b[t + tau]];
  std::vector<double> px(bins, 0.0), py(bins, 0.0);
  for (std::size_t i = 0; i < bins; ++i)
    for (std::size_t j = 0; j < bins; ++j) {
      px[i] += joint[i * bins + j];
      py[j] += joint[i * bins + j];
    }
  const double nn = static_cast<double>(n);
  CompensatedSum sum;
  for (std::size_t i = 0; i < bins; ++i)
    for (std::size_t j = 0; j < bins; ++j) {
      const double c = joint[i * bins + j];
      if (c > 0.0) sum.add(c / nn * std::log(c * nn / (px[i] * py[j])));
    }
  return std::max(0.0, sum.value());
}

struct ChannelAmi {
  std::vector<double> ami, smoothed;
  std::size_t delay = 0;  // 0: no significant minimum
  double floor = 0.0;
  double scatter = 0.0;  // sigma of the raw curve about its trend, where the minimum was accepted
};

/// Robust scatter sigma of a curve's values about a smooth trend, from its third differences over
/// lags [from, to] (each needs lags k - 1 .. k + 2): a third difference leaves a quadratic trend out
/// and has variance 20 sigma^2 for independent errors; the median of their magnitudes is 0.6745 of
/// their standard deviation for Gaussian errors (MAD). 0 when fewer than 5 differences are available.
double curve_scatter(const std::vector<double>& a, std::size_t from, std::size_t to) {
  std::vector<double> third;
  for (std::size_t k = std::max<std::size_t>(1, from); k <= to && k + 2 < a.size(); ++k)
    third.push_back(std::abs(a[k + 2] - 3.0 * a[k + 1] + 3.0 * a[k] - a[k - 1]));
  if (third.size() < 5) return 0.0;
  return 1.4826 * upper_median(std::move(third)) / std::sqrt(20.0);
}

ChannelAmi channel_ami(const std::vector<double>& x, std::size_t bins, std::size_t max_delay,
                       const AmiOptions& o) {
  ChannelAmi r;
  const auto b = bin_indices(x, bins);
  std::vector<std::uint32_t> joint(bins * bins);
  const std::size_t h = o.smoothing / 2;
  r.floor = static_cast<double>((bins - 1) * (bins - 1)) / (2.0 * static_cast<double>(x.size()));
  // Centred on lag t; within h of lag 0 the window narrows to t on either side (lag 0 itself raw),
  // so that the smoothed curve has no step where the full window begins.
  auto smooth_at = [&](std::size_t t) {
    const std::size_t half = std::min(t, h);
    double s = 0.0;
    for (std::size_t k = t - half; k <= t + half; ++k) s += r.ami[k];
    return s / static_cast<double>(2 * half + 1);
  };
  std::size_t candidate = 0;  // a local minimum being confirmed
  std::size_t shoulder = 0;   // first local minimum of a stretch that may be flat (see below)
  for (std::size_t tau = 0; tau <= max_delay; ++tau) {
    r.ami.push_back(mutual_information(b, bins, tau, joint));
    if (tau < h) continue;  // smoothed[t] is centred on lag t: it needs lag t + h
    r.smoothed.push_back(smooth_at(tau - h));
    const std::size_t t = r.smoothed.size() - 1;  // newest smoothed index
    if (r.delay != 0) continue;  // the whole curve is wanted (`ami` command): only extend it
    if (candidate != 0) {
      const double depth = r.smoothed[0] - r.smoothed[candidate];
      // Near the floor the estimator's bias b hides structure (maps decay into it within a few
      // lags and then wiggle): there a rise must exceed significance x b. Well above it the curve
      // of a sampled flow is smooth, b is an offset shared by neighbouring lags, and a shallow
      // first minimum (Lorenz x: ~1 % of the drop from I(0)) is the minimum.
      const bool near_floor = r.smoothed[candidate] < o.floor_zone * r.floor;
      double need = near_floor ? std::max(o.significance * r.floor, 0.01 * depth) : o.relative_rise * depth;
      // And above the curve's own scatter (AmiOptions::noise_rise): the standard error of the
      // difference of two averages of w raw values is sigma sqrt(2 / w). Measured from half the
      // candidate's lag on, where the decline has flattened (its curvature is not scatter), up to
      // the newest raw lag. A median over lags, so computed only once the rise passes the other need.
      double scatter = 0.0;
      if (o.noise_rise > 0.0 && r.smoothed[t] - r.smoothed[candidate] >= need) {
        scatter = curve_scatter(r.ami, candidate / 2, r.ami.size() - 3);
        need = std::max(need, o.noise_rise * scatter * std::sqrt(2.0 / static_cast<double>(2 * h + 1)));
      }
      if (r.smoothed[t] < r.smoothed[candidate]) {
        candidate = 0;  // the curve kept falling: not a minimum
      } else if (r.smoothed[t] - r.smoothed[candidate] >= need) {
        r.delay = candidate;  // significant rise after it: accepted
        r.scatter = scatter;
        // A minimum at the level of independent samples (below significance x b) is the floor of a
        // series that decorrelates completely and rises again only at its next recurrence (the
        // spikes of Roessler z): the decline ended where the curve first came within b of that
        // level, not at the last wiggle before the recurrence.
        if (r.smoothed[candidate] < o.significance * r.floor)
          while (r.delay > 1 && r.smoothed[r.delay - 1] <= r.smoothed[candidate] + r.floor) --r.delay;
      } else if (t > 2 * candidate + 2 * h + 2) {
        candidate = 0;  // no significant rise within as many steps again: noise-floor wiggle
      }
    }
    // A shoulder: well above the floor, the curve stops falling at a local minimum and then stays
    // within relative_rise x its drop of it, neither rising nor falling, for a third as many lags
    // again. The decline has ended there even though no minimum rises significantly: Lorenz x
    // (some series of N = 10^4; build/start_variants counts the delays of 200) stays flat to
    // +-0.4 % of its drop from lag ~20 to ~31, its wiggles too shallow to count as a rise, and
    // falls again to a deep minimum at ~60 samples, two thirds of a loop, which is no
    // reconstruction delay (the embedding with m = 3-4 then spans more than a mean period).
    if (r.delay == 0 && shoulder != 0) {
      const double tol = o.relative_rise * (r.smoothed[0] - r.smoothed[shoulder]);
      if (std::abs(r.smoothed[t] - r.smoothed[shoulder]) > tol)
        shoulder = 0;
      else if (t >= shoulder + std::max(shoulder / 3, 2 * h + 2))
        r.delay = shoulder;
    }
    if (r.delay != 0) {
      if (o.stop_at_minimum) break;
      continue;
    }
    const bool local_minimum = t >= 2 && r.smoothed[t - 1] < r.smoothed[t - 2] && r.smoothed[t - 1] <= r.smoothed[t];
    if (local_minimum && candidate == 0) candidate = t - 1;
    if (local_minimum && shoulder == 0 && r.smoothed[t - 1] >= o.floor_zone * r.floor) shoulder = t - 1;
  }
  // A coarsely sampled flow falls most of the way within its first lags, and the moving average,
  // which then spans a third or more of the way to the first minimum, smooths a minimum at lag 2..6
  // into a monotone decline (Lorenz x at dt = 0.1: I = 2.48, 0.95, 0.75, 0.78, 0.64, ... nats; the
  // smoothed curve's first minimum is at 6, where FNN needs m = 5 and the embedding window spans
  // 2.4 time units). A curve that loses more than coarse_first_lag of I(0) at its first lag may be
  // such a curve: its lags 1..2 x 3 are searched unsmoothed too. A finely sampled one is
  // not, since its raw values zigzag with the bins at small lags (a sine of 126 samples per period:
  // I = 2.57, 1.95, 1.75, 1.77, 1.59, ...), which is what the smoothing is for; and a coarse curve
  // may zigzag too, which the shifted bins below tell from a minimum of the signal.
  if (h > 0 && r.ami.size() > 1 && r.ami[1] < (1.0 - o.coarse_first_lag) * r.ami[0]) {
    // A minimum with its rise (within as many lags again, before the curve falls below it).
    auto is_minimum = [&](const std::vector<double>& ami, std::size_t m) {
      if (!(ami[m] < ami[m - 1] && ami[m] <= ami[m + 1])) return false;
      const double need = o.relative_rise * (ami[0] - ami[m]);
      for (std::size_t j = m + 1; j < ami.size() && j <= 2 * m + 1; ++j) {
        if (ami[j] < ami[m]) return false;
        if (ami[j] - ami[m] >= need) return true;
      }
      return false;
    };
    // The bins' zigzag moves when the bin edges move, a minimum of the signal does not: with the
    // edges shifted by half a width the curve must have one too, at the same lag give or take one
    // (a shallow minimum of Lorenz x at dt = 0.05 sits at lag 4 with 16 bins, at 5 with 15).
    // Computed once, at the first candidate, over every lag a candidate (<= 2 x 3) can ask.
    std::vector<double> shifted_ami;
    auto survives_shifted_bins = [&](std::size_t m) {
      if (shifted_ami.empty()) {
        const auto shifted = bin_indices(x, bins, 0.5);
        std::vector<std::uint32_t> joint2((bins + 1) * (bins + 1));
        for (std::size_t tau = 0; tau <= std::min(4 * kNarrowestSmoothing + 3, r.ami.size() - 1); ++tau)
          shifted_ami.push_back(mutual_information(shifted, bins + 1, tau, joint2));
      }
      for (std::size_t k = std::max<std::size_t>(m, 2) - 1; k <= m + 1 && k + 1 < shifted_ami.size(); ++k)
        if (is_minimum(shifted_ami, k)) return true;
      return false;
    };
    // Only a minimum the smoothing lost: one the smoothed curve has within twice its lag is the same
    // minimum shifted by the averaging (Roessler x at dt = 0.2: raw 6, smoothed 7), and stays.
    for (std::size_t m = 1; m + 1 < r.ami.size() && m <= 2 * kNarrowestSmoothing && (r.delay == 0 || 2 * m <= r.delay); ++m) {
      if (r.ami[m] >= o.floor_zone * r.floor && is_minimum(r.ami, m) && survives_shifted_bins(m)) {
        r.delay = m;
        r.scatter = 0.0;  // a minimum of the raw curve, not of the smoothed one
        break;
      }
    }
  }
  // Smoothed values for the tail (truncated window).
  while (r.smoothed.size() < r.ami.size()) r.smoothed.push_back(r.ami[r.smoothed.size()]);
  return r;
}

/// AmiOptions::smoothing = 0: the ripple spacing T / (pi B) of the histogram estimate for a motion of
/// mean period T (samples) over B bins, rounded down to odd, at least 3 (see ami.hpp).
std::size_t automatic_smoothing(std::size_t mean_period, std::size_t bins, bool map) {
  if (map || mean_period == 0) return kNarrowestSmoothing;
  const auto spacing = static_cast<std::size_t>(static_cast<double>(mean_period) / (std::numbers::pi * static_cast<double>(bins)));
  if (spacing <= kNarrowestSmoothing) return kNarrowestSmoothing;
  return spacing % 2 == 1 ? spacing : spacing - 1;
}

}  // namespace

const char* to_string(DelayRule rule) {
  switch (rule) {
    case DelayRule::first_minimum: return "first AMI minimum";
    case DelayRule::autocorrelation_1e: return "autocorrelation 1/e time";
    case DelayRule::map_iteration: return "a map's iteration";
  }
  return "unknown";
}

void AmiOptions::validate() const {
  if (smoothing % 2 == 0 && smoothing != 0)
    throw OptionError("ami.smoothing = " + std::to_string(smoothing) + ": expected an odd width >= 1 (0 = auto)");
  if (bins == 1 || bins > 4096) throw OptionError("ami.bins = " + std::to_string(bins) + ": expected 2..4096 (0 = auto)");
  if (!(significance >= 0.0)) throw OptionError("ami.significance: expected >= 0");
  if (!(floor_zone >= 0.0)) throw OptionError("ami.floor_zone: expected >= 0");
  if (!(relative_rise >= 0.0 && relative_rise < 1.0)) throw OptionError("ami.relative_rise: expected 0 <= value < 1");
  if (!(noise_rise >= 0.0 && std::isfinite(noise_rise))) throw OptionError("ami.noise_rise: expected a finite value >= 0 (0 = off)");
  if (!(coarse_first_lag > 0.0 && coarse_first_lag <= 1.0)) throw OptionError("ami.coarse_first_lag: expected 0 < value <= 1");
}

std::size_t autocorrelation_time(const std::vector<double>& x, std::size_t max_lag) {
  const double target = std::exp(-1.0) * lagged_product_sum(x, 0);
  for (std::size_t lag = 1; lag <= max_lag && lag < x.size(); ++lag)
    if (lagged_product_sum(x, lag) <= target) return lag;
  return std::max<std::size_t>(1, std::min(max_lag, x.size() - 1));
}

AmiResult estimate_delay_ami(const Series& series, const AmiOptions& options) {
  options.validate();
  validate_series(series);
  const std::size_t n = series.size();
  if (n < 16) throw InputError("AMI needs at least 16 samples, the series has " + std::to_string(n));
  AmiResult r;
  r.bins = options.bins ? options.bins
                        : std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(std::log2(double(n)))) + 1, 4, 64);
  const std::size_t max_delay = options.max_delay ? std::min(options.max_delay, n / 2)
                                                  : std::min<std::size_t>((n - 1) / 4, 1000);
  if (options.max_delay > max_delay)  // beyond N/2 a delay's pairs would be fewer than half the series
    r.warnings.push_back("AMI: largest delay " + std::to_string(options.max_delay) + " clamped to " +
                         std::to_string(max_delay) + " (half the series' " + std::to_string(n) + " samples)");
  const Series s = standardized(series);
  std::size_t best = 0;
  bool any_fallback = false, any_map_step = false;
  const bool map = options.map || (options.mean_period > 0 && options.mean_period < kMinFlowPeriod);
  AmiOptions resolved = options;
  resolved.smoothing = options.smoothing ? options.smoothing : automatic_smoothing(options.mean_period, r.bins, map);
  r.smoothing = resolved.smoothing;
  const std::size_t map_period =
      options.mean_period > 0 ? std::min(options.mean_period, kMinFlowPeriod - 1) : kMinFlowPeriod - 1;
  for (std::size_t c = 0; c < s.channel_count(); ++c) {
    ChannelAmi a = channel_ami(s.channels[c], r.bins, max_delay, resolved);
    std::size_t d = a.delay;
    // The channel is named where there are several (mlce estimate --each names its own channels).
    const std::string channel = s.channel_count() > 1 ? channel_name(series, c) + ": " : std::string();
    if (d == 0 || (map && d > map_period)) {
      const std::size_t minimum = d;
      d = map ? 1 : autocorrelation_time(s.channels[c], max_delay);
      (map ? any_map_step : any_fallback) = true;
      r.warnings.push_back(
          channel +
          (minimum == 0 ? "AMI has no significant minimum up to tau = " + std::to_string(max_delay) +
                              " (decays into its noise floor, as for maps)"
                        : "AMI's first minimum, at tau = " + std::to_string(minimum) + ", lies beyond " +
                              std::to_string(map_period) +
                              " samples in a map: its AMI levels off above its floor, as the bands of a banded "
                              "chaotic map or the lobes of a map that switches between them slowly do, and does not "
                              "mark a decorrelation") +
          (map ? ": delay = 1 (a map's iteration)" : ": delay = autocorrelation 1/e time = " + std::to_string(d)));
    }
    r.channel_delay.push_back(d);
    if (c == 0) {
      r.ami = std::move(a.ami);
      r.smoothed = std::move(a.smoothed);
      r.noise_floor = a.floor;
      r.scatter = a.scatter;
    }
    best = best == 0 ? d : std::min(best, d);
  }
  r.delay = std::max<std::size_t>(1, best);
  r.rule = r.channel_delay.size() > 1 ? DelayRule::first_minimum
           : any_map_step             ? DelayRule::map_iteration
           : any_fallback             ? DelayRule::autocorrelation_1e
                                      : DelayRule::first_minimum;
  return r;
}

}  // namespace mlce
