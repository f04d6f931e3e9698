#include "mlce/mean_period.hpp"

#include <fftw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>

#include "fftw_plan.hpp"
#include "mlce/numerics.hpp"

namespace mlce {
namespace {

using detail::backward_plan;
using detail::forward_plan;
using detail::Plan;

struct ChannelSpectrum {
  double mean_frequency = 0.0;  ///< power-weighted mean, cycles per sample
  double fast_share = 0.0;      ///< share of the power above a quarter of the sampling rate
  double band_edge = 0.0;       ///< the lowest frequency below which `band_share` of the power lies, cycles per sample
  double taper_mean_share = 0.0;  ///< MeanPeriodResult::taper_mean_share
};

/// The taper-weighted mean of x - mean, r, and the share of the tapered series' energy that the bump
/// taper x r holds (MeanPeriodResult::taper_mean_share).
struct TaperMean {
  double offset = 0.0, share = 0.0;
};
TaperMean taper_mean(const std::vector<double>& x, double mean, const std::vector<double>& taper) {
  CompensatedSum weight, weighted, bump_energy, energy;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double d = x[i] - mean;
    weight.add(taper[i]);
    weighted.add(taper[i] * d);
    bump_energy.add(taper[i] * taper[i]);
    energy.add(taper[i] * taper[i] * d * d);
  }
  if (!(weight.value() > 0.0 && energy.value() > 0.0)) return {};
  const double r = weighted.value() / weight.value();
  return {r, r * r * bump_energy.value() / energy.value()};
}

/// Power-weighted mean frequency of one channel, cycles per sample, and the share of its power
/// above a quarter of the sampling rate.
ChannelSpectrum channel_spectrum(const std::vector<double>& x, SpectralWindow window, double band_share = 1.0) {
  const std::size_t n = x.size();
  CompensatedSum mean_sum;
  for (double v : x) mean_sum.add(v);
  const double mean = mean_sum.value() / static_cast<double>(n);

  const std::size_t nc = n / 2 + 1;
  std::unique_ptr<double, decltype(&fftw_free)> in(fftw_alloc_real(n), &fftw_free);
  std::unique_ptr<fftw_complex, decltype(&fftw_free)> out(fftw_alloc_complex(nc), &fftw_free);
  const Plan plan = forward_plan(n, in.get(), out.get());
  std::vector<double> taper(n, 1.0);
  if (window == SpectralWindow::hann)
    for (std::size_t i = 0; i < n; ++i)
      taper[i] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n));
  // The plain mean, unless beneath the taper it would be a bump holding the lowest bins (kTaperMeanShare).
  const TaperMean bump = window == SpectralWindow::hann ? taper_mean(x, mean, taper) : TaperMean{};
  const double level = bump.share > kTaperMeanShare ? mean + bump.offset : mean;
  for (std::size_t i = 0; i < n; ++i) in.get()[i] = taper[i] * (x[i] - level);
  plan.execute();
  // One-sided periodogram P_k, k = 1..n/2 (DC excluded); the scale factor cancels in the ratio.
  CompensatedSum power, moment, fast;
  std::vector<double> periodogram(nc, 0.0);
  for (std::size_t k = 1; k < nc; ++k) {
    const double re = out.get()[k][0], im = out.get()[k][1];
    const double p = re * re + im * im;
    periodogram[k] = p;
    power.add(p);
    moment.add(p * static_cast<double>(k) / static_cast<double>(n));
    if (4 * k > n) fast.add(p);  // f_k = k / n > 1/4 per sample
  }
  if (!(power.value() > 0.0)) return {};
  ChannelSpectrum c{moment.value() / power.value(), fast.value() / power.value(), 0.5, bump.share};
  if (band_share >= 1.0 || nc < 8) return c;
  // The band edge of the power above a white floor: white noise folds onto itself and changes nothing,
  // a signal's harmonics fold onto other frequencies. A white periodogram's bins are exponentially
  // distributed about their mean (the median / ln 2 of the upper half of the band, where a sampled flow's
  // signal has died out): above 10 x that mean lies one bin in e^10 of the noise.
  const double floor_mean =
      median(std::vector<double>(periodogram.begin() + static_cast<std::ptrdiff_t>(nc / 2), periodogram.end())) /
      std::numbers::ln2;
  const double threshold = 10.0 * floor_mean;
  CompensatedSum excess;
  for (std::size_t k = 1; k < nc; ++k) excess.add(std::max(0.0, periodogram[k] - threshold));
  CompensatedSum below;
  for (std::size_t k = 1; k < nc; ++k) {
    below.add(std::max(0.0, periodogram[k] - threshold));
    if (below.value() >= band_share * excess.value()) {
      c.band_edge = static_cast<double>(k) / static_cast<double>(n);
      break;
    }
  }
  return c;
}

}  // namespace

void MeanPeriodOptions::validate() const {
  if (!(max_fraction > 0.0 && max_fraction <= 1.0))
    throw OptionError("mean_period.max_fraction = " + fmt::format("{:g}", max_fraction) + ": expected 0 < value <= 1");
  if (!(map_fast_share > 0.0 && map_fast_share <= 1.0))
    throw OptionError("mean_period.map_fast_share = " + fmt::format("{:g}", map_fast_share) + ": expected 0 < value <= 1");
}

MeanPeriodResult estimate_mean_period(const Series& series, const MeanPeriodOptions& options) {
  options.validate();
  validate_series(series);
  const std::size_t n = series.size();
  if (n < 4) throw InputError("mean frequency needs at least 4 samples, the series has " + std::to_string(n));
  MeanPeriodResult r;
  // The peak magnitude is divided out so that 1e300-amplitude data cannot overflow |X|^2.
  const Series s = standardized(series);
  double f_max = 0.0;
  for (const auto& x : s.channels) {
    const ChannelSpectrum c = channel_spectrum(x, options.window);
    r.channel_frequency.push_back(c.mean_frequency / series.dt);
    f_max = std::max(f_max, c.mean_frequency);
    r.fast_share = std::max(r.fast_share, c.fast_share);
    r.taper_mean_share = std::max(r.taper_mean_share, c.taper_mean_share);
  }
  r.taper_weighted_mean = r.taper_mean_share > kTaperMeanShare;
  r.mean_frequency_per_sample = f_max;
  r.mean_frequency = f_max / series.dt;
  // eq. 19: T = ceil(fs / max(meanfreq)), in samples.
  const double cap = std::max(1.0, std::floor(options.max_fraction * static_cast<double>(n)));
  double period = f_max > 0.0 ? std::ceil(1.0 / f_max - 1e-9) : cap;
  if (period > cap) {
    r.clamped = true;
    r.warnings.push_back("mean period " + std::to_string(static_cast<long long>(period)) +
                         " samples clamped to " + std::to_string(static_cast<long long>(cap)) + " (" +
                         fmt::format("{:g}", options.max_fraction) + " of the series): the series spans few periods");
    period = cap;
  }
  r.mean_period = static_cast<std::size_t>(std::max(1.0, period));
  r.map = r.mean_period < kMinFlowPeriod || r.fast_share >= options.map_fast_share;
  return r;
}

double band_edge_frequency(const Series& series, double share) {
  if (!(share > 0.0 && share <= 1.0)) throw OptionError(fmt::format("band edge share = {:g}: expected 0 < value <= 1", share));
  validate_series(series);
  if (series.size() < 4) throw InputError("a spectrum needs at least 4 samples, the series has " + std::to_string(series.size()));
  const Series s = standardized(series);
  double edge = 0.0;
  for (const auto& x : s.channels) edge = std::max(edge, channel_spectrum(x, SpectralWindow::hann, share).band_edge);
  return edge;
}

namespace {
/// end_repeat's D(L) and period over samples [from, from + q) of each channel, lags 1 .. max_lag
/// (end_repeat states the rule; whole_record_repeat applies it to a whole record).
EndRepeat repeat_over(const Series& series, std::size_t from, std::size_t q, std::size_t max_lag) {
  EndRepeat out;
  // Zero-padded to 2q: the circular correlation of the padded segment is the linear one.
  const std::size_t size = 2 * q, nc = size / 2 + 1;
  std::unique_ptr<double, decltype(&fftw_free)> buffer(fftw_alloc_real(size), &fftw_free);
  std::unique_ptr<fftw_complex, decltype(&fftw_free)> spectrum(fftw_alloc_complex(nc), &fftw_free);
  const Plan forward = forward_plan(size, buffer.get(), spectrum.get());
  const Plan backward = backward_plan(size, spectrum.get(), buffer.get());
  std::vector<double> d(max_lag + 1, 0.0), segment(q), prefix(q + 1);
  std::size_t channels = 0;
  for (const auto& x : series.channels) {
    // Over the peak first (no square of 1e200 overflows), then about the segment's mean.
    const std::span<const double> part(x.data() + from, q);
    const double peak = max_abs(part);
    if (!(peak > 0.0)) continue;
    CompensatedSum mean_sum;
    for (double v : part) mean_sum.add(v / peak);
    const double mean = mean_sum.value() / static_cast<double>(q);
    CompensatedSum squares;
    prefix[0] = 0.0;
    for (std::size_t t = 0; t < q; ++t) {
      segment[t] = part[t] / peak - mean;
      squares.add(segment[t] * segment[t]);
      prefix[t + 1] = squares.value();
    }
    const double variance = squares.value() / static_cast<double>(q);
    if (!(variance > 0.0)) continue;
    std::copy(segment.begin(), segment.end(), buffer.get());
    std::fill(buffer.get() + q, buffer.get() + size, 0.0);
    forward.execute();
    for (std::size_t k = 0; k < nc; ++k) {
      const double re = spectrum.get()[k][0], im = spectrum.get()[k][1];
      spectrum.get()[k][0] = re * re + im * im, spectrum.get()[k][1] = 0.0;
    }
    backward.execute();  // buffer[L] = size x sum over t of s[t] s[t + L]
    for (std::size_t lag = 1; lag <= max_lag; ++lag) {
      const double cross = buffer.get()[lag] / static_cast<double>(size);
      const double head = prefix[q - lag], rest = prefix[q] - prefix[lag];  // s[0 .. q-L), s[L .. q)
      d[lag] += std::max(0.0, head + rest - 2.0 * cross) / static_cast<double>(q - lag) / variance;
    }
    ++channels;
  }
  if (channels == 0) return out;
  for (double& v : d) v /= static_cast<double>(channels);
  std::size_t first = 1;
  while (first <= max_lag && d[first] < 0.5) ++first;
  // D's local minima beyond its first rise, each refined by the parabola through its neighbours (a
  // period between two samples). A multiple of the period can lie closer to a whole lag than the
  // period does (37.3 samples: 373 repeats exactly), so the first minimum within 1.25 x the least
  // plus 1e-4 is the period (a difference within 12 % of the least, or 0.01 in quadrature: the
  // parabola's residual at 37.3 samples, 0.007, and the scatter of D from lag to lag on a noisy cycle).
  std::vector<std::pair<double, double>> minima;  // (lag, D there)
  for (std::size_t lag = std::max<std::size_t>(first, 2); lag < max_lag; ++lag) {
    if (d[lag] > d[lag - 1] || d[lag] > d[lag + 1]) continue;
    const double a = d[lag - 1], b = d[lag], c = d[lag + 1], curvature = a - 2.0 * b + c;
    const double shift = curvature > 0.0 ? 0.5 * (a - c) / curvature : 0.0;
    minima.emplace_back(static_cast<double>(lag) + shift, b - 0.25 * (a - c) * shift);
  }
  if (minima.empty()) return out;  // none inside: the period, if any, lies beyond the lags compared
  double least = minima.front().second;
  for (const auto& m : minima) least = std::min(least, m.second);
  const auto period = std::find_if(minima.begin(), minima.end(), [least](const auto& m) { return m.second <= 1.25 * least + 1e-4; });
  out.period = period->first;
  least = period->second;
  out.difference = std::sqrt(std::max(0.0, least));
  return out;
}
}  // namespace

EndRepeat end_repeat(const Series& series) {
  const std::size_t n = series.size();
  // Lags up to a third of the segment: the stretch compared, from t to t + L, then spans at least two
  // periods (a weakly chaotic orbit can shadow a periodic one for one period: Thomas' flow, 2 x 10^4
  // samples from (0.2, 0, 0), repeated itself after 3174 samples to 1.2 % over the 3493 that a lag
  // of up to half the segment compared, scratch).
  const std::size_t q = std::min(n / 3, kEndRepeatMaxSamples);
  if (q < 16) return {};
  return repeat_over(series, n - q, q, q / 3);
}

EndRepeat whole_record_repeat(const Series& series) {
  const std::size_t q = std::min(series.size(), kEndRepeatMaxSamples);
  if (q < 16) return {};
  return repeat_over(series, 0, q, q / 2);
}

}  // namespace mlce
