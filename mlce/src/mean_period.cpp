#include "mlce/mean_period.hpp"

#include <fftw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>

#include "mlce/numerics.hpp"

namespace mlce {
namespace {

std::mutex& planner_mutex() {  // FFTW's planner is not thread-safe; execution is.
  static std::mutex m;
  return m;
}

struct ChannelSpectrum {
  double mean_frequency = 0.0;  ///< power-weighted mean, cycles per sample
  double fast_share = 0.0;      ///< share of the power above a quarter of the sampling rate
};

/// Power-weighted mean frequency of one channel, cycles per sample, and the share of its power
/// above a quarter of the sampling rate.
ChannelSpectrum channel_spectrum(const std::vector<double>& x, SpectralWindow window) {
  const std::size_t n = x.size();
  CompensatedSum mean_sum;
  for (double v : x) mean_sum.add(v);
  const double mean = mean_sum.value() / static_cast<double>(n);

  const std::size_t nc = n / 2 + 1;
  std::unique_ptr<double, decltype(&fftw_free)> in(fftw_alloc_real(n), &fftw_free);
  std::unique_ptr<fftw_complex, decltype(&fftw_free)> out(fftw_alloc_complex(nc), &fftw_free);
  fftw_plan plan;
  {
    std::lock_guard lock(planner_mutex());
    plan = fftw_plan_dft_r2c_1d(static_cast<int>(n), in.get(), out.get(), FFTW_ESTIMATE);
  }
  for (std::size_t i = 0; i < n; ++i) {
    double w = 1.0;
    if (window == SpectralWindow::hann)
      w = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n));
    in.get()[i] = w * (x[i] - mean);
  }
  fftw_execute(plan);
  {
    std::lock_guard lock(planner_mutex());
    fftw_destroy_plan(plan);
  }
  // One-sided periodogram P_k, k = 1..n/2 (DC excluded); the scale factor cancels in the ratio.
  CompensatedSum power, moment, fast;
  for (std::size_t k = 1; k < nc; ++k) {
    const double re = out.get()[k][0], im = out.get()[k][1];
    const double p = re * re + im * im;
    power.add(p);
    moment.add(p * static_cast<double>(k) / static_cast<double>(n));
    if (4 * k > n) fast.add(p);  // f_k = k / n > 1/4 per sample
  }
  if (!(power.value() > 0.0)) return {};
  return {moment.value() / power.value(), fast.value() / power.value()};
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
  }
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

}  // namespace mlce
