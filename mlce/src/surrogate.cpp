#include "mlce/surrogate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

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

std::vector<double> iaaft_surrogate(const std::vector<double>& x, std::uint64_t seed, std::size_t iterations) {
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
    std::iota(order.begin(), order.end(), std::size_t{0});
    const double* y = real.get();
    std::sort(order.begin(), order.end(), [y](std::size_t a, std::size_t b) { return y[a] < y[b]; });
    for (std::size_t i = 0; i < n; ++i) s[order[i]] = sorted[i];  // the series' values in that rank order
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
  ro.horizon = std::max(setup.horizon, setup.last);
  ro.max_references = setup.max_references;
  out.series_slope = curve_slope(series, ro, out.first, out.last);
  Series surrogate = series;
  CompensatedSum sum, square;
  for (std::size_t k = 0; k < options.count; ++k) {
    if (progress) progress("surrogates", static_cast<double>(k) / static_cast<double>(options.count));
    surrogate.channels[0] = iaaft_surrogate(series.channels[0], options.seed + k, options.iterations);
    const double slope = curve_slope(surrogate, ro, out.first, out.last);
    out.surrogate_slopes.push_back(slope);
    sum.add(slope);
    if (slope >= out.series_slope) ++out.at_least;
  }
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
