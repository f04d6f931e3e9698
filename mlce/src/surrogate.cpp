#include "mlce/surrogate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <utility>

#include <omp.h>

#include "fftw_plan.hpp"
#include "mlce/numerics.hpp"
#include "mlce/rosenstein.hpp"

namespace mlce {

void SurrogateOptions::validate() const {
  if (count < 1) throw OptionError("surrogates.count = 0: expected >= 1");
  if (!(min_sigmas >= 0.0)) throw OptionError(fmt::format("surrogates.min_sigmas = {:g}: expected >= 0", min_sigmas));
  if (iterations < 1) throw OptionError("surrogates.iterations = 0: expected >= 1");
  if (!(significance > 0.0 && significance < 1.0))
    throw OptionError(fmt::format("surrogates.significance = {:g}: expected 0 < value < 1", significance));
}

std::string segment_words(const SurrogateTest& t) {
  return t.samples < t.of_samples ? fmt::format("first {} of {} samples", t.samples, t.of_samples) : std::string();
}

std::vector<double> iaaft_surrogate(const std::vector<double>& x, std::uint64_t seed, std::size_t iterations,
                                    std::size_t* passes) {
  const std::size_t n = x.size();
  if (n < 4) throw InputError("a surrogate needs at least 4 samples, the series has " + std::to_string(n));
  std::vector<double> sorted(x);
  std::sort(sorted.begin(), sorted.end());
  if (sorted.front() == sorted.back()) throw InputError("a surrogate of a constant series is the series itself");
  // Scaled by the largest |x|: squares of 1e200 would overflow, of 1e-200 underflow.
  const double scale = std::max(std::abs(sorted.front()), std::abs(sorted.back()));
  const std::size_t nc = n / 2 + 1;
  std::unique_ptr<double, decltype(&fftw_free)> real(fftw_alloc_real(n), &fftw_free);
  std::unique_ptr<fftw_complex, decltype(&fftw_free)> spectrum(fftw_alloc_complex(nc), &fftw_free);
  const detail::Plan forward = detail::forward_plan(n, real.get(), spectrum.get());
  const detail::Plan backward = detail::backward_plan(n, spectrum.get(), real.get());
  for (std::size_t i = 0; i < n; ++i) real.get()[i] = x[i] / scale;
  forward.execute();
  std::vector<double> amplitude(nc);
  for (std::size_t k = 0; k < nc; ++k) amplitude[k] = std::hypot(spectrum.get()[k][0], spectrum.get()[k][1]);

  std::vector<double> s(x);  // shuffled (Fisher-Yates): the start
  std::uint64_t state = seed;
  for (std::size_t i = n - 1; i > 0; --i) std::swap(s[i], s[static_cast<std::size_t>(uniform01(state) * static_cast<double>(i + 1)) % (i + 1)]);
  // The rank order sorts (value, index) pairs, contiguous in memory: an index sort that looks its
  // values up through a comparator took half the test's time (perf, Lorenz x at 10^4 samples).
  std::vector<std::pair<double, std::size_t>> ranked(n);
  std::vector<std::size_t> order(n), previous;
  for (std::size_t pass = 0; pass < iterations; ++pass) {
    for (std::size_t i = 0; i < n; ++i) real.get()[i] = s[i] / scale;
    forward.execute();
    for (std::size_t k = 0; k < nc; ++k) {  // the series' amplitudes, the surrogate's phases
      double& re = spectrum.get()[k][0];
      double& im = spectrum.get()[k][1];
      const double a = std::hypot(re, im);
      if (a > 0.0) {
        re *= amplitude[k] / a, im *= amplitude[k] / a;
      } else {
        re = amplitude[k], im = 0.0;
      }
    }
    backward.execute();  // n times the inverse; only the order of its values is used
    const double* y = real.get();
    for (std::size_t i = 0; i < n; ++i) ranked[i] = {y[i], i};
    std::sort(ranked.begin(), ranked.end());  // ties by index, as a stable order would
    for (std::size_t i = 0; i < n; ++i) order[i] = ranked[i].second;
    for (std::size_t i = 0; i < n; ++i) s[order[i]] = sorted[i];  // the series' values in that rank order
    if (passes) *passes = pass + 1;
    if (order == previous) break;  // converged: the ranks no longer change
    previous = order;
  }
  return s;
}

namespace {

/// The plain curve's slope per sample over steps first..last, with the estimate's embedding.
double curve_slope(const Series& series, const RosensteinOptions& ro, std::size_t first, std::size_t last) {
  const DivergenceCurve curve = divergence_curve(series, ro);
  return fit_line(curve.mean_log_distance.data(), first, last).slope;
}

}  // namespace

SurrogateTest surrogate_test(const Series& series, const SurrogateSetup& setup, const SurrogateOptions& options,
                             const ProgressCallback& progress) {
  options.validate();
  validate_series(series);
  if (series.channels.size() != 1)
    throw OptionError("the surrogate test takes one channel; the series has " + std::to_string(series.channels.size()));
  if (setup.last <= setup.first) throw OptionError("the surrogate test needs a fit region of two steps or more");
  SurrogateTest out;
  out.first = setup.first, out.last = setup.last;
  RosensteinOptions ro;
  ro.dim = setup.dim, ro.delay = setup.delay, ro.theiler = setup.theiler;
  ro.horizon = setup.last;  // the slope reads steps first..last only
  ro.max_references = setup.max_references;
  ro.align_phase = setup.align_phase;
  const std::size_t n = series.channels[0].size();
  const std::size_t span = (setup.dim - 1) * setup.delay + setup.last + 1;
  out.of_samples = n;
  out.samples = options.max_samples == 0 ? n : std::min(n, std::max(options.max_samples, 8 * span));
  const std::vector<double>& x = series.channels[0];
  const auto holds_still = [&x](std::size_t count) {  // the first `count` values all equal
    const auto end = x.begin() + static_cast<std::ptrdiff_t>(count);
    return std::adjacent_find(x.begin(), end, std::not_equal_to<>()) == end;
  };
  if (holds_still(out.samples)) out.samples = n;  // a still leading segment has no surrogates: the whole series
  if (n < 4 || holds_still(n)) throw InputError("the surrogate test needs a series of at least 4 samples, not all equal");
  Series segment = series;
  segment.channels[0].resize(out.samples);
  out.series_slope = curve_slope(segment, ro, out.first, out.last);
  // The surrogates of a batch are made side by side, one a thread (each pass of IAAFT is serial),
  // and their curves then one after the other (each curve's search runs on every thread). A batch
  // holds one surrogate a thread, so memory stays a few series at any length.
  const auto threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  Series surrogate = segment;
  CompensatedSum sum, square, passes;
  for (std::size_t k0 = 0; k0 < options.count; k0 += threads) {
    if (progress) progress("surrogates", static_cast<double>(k0) / static_cast<double>(options.count));
    const std::size_t batch = std::min(threads, options.count - k0);
    std::vector<std::vector<double>> made(batch);
    std::vector<std::size_t> made_passes(batch, 0);
#pragma omp parallel for schedule(static, 1) num_threads(static_cast<int>(batch))
    for (std::size_t i = 0; i < batch; ++i)  // cannot throw: the segment has >= 4 values, not all equal
      made[i] = iaaft_surrogate(segment.channels[0], options.seed + k0 + i, options.iterations, &made_passes[i]);
    for (std::size_t i = 0; i < batch; ++i) {
      surrogate.channels[0] = std::move(made[i]);
      const double slope = curve_slope(surrogate, ro, out.first, out.last);
      out.surrogate_slopes.push_back(slope);
      sum.add(slope);
      passes.add(static_cast<double>(made_passes[i]));
      if (slope >= out.series_slope) ++out.at_least;
    }
  }
  out.mean_passes = passes.value() / static_cast<double>(options.count);
  if (progress) progress("surrogates", 1.0);
  const double k = static_cast<double>(options.count);
  const double mean = sum.value() / k;
  for (const double s : out.surrogate_slopes) square.add((s - mean) * (s - mean));
  const double deviation = options.count > 1 ? std::sqrt(square.value() / (k - 1.0)) : 0.0;
  out.sigmas = deviation > 0.0                 ? (out.series_slope - mean) / deviation
               : out.series_slope > mean        ? std::numeric_limits<double>::infinity()
               : out.series_slope < mean        ? -std::numeric_limits<double>::infinity()
                                                : 0.0;
  out.p_value = static_cast<double>(1 + out.at_least) / (1.0 + k);
  out.significance = options.significance, out.min_sigmas = options.min_sigmas;
  out.distinguished = out.p_value <= options.significance && out.sigmas >= options.min_sigmas;
  const auto needed = static_cast<std::size_t>(std::ceil(1.0 / options.significance - 1.0 - 1e-9));
  if (options.count < needed)
    out.warnings.push_back(fmt::format("{} surrogates cannot reach p <= {:g}: at least {} needed", options.count,
                                       options.significance, needed));
  return out;
}

}  // namespace mlce
