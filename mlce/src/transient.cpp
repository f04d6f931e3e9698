#include "mlce/transient.hpp"

#include "mlce/mean_period.hpp"
#include "mlce/numerics.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <utility>
#include <vector>

namespace mlce {

namespace {
/// A tail of white measurement noise below this share of the largest window RMS is a floor too
/// (white_and_level_tail), and the series is analysed up to where its window RMS stays within
/// kWhiteFloorCut x the noise's. Measured on e^{-zeta w t} sin(w t) plus white noise of 0.1-3 % of
/// its start (zeta 0.01-0.05, 2000 and 8000 samples, scratch): a cut at 3x the noise level kept
/// noise-dominated pairs (zeta 0.05, 3 %: 0.30 lambda, read neutral), at 10x it left 2-3 periods
/// (read neutral, a limit cycle); at 5x every cut case read stable, at 0.83-1.01 lambda with noise
/// up to 1 % of the start and 0.39-0.82 with 3 %.
constexpr double kWhiteFloorShare = 0.1;
constexpr double kWhiteLagCorrelation = 0.3;
constexpr double kWhiteFloorCut = 5.0;
/// Fewer samples than this say nothing about their whiteness (lag correlations of a handful of
/// samples are anything): the white-noise rules then do not judge.
constexpr std::size_t kFewestToJudgeWhiteness = 16;
}  // namespace

void TransientOptions::validate() const {
  if (!(band >= 0.0)) throw OptionError("transient.band: expected >= 0 (0 = automatic)");
  if (!(band_min > 0.0 && band_min <= band_max)) throw OptionError("transient.band_min/band_max: expected 0 < min <= max");
  if (!(band_max_irregular >= band_max)) throw OptionError("transient.band_max_irregular: expected >= band_max");
  if (!(floor_ratio >= 0.0 && floor_ratio < 1.0)) throw OptionError("transient.floor_ratio: expected [0, 1)");
}

namespace {

/// Per window of `count` consecutive windows of `w` samples: the sum over channels of the squared
/// deviations, each channel divided by its peak |x| first (squares of 1e300 would overflow; the
/// callers compare levels or their logarithms' slope, so the scale does not matter otherwise).
/// Deviations about the channel's mean over samples [about_from, count * w), or, without about_from,
/// about each window's own mean. All-zero channels add nothing.
std::vector<double> window_square_sums(const Series& s, std::size_t w, std::size_t count,
                                       std::optional<std::size_t> about_from) {
  std::vector<double> sums(count, 0.0);
  for (const auto& x : s.channels) {
    const double peak = max_abs(x);
    if (!(peak > 0.0)) continue;
    auto mean_over = [&](std::size_t from, std::size_t to) {
      double mean = 0.0;
      for (std::size_t i = from; i < to; ++i) mean += x[i] / peak;
      return mean / static_cast<double>(to - from);
    };
    const double shared = about_from ? mean_over(*about_from, count * w) : 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      const double mean = about_from ? shared : mean_over(k * w, (k + 1) * w);
      for (std::size_t i = k * w; i < (k + 1) * w; ++i) sums[k] += (x[i] / peak - mean) * (x[i] / peak - mean);
    }
  }
  return sums;
}

/// Subtracts v's mean from every element and returns that mean (a compensated sum: a long
/// stretch of near-equal values keeps its last digits).
double centre_in_place(std::vector<double>& v) {
  CompensatedSum sum;
  for (const double u : v) sum.add(u);
  const double mean = sum.value() / static_cast<double>(v.size());
  for (double& u : v) u -= mean;
  return mean;
}

/// Correlations of a centred stretch at lags 1, 2 and 3 (lagged_product_sum over its lag-0 sum);
/// nullopt for a constant stretch (the underflow rule's case: no whiteness to judge).
std::optional<std::array<double, 3>> lag_correlations(const std::vector<double>& centred) {
  const double var = lagged_product_sum(centred, 0);
  if (!(var > 0.0)) return std::nullopt;
  return std::array<double, 3>{lagged_product_sum(centred, 1) / var, lagged_product_sum(centred, 2) / var,
                               lagged_product_sum(centred, 3) / var};
}

/// Are samples [from, to) of every channel white: autocorrelation at lags 1, 2 and 3, about the
/// stretch's mean, below kWhiteLagCorrelation in magnitude? A sampled periodic or smooth motion fails
/// at one of the three lags for any sampling of 2 or more samples per cycle (a sine at 4 per cycle:
/// lag 2 gives -1; at 3: lag 3 gives +1), white noise passes (|rho| ~ 1/sqrt(samples)). Constant
/// channels pass (they are the underflow rule's case).
bool white_samples(const Series& s, std::size_t from, std::size_t to) {
  for (const auto& channel : s.channels) {
    // Divided by the stretch's peak |x| first: squares of 1e300 would overflow.
    const double peak = max_abs(std::span<const double>(channel).subspan(from, to - from));
    if (!(peak > 0.0)) continue;
    std::vector<double> x(channel.begin() + static_cast<std::ptrdiff_t>(from), channel.begin() + static_cast<std::ptrdiff_t>(to));
    for (double& v : x) v /= peak;
    centre_in_place(x);
    const auto rho = lag_correlations(x);
    if (!rho) continue;
    for (const double r : *rho)
      if (std::abs(r) >= kWhiteLagCorrelation) return false;
  }
  return true;
}

/// Is the last quarter of the 100 windows white noise at a steady level, i.e. measurement noise a
/// decay has sunk into rather than a small motion it settled on? Level: the median window RMS of
/// the quarter's two halves within 2x of each other (a decay still falling is no floor). White:
/// white_samples over the quarter.
bool white_and_level_tail(const Series& s, const std::vector<double>& rms, std::size_t w) {
  const double first = upper_median({rms.begin() + 75, rms.begin() + 88}), second = upper_median({rms.begin() + 88, rms.end()});
  if (!(first <= 2.0 * second && second <= 2.0 * first)) return false;
  return white_samples(s, 75 * w, 100 * w);
}

constexpr double kWhiteIncrementTolerance = 0.2;

/// At most this share of a window's samples distinct: a sampled motion above its resolution changes
/// its value at nearly every sample (40 of 40 in the lags' windows before ~6 s).
constexpr double kQuantisedLevelShare = 0.5;

/// Steps of a resolution are as large as what they make: the increments' RMS over the RMS about the
/// mean, over the last quarter, is ~1.3-1.6 for the real isotropic run's lags at their resolution
/// and 2 sin(pi / P) for a sine of P samples a period (0.06 for the small limit cycle of
/// Transient.DecayIntoTheNoiseFloorEndsWhereTheFloorStarts, which repeats its values every period
/// as exactly as a quantum does, and is no floor).
constexpr double kQuantisedRoughness = 0.5;

/// Does the last quarter of the 100 windows of w samples step between a few written values: in the
/// channel that repeats least, the median over the quarter's windows of the number of distinct
/// values (values within 1e-9 of the channel's largest |x| are one: the rounding of a unit
/// conversion) at least 2 and at most kQuantisedLevelShare x w, and in every channel increments as
/// large as the deviations (kQuantisedRoughness)?
bool quantised_tail(const Series& s, std::size_t w) {
  std::size_t most = 0;
  for (const auto& c : s.channels) {
    CompensatedSum sum, deviation, increment;
    for (std::size_t i = 75 * w; i < 100 * w; ++i) sum.add(c[i]);
    const double mean = sum.value() / static_cast<double>(25 * w);
    for (std::size_t i = 75 * w; i < 100 * w; ++i) {
      deviation.add((c[i] - mean) * (c[i] - mean));
      if (i > 75 * w) increment.add((c[i] - c[i - 1]) * (c[i] - c[i - 1]));
    }
    // Per sample, as mean squares: 25 w deviations, 25 w - 1 increments.
    if (!(increment.value() / static_cast<double>(25 * w - 1) >=
          kQuantisedRoughness * kQuantisedRoughness * deviation.value() / static_cast<double>(25 * w)))
      return false;
    double peak = 0.0;
    for (const double v : c) peak = std::max(peak, std::abs(v));
    const double same = 1e-9 * peak;
    std::vector<double> counts, window(w);
    for (std::size_t k = 75; k < 100; ++k) {
      std::copy_n(c.begin() + static_cast<std::ptrdiff_t>(k * w), w, window.begin());
      std::sort(window.begin(), window.end());
      std::size_t distinct = 1;
      for (std::size_t i = 1; i < w; ++i) distinct += window[i] - window[i - 1] > same;
      counts.push_back(static_cast<double>(distinct));
    }
    most = std::max(most, static_cast<std::size_t>(upper_median(counts)));
  }
  // One value throughout is a constant tail (rounded to 0 or held to the bit): underflow, not steps.
  return most >= 2 && static_cast<double>(most) <= kQuantisedLevelShare * static_cast<double>(w);
}

/// Noise under a decay whose last quarter is not all noise: white_increment_noise over windows
/// 75..99 of w samples, summed in square over the channels each divided by its peak |x|, as
/// window_square_sums scales them. nullopt: not noise.
std::optional<double> increment_noise(const Series& s, std::size_t w) {
  const auto noise = white_increment_noise(s, 75 * w, 100 * w);
  if (!noise) return std::nullopt;
  double noise_square = 0.0;
  for (const double v : noise->relative) noise_square += v * v;
  if (!(noise_square > 0.0)) return std::nullopt;
  return std::sqrt(noise_square);
}

/// Increments of samples [from, to) of a channel, each sample divided by `peak` first (no square of
/// 1e300 overflows), and the third differences made of them.
std::vector<double> scaled_increments(const std::vector<double>& channel, std::size_t from, std::size_t to, double peak) {
  std::vector<double> dx(to - from - 1);
  for (std::size_t i = from; i + 1 < to; ++i) dx[i - from] = channel[i + 1] / peak - channel[i] / peak;
  return dx;
}
std::vector<double> third_differences(const std::vector<double>& dx) {
  std::vector<double> d3(dx.size() > 3 ? dx.size() - 3 : 0);
  for (std::size_t i = 0; i < d3.size(); ++i) d3[i] = dx[i + 2] - 2.0 * dx[i + 1] + dx[i];
  return d3;
}

}  // namespace

std::optional<IncrementNoise> white_increment_noise(const Series& s, std::size_t from, std::size_t to,
                                                   WhitenessTest test) {
  to = std::min(to, s.size());
  if (from >= to || to - from < kFewestToJudgeWhiteness) return std::nullopt;
  const std::size_t mid = from + (to - from) / 2;
  IncrementNoise out;
  for (const auto& channel : s.channels) {
    const double peak = max_abs(channel);
    out.relative.push_back(0.0);
    out.deviation.push_back(0.0);
    if (!(peak > 0.0)) continue;
    const std::vector<double> dx = scaled_increments(channel, from, to, peak);
    const std::vector<double> d3 = third_differences(dx);
    if (test == WhitenessTest::increments) {
      const auto rho = lag_correlations(dx);  // increments of a stationary stretch have mean ~0
      if (!rho) continue;
      const auto [rho1, rho2, rho3] = *rho;
      if (std::abs(rho1 + 0.5) >= kWhiteIncrementTolerance || std::abs(rho2) >= kWhiteLagCorrelation ||
          std::abs(rho3) >= kWhiteLagCorrelation)
        return std::nullopt;
    } else {
      // Third differences of white noise correlate -15/20, 6/20 and -1/20 at lags 1, 2 and 3.
      const auto rho = lag_correlations(d3);
      if (!rho) continue;
      const auto [rho1, rho2, rho3] = *rho;
      if (std::abs(rho1 + 0.75) >= kWhiteIncrementTolerance || std::abs(rho2 - 0.3) >= kWhiteIncrementTolerance ||
          std::abs(rho3 + 0.05) >= kWhiteIncrementTolerance)
        return std::nullopt;
    }
    double first = 0.0, second = 0.0;  // sums of (third difference)^2 in the two halves
    for (std::size_t i = 0; i < d3.size(); ++i) (from + i < mid ? first : second) += d3[i] * d3[i];
    if (!(first <= 2.0 * second && second <= 2.0 * first)) return std::nullopt;
    out.relative.back() = std::sqrt((first + second) / (20.0 * static_cast<double>(d3.size())));
    out.deviation.back() = out.relative.back() * peak;
  }
  return out;
}

std::size_t steady_noise_start(const Series& s) {
  constexpr std::size_t windows = 8;
  const std::size_t N = s.size(), w = N / windows;
  if (w < kFewestToJudgeWhiteness) return 0;
  std::vector<std::vector<double>> energy;  // per channel, per window: the sum of (third difference)^2
  for (const auto& x : s.channels) {
    const double peak = max_abs(x);
    std::vector<double> e(windows, 0.0);
    if (peak > 0.0)
      for (std::size_t k = 0; k < windows; ++k) {
        const std::size_t from = N - (windows - k) * w;  // the windows end at the series' end
        CompensatedSum sum;
        for (const double d : third_differences(scaled_increments(x, from, from + w, peak))) sum.add(d * d);
        e[k] = sum.value();
      }
    energy.push_back(std::move(e));
  }
  // The longest run of windows to the end that is steady: none of its windows exceeds the run's mean
  // by more than 3 standard errors of its difference from that mean (one-sided: a leak only raises
  // a window). Judged against the run's mean, not the windows after each: a last window low by chance
  // would otherwise refuse every window before it.
  std::size_t first = 0;  // the first window kept
  for (; first + 1 < windows; ++first) {
    const double len = static_cast<double>(windows - first);
    const double tolerance =
        3.0 * std::sqrt(kThirdDifferenceVarianceFactor / static_cast<double>(w - 4) * (1.0 - 1.0 / len));
    bool steady = true;
    for (const auto& e : energy) {
      double mean = 0.0;
      for (std::size_t k = first; k < windows; ++k) mean += e[k] / len;
      for (std::size_t k = first; k < windows && steady; ++k) steady = !(mean > 0.0) || e[k] / mean - 1.0 <= tolerance;
    }
    if (steady) break;
  }
  return first == 0 ? 0 : N - (windows - first) * w;  // the N % 8 samples before the windows go with the first
}

std::string floor_evidence(const Floor& f, double floor_ratio) {
  if (f.from_increments) return fmt::format("its last quarter's increments white, noise at {:.2g} of its largest RMS", f.level);
  if (f.white_noise) return fmt::format("its last quarter white, at {:.2g} of its largest RMS", f.level);
  if (f.resolution)
    return fmt::format("its last quarter repeating the few values of its written resolution, at {:.2g} of the largest RMS{}",
                       f.level, f.against_record ? " of the record it was cut from" : "");
  return f.against_record ? fmt::format("RMS below {:g} of the largest deviation of the record it was cut from", floor_ratio)
                          : fmt::format("RMS below {:g} of its largest", floor_ratio);
}

std::string describe(const Floor& f, double floor_ratio) {
  return (f.white_noise  ? "white-noise floor ("
          : f.resolution ? "resolution floor ("
                         : "noise/underflow floor (") +
         floor_evidence(f, floor_ratio) + ")";
}

/// How many times the series' largest deviation the record it was cut from deviates by: per channel
/// the record's largest deviation over the series' own (peak_deviations), the least over the
/// channels, at least 1 (1 when there is no record, or a channel is constant). A ratio of like to
/// like, so that the crest factor of a peak (an impulse's start) does not count as scale.
double record_to_series(const Series& s, const std::vector<double>& record_deviation) {
  if (record_deviation.size() != s.channel_count()) return 1.0;
  const std::vector<double> own = peak_deviations(s);
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < own.size(); ++c) {
    const double ratio = record_deviation[c] / own[c];
    if (!(own[c] > 0.0) || !std::isfinite(ratio)) return 1.0;
    least = std::min(least, ratio);
  }
  return std::max(least, 1.0);
}

/// Window RMS values that hold their level: the later half's median at least half the earlier
/// half's, at least two windows. Medians, so that the end of the decay into the level (the first
/// windows, up to 10x it) does not count; a decay that goes on falling over the windows fails.
bool holds_its_level(std::span<const double> rms) {
  if (rms.size() < 2) return false;
  const std::size_t half = rms.size() / 2;
  const double early = upper_median({rms.begin(), rms.begin() + static_cast<std::ptrdiff_t>(half)});
  const double late = upper_median({rms.end() - static_cast<std::ptrdiff_t>(half), rms.end()});
  return late >= 0.5 * early;
}

Floor detect_floor(const Series& s, double floor_ratio, const std::vector<double>& record_deviation) {
  const std::size_t n = s.size(), windows = 100, w = n / windows;
  if (w < 2 || floor_ratio <= 0.0) return {};
  // In place, no standardised copy; about the last quarter's mean (the level the series settles at).
  std::vector<double> rms = window_square_sums(s, w, windows, 75 * w);
  for (double& v : rms) v = std::sqrt(v / static_cast<double>(w));
  const double level = upper_median({rms.begin() + 75, rms.end()}), peak = *std::max_element(rms.begin(), rms.end());
  // A window cut late in a decay holds only its tail: the floor is judged against the scale of the
  // record it was cut from, as the whole record's analysis judges it.
  const double reference = peak * record_to_series(s, record_deviation);
  const bool underflow = level < floor_ratio * reference;
  Floor floor;
  double cut_level = 0.0;  // the floor starts where every later window stays at or below this
  if (level < kResolutionFloorShare * reference && quantised_tail(s, w)) {
    // Steps of the resolution come and go (a window of 40 samples holds none, one or a few): the
    // floor reaches up to the quarter's largest window, and starts where the windows stay within 10x
    // of that (the real isotropic run's rel:11:4:z: mostly 0 from ~10 s, its last windows 15x its
    // median, so 10x the median found no floor and the record read -0.89 1/s, not -1.18).
    cut_level = 10.0 * *std::max_element(rms.begin() + 75, rms.end());
    floor.resolution = true;
    floor.level = level / reference;
    floor.against_record = !(level < kResolutionFloorShare * peak);
  } else if (underflow) {
    cut_level = 10.0 * level;
    floor.level = level / reference;
    floor.against_record = !(level < floor_ratio * peak);
  } else if (level < kWhiteFloorShare * peak && white_and_level_tail(s, rms, w)) {
    cut_level = kWhiteFloorCut * level;
    floor.white_noise = true;
    floor.level = level / peak;
  } else if (const auto noise = increment_noise(s, w); noise && *noise < kWhiteFloorShare * peak) {
    // The noise holds only the end of the last quarter, or none of it yet (its samples not white):
    // the same cut, at kWhiteFloorCut x the noise's RMS from the increments.
    cut_level = kWhiteFloorCut * *noise;
    floor.white_noise = floor.from_increments = true;
    floor.level = *noise / peak;
  } else {
    return {};
  }
  std::size_t k = windows;
  while (k > 0 && rms[k - 1] <= cut_level) --k;
  // Below the record's scale only, a floor must hold its level: the residue of rounding and solver
  // tolerance does, while a decay that goes on falling is still the motion, however far down (the
  // real MBDyn run of the isotropic rotor at 200 rpm decays cleanly to 3e-10 of its start, and the
  // ad-hoc nonlinear-damper run from 15 s reads its -0.34 1/s over the whole window).
  if (floor.against_record && !holds_its_level({rms.begin() + static_cast<std::ptrdiff_t>(k), rms.end()})) return {};
  // A last window above that level ends no floor: a cut there would leave out only the samples
  // past the 100 windows (the iso_200rpm run's rel:11:4:z: "floor from sample 4000", 1 sample).
  if (k == windows) return {};
  // A white floor ends a decay of a motion; when the samples kept before it are white as well, the
  // record is noise throughout, only louder in places (rounding noise of a channel that carries no
  // motion, as the real LCO run's node:2:y: 1e-22 m, bursts of 30x): no floor, and the estimator's
  // own checks then say that the curve resolves no divergence.
  if (floor.white_noise && k * w >= kFewestToJudgeWhiteness && white_samples(s, 0, k * w)) return {};
  floor.index = k * w;
  floor.whole = k == 0;  // only against the record: the series' own largest window is > 10x its level
  return floor;
}

TransientResult detect_transient(const Series& series, const TransientOptions& options) {
  options.validate();
  validate_series(series);
  const Series s = standardized(series);
  const std::size_t n = s.size();
  TransientResult r;
  // The raw series: detect_floor scales it itself, and a shift by the mean would round a tail far
  // below the mean's last digit onto it (an early, false floor).
  if (const Floor f = detect_floor(series, options.floor_ratio); f.index > 0) {
    r.settled = false;
    r.floor_index = f.index;
    r.end_time = s.time(0);
    r.rule = "decays into the " + describe(f, options.floor_ratio) + " from sample " + std::to_string(f.index) +
             ": nothing cut at the start";
    return r;
  }
  // Window RMS about the last quarter's mean (the centre of the settled motion), the median window
  // RMS of the last quarter and its relative scatter there (largest deviation / median).
  struct Windows {
    std::size_t w = 0, count = 0, tail_from = 0;
    std::vector<double> rms;
    double ref = 0.0, scatter = 0.0;
  };
  auto measure = [&](std::size_t w) {
    Windows m;
    m.w = w;
    m.count = n / std::max<std::size_t>(w, 1);
    if (m.count < 8) return m;
    m.tail_from = m.count - m.count / 4;
    std::vector<double> mean_tail(s.channel_count(), 0.0);  // once per channel, not once per window
    for (std::size_t c = 0; c < s.channel_count(); ++c) {
      for (std::size_t i = m.tail_from * w; i < m.count * w; ++i) mean_tail[c] += s.channels[c][i];
      mean_tail[c] /= static_cast<double>((m.count - m.tail_from) * w);
    }
    m.rms.resize(m.count);
    for (std::size_t k = 0; k < m.count; ++k) {
      double acc = 0.0;
      for (std::size_t c = 0; c < s.channel_count(); ++c)
        for (std::size_t i = k * w; i < (k + 1) * w; ++i) {
          const double e = s.channels[c][i] - mean_tail[c];
          acc += e * e;
        }
      m.rms[k] = std::sqrt(acc / static_cast<double>(w));
    }
    const std::vector<double> tail(m.rms.begin() + static_cast<std::ptrdiff_t>(m.tail_from), m.rms.end());
    m.ref = upper_median(tail);
    double largest = 0.0;
    for (double v : tail) largest = std::max(largest, std::abs(v - m.ref));
    m.scatter = m.ref > 0.0 ? largest / m.ref : 0.0;
    return m;
  };
  Windows m = measure(options.window ? options.window : std::max<std::size_t>(2 * options.period, n / 100));
  // A motion with several frequencies (a hub driven by a blade's limit cycle) beats: its RMS over
  // two mean periods scatters more than a band can absorb. Longer windows average the beat out.
  if (options.window == 0 && options.band == 0.0)
    while (m.count >= 16 && 1.5 * m.scatter > options.band_max) {
      Windows longer = measure(2 * m.w);
      if (longer.count < 8) break;
      m = std::move(longer);
    }
  if (m.count < 8) {
    r.rule = "series shorter than 8 RMS windows of " + std::to_string(m.w) + " samples: nothing cut";
    r.end_time = s.time(0);
    return r;
  }
  const std::size_t w = m.w, windows = m.count, tail_from = m.tail_from;
  const std::vector<double>& rms = m.rms;
  const double ref = m.ref;
  // The band is 1.5 x the largest deviation of a last-quarter window, and at least 8 robust
  // standard deviations of the window RMS over the last quarter, up to band_max_irregular. The
  // largest deviation of the last quarter's few windows (7 for 10^4 samples) may be small by chance
  // while the motion is irregular, and then any excursion of a chaotic series cut it up to there
  // (test Transient.ChaosAlreadyOnItsAttractorIsNotCut: of 16 Lorenz x and 16 Roessler x series of
  // 10^4 samples already on the attractor, 6 and 3 lost 10-75 %; with the widening 3 and 0).
  // The deviation is estimated from second differences,
  // 1.4826 x median |rms_{k+1} - 2 rms_k + rms_{k-1}| / sqrt 6: a settling limit cycle's RMS trend
  // has no curvature to speak of, so its band stays 2 % (first differences widened it with the
  // trend, and 30-s runs of the rotor were then cut inside their overshoot; bench/speed_accuracy.sh's
  // "run 30 s" row keeps its error). 8 deviations, not 3-5: the median of ~5 second differences can
  // underestimate them by 2x, and Lorenz's window RMS are heavy-tailed.
  std::vector<double> dev;
  for (std::size_t k = tail_from + 1; k + 1 < windows; ++k) dev.push_back(std::abs(rms[k + 1] - 2.0 * rms[k] + rms[k - 1]));
  // Fewer than 3 second differences: no widening.
  const double robust_sd = dev.size() >= 3 && ref > 0.0 ? 1.4826 * upper_median(std::move(dev)) / std::sqrt(6.0) / ref : 0.0;
  // The last quarter drifts (decay or growth) when its first or last window leaves the band of the
  // last quarter itself; the widening applies to the search for the transient's end only.
  const double tail_band = options.band > 0.0 ? options.band : std::clamp(1.5 * m.scatter, options.band_min, options.band_max);
  const double band = options.band > 0.0 ? options.band : std::max(tail_band, std::min(8.0 * robust_sd, options.band_max_irregular));
  auto inside = [&](double v) { return std::abs(v - ref) <= band * ref; };
  auto inside_tail_band = [&](double v) { return std::abs(v - ref) <= tail_band * ref; };
  std::ostringstream rule;
  if (ref == 0.0 || !inside_tail_band(rms[tail_from]) || !inside_tail_band(rms[windows - 1])) {
    r.settled = false;
    rule << "RMS still drifts in the last quarter (decay or growth): no settled part, nothing cut";
    r.rule = rule.str();
    r.end_time = s.time(0);
    return r;
  }
  std::size_t k = windows;
  while (k > 0 && inside(rms[k - 1])) --k;
  r.end_index = k * w;
  r.end_time = s.time(r.end_index);
  rule << "moving RMS in windows of " << w << " samples settles within " << band * 100
       << " % of the last quarter's median from sample " << r.end_index;
  r.rule = rule.str();
  return r;
}

EnvelopeRates envelope_rates(const Series& s, std::size_t period) {
  const std::size_t w = 2 * std::max<std::size_t>(period, 1), windows = s.size() / w;
  const std::vector<double> sums = window_square_sums(s, w, windows, std::nullopt);
  std::vector<double> centre, log_rms;
  std::size_t end_from = 0;  // first collected window whose centre lies in the second half
  for (std::size_t k = 0; k < windows; ++k)
    if (sums[k] > 0.0) {  // no log 0
      centre.push_back((static_cast<double>(k) + 0.5) * static_cast<double>(w));
      log_rms.push_back(0.5 * std::log(sums[k] / static_cast<double>(w)));
      if (2.0 * centre.back() < static_cast<double>(s.size())) end_from = centre.size();
    }
  EnvelopeRates r;
  if (centre.size() >= 4) {
    const LineFit line = fit_line(centre.data(), log_rms.data(), centre.size());
    r.whole = line.slope, r.whole_stderr = line.slope_stderr;
  }
  if (centre.size() >= end_from + 4)
    r.end = fit_line(centre.data() + end_from, log_rms.data() + end_from, centre.size() - end_from).slope;
  return r;
}

double amplitude_ratio(const Series& s) {
  const std::size_t w = s.size() / 3;
  if (w == 0) return std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> sums = window_square_sums(s, w, 3, 0);
  return sums[0] > 0.0 ? std::sqrt(sums[2] / sums[0]) : std::numeric_limits<double>::quiet_NaN();
}

namespace {
/// Sum of squares about their own (weighted) mean of x[from .. from + whole) / peak and share x the
/// next sample: a window of whole + share samples.
double window_square_sum(const std::vector<double>& x, double peak, std::size_t from, std::size_t whole, double share) {
  const double width = static_cast<double>(whole) + share;
  double mean = share * x[from + whole] / peak;
  for (std::size_t i = from; i < from + whole; ++i) mean += x[i] / peak;
  mean /= width;
  const double last = x[from + whole] / peak - mean;
  double sum = share * last * last;
  for (std::size_t i = from; i < from + whole; ++i) sum += (x[i] / peak - mean) * (x[i] / peak - mean);
  return sum;
}
}  // namespace

double ends_amplitude_rate(const Series& s, double period_samples) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::size_t n = s.size();
  if (!(period_samples > 0.0) || !std::isfinite(period_samples) || n < 4) return nan;
  const double periods_in_third = std::floor(static_cast<double>(n) / 3.0 / period_samples);
  const double w = std::max(1.0, periods_in_third) * period_samples;  // samples, fractional
  if (w < 2.0 || 2.0 * w + 2.0 > static_cast<double>(n)) return nan;
  // The window's whole samples and the share of one more sample that completes its period (a
  // period between two samples: 628.3 at 628 would leave the RMS of a steady sine uneven by the
  // 0.3 sample's phase, ~2e-4 per period).
  const auto whole = static_cast<std::size_t>(w);
  const double share = w - static_cast<double>(whole);
  double first = 0.0, last = 0.0;
  for (const auto& x : s.channels) {
    const double peak = max_abs(x);
    if (!(peak > 0.0)) continue;
    first += window_square_sum(x, peak, 0, whole, share);
    last += window_square_sum(x, peak, n - whole - 1, whole, share);
  }
  if (!(first > 0.0) || !(last > 0.0)) return nan;  // no log 0
  return 0.5 * std::log(last / first) / (static_cast<double>(n - 1) - w);  // between the windows' centres
}

ScaledRepeat scaled_repeat(const Series& s, double period_samples) {
  ScaledRepeat out;
  const std::size_t n = s.size();
  if (!(period_samples > 0.0) || !(2.0 * period_samples <= static_cast<double>(n))) return out;
  out.period = period_samples;
  const auto lag = static_cast<std::size_t>(period_samples);
  const double share = period_samples - static_cast<double>(lag);  // of the sample after x(t + lag)
  const std::size_t count = n - lag - 1;                            // t with t + lag + 1 < n
  // x(t + P) = a x(t) + b per channel: the intercept b = c (1 - a) carries an offset c the mode
  // oscillates about (a decaying mode's mean over the record is not c).
  double uu = 0.0, uv = 0.0, vv = 0.0;
  for (const auto& x : s.channels) {
    const double peak = max_abs(x);
    if (!(peak > 0.0)) continue;
    auto later = [&](std::size_t t) { return ((1.0 - share) * x[t + lag] + share * x[t + lag + 1]) / peak; };
    double mean_u = 0.0, mean_v = 0.0;
    for (std::size_t t = 0; t < count; ++t) mean_u += x[t] / peak, mean_v += later(t);
    mean_u /= static_cast<double>(count), mean_v /= static_cast<double>(count);
    for (std::size_t t = 0; t < count; ++t) {
      const double u = x[t] / peak - mean_u, v = later(t) - mean_v;
      uu += u * u, uv += u * v, vv += v * v;
    }
  }
  if (!(uu > 0.0) || !(vv > 0.0)) return out;
  out.scale = uv / uu;
  // sum (v - a u)^2 = vv - 2 a uv + a^2 uu = vv - uv^2 / uu at the least-squares a
  out.difference = std::sqrt(std::max(0.0, vv - uv * uv / uu) / vv);
  return out;
}

Drift linear_drift(const Series& s) {
  Drift d;
  std::vector<double> scaled;
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const auto& x = s.channels[c];
    if (x.size() < 3) continue;
    const double peak = max_abs(x);
    if (!(peak > 0.0)) continue;
    scaled.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) scaled[i] = x[i] / peak;
    const std::size_t last = scaled.size() - 1, half = last / 2;
    const double r2 = fit_line(scaled.data(), std::size_t{0}, last).r2;
    if (!std::isfinite(r2)) continue;
    const double first = fit_line(scaled.data(), std::size_t{0}, half).slope, second = fit_line(scaled.data(), half, last).slope;
    if (first * second <= 0.0 || std::abs(second) < kSettlingSlope * std::abs(first))
      d.settling_share = std::max(d.settling_share, r2);
    else if (r2 > d.share)
      d.share = r2, d.channel = c;
  }
  return d;
}

WhiteSteps white_steps(const Series& s) {
  WhiteSteps out;
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const auto& x = s.channels[c];
    const std::size_t n = x.size() < 2 ? 0 : x.size() - 1;  // steps
    const std::size_t lags = std::min(kWhiteStepLags, n / 10);
    if (lags < 2) continue;
    // Each channel in units of its peak |x| first: squares of 1e300 would overflow. The steps are
    // differences of those (a 1e-300 walk has steps of ~1e-302 of its peak: no underflow).
    const double peak = max_abs(x);
    if (!(peak > 0.0)) continue;
    std::vector<double> steps(n), level(x.size());
    for (std::size_t t = 0; t < x.size(); ++t) level[t] = x[t] / peak;
    for (std::size_t t = 0; t < n; ++t) steps[t] = level[t + 1] - level[t];
    const double mean_step = centre_in_place(steps);
    centre_in_place(level);
    const double step_sum = lagged_product_sum(steps, 0), level_sum = lagged_product_sum(level, 0);
    if (!(step_sum > 0.0)) continue;  // a constant or a straight line: no noise in its steps
    const double step_variance = step_sum / static_cast<double>(n);
    if (mean_step * mean_step >= step_variance) continue;  // a drift with rounding, not a walk
    const double ratio = (level_sum / static_cast<double>(x.size())) / step_variance;
    if (!(ratio >= kWalkVarianceRatio)) continue;
    const double dn = static_cast<double>(n);
    CompensatedSum q;
    for (std::size_t k = 1; k <= lags; ++k) {
      const double rho = lagged_product_sum(steps, k) / step_sum;
      q.add(rho * rho / (dn - static_cast<double>(k)));
    }
    const double statistic = dn * (dn + 2.0) * q.value();
    const double critical =
        boost::math::quantile(boost::math::chi_squared_distribution<double>(static_cast<double>(lags)), 0.999);
    if (!out.tested || statistic / critical < out.statistic / out.critical)
      out = {statistic < critical, true, c, statistic, critical, lags, ratio};
  }
  return out;
}

WrappedAngle wrapped_angle(const Series& s) {
  WrappedAngle w;
  std::vector<double> steps;
  for (std::size_t c = 0; c < s.channels.size() && w.count == 0; ++c) {
    const auto& x = s.channels[c];
    if (x.size() < 3) continue;
    const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
    const double range = *hi - *lo;
    steps.resize(x.size() - 1);
    for (std::size_t i = 1; i < x.size(); ++i) steps[i - 1] = std::abs(x[i] - x[i - 1]);
    auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
    std::nth_element(steps.begin(), mid, steps.end());
    const double median = *mid;
    for (std::size_t i = 1; i < x.size(); ++i) {
      const double jump = x[i] - x[i - 1], size = std::abs(jump);
      if (size < 0.5 * range || median >= 0.05 * size) continue;
      const bool deg = std::abs(size - 360.0) <= 36.0, rad = std::abs(size - 2.0 * std::numbers::pi) <= 0.2 * std::numbers::pi;
      if (!deg && !rad) continue;
      if (w.count++ == 0) w.channel = c, w.sample = i, w.jump = jump, w.degrees = deg;
    }
  }
  return w;
}

Series skip_transient(const Series& series, TransientResult* result) {
  TransientOptions o;
  o.period = estimate_mean_period(series, {}).mean_period;
  const TransientResult r = detect_transient(series, o);
  if (result) *result = r;
  return time_window(series, r.end_time, series.time(series.size() - 1));
}

}  // namespace mlce
