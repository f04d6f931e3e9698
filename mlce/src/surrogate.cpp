#include "mlce/surrogate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <utility>

#include <boost/sort/pdqsort/pdqsort.hpp>
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
  if (t.first_sample > 0)
    return fmt::format("samples {}..{} of {}", t.first_sample, t.first_sample + t.samples - 1, t.of_samples);
  return t.samples < t.of_samples ? fmt::format("first {} of {} samples", t.samples, t.of_samples) : std::string();
}

EndMatch match_ends(const std::vector<std::vector<double>>& x, std::size_t length, std::size_t min_length) {
  const std::size_t n = x.empty() ? 0 : x[0].size();
  if (length > n) throw InputError(fmt::format("match_ends: a segment of {} samples in a series of {}", length, n));
  EndMatch best{0, length, std::numeric_limits<double>::infinity()};
  if (min_length >= length || length < 2) return best;  // no choice
  // Each channel's jump in units of its rms step over the leading `length` samples.
  std::vector<double> step(x.size());
  for (std::size_t c = 0; c < x.size(); ++c) {
    CompensatedSum squares;
    for (std::size_t i = 1; i < length; ++i) squares.add((x[c][i] - x[c][i - 1]) * (x[c][i] - x[c][i - 1]));
    step[c] = squares.value() / static_cast<double>(length - 1);
  }
  const std::size_t starts = std::min<std::size_t>(kEndMatchStarts, std::max<std::size_t>(1, length / 10));
  const std::size_t shortest = std::max(min_length, length - std::min(length / 5, kEndMatchLengths));
  for (std::size_t start = 0; start < starts; ++start)
    for (std::size_t l = shortest; l <= length && start + l < n; ++l) {
      double jump = 0.0;  // x[start + l] is where the record goes on; the wrap goes to x[start] instead
      for (std::size_t c = 0; c < x.size(); ++c) {
        const double d = x[c][start + l] - x[c][start];
        jump += step[c] > 0.0 ? d * d / step[c] : (d != 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
      }
      if (jump < best.jump) best = {start, l, jump};
    }
  return best;
}

std::vector<double> iaaft_surrogate(const std::vector<double>& x, std::uint64_t seed, std::size_t iterations,
                                    std::size_t* passes) {
  return std::move(iaaft_surrogates({x}, seed, iterations, passes).front());
}

namespace {
/// The shuffle's seed of channel c of a surrogate made from `seed`: channel 0 takes the seed itself
/// (so that a one-channel surrogate is the univariate one), the others a splitmix64 hash of (seed, c),
/// never seed + c: surrogate k's channel 1 would then repeat surrogate k + 1's channel 0.
std::uint64_t channel_seed(std::uint64_t seed, std::size_t c) {
  if (c == 0) return seed;
  std::uint64_t state = seed ^ (0xD1B54A32D192ED03ull * static_cast<std::uint64_t>(c));
  return splitmix64(state);
}
}  // namespace

std::vector<std::vector<double>> iaaft_surrogates(const std::vector<std::vector<double>>& x, std::uint64_t seed,
                                                  std::size_t iterations, std::size_t* passes) {
  const std::size_t channels = x.size();
  if (channels == 0) throw InputError("a surrogate needs at least one channel");
  const std::size_t n = x[0].size();
  for (std::size_t c = 1; c < channels; ++c)
    if (x[c].size() != n)
      throw InputError(fmt::format("a surrogate's channels have one length: channel {} has {} samples, channel 0 {}", c,
                                   x[c].size(), n));
  if (n < 4) throw InputError("a surrogate needs at least 4 samples, the series has " + std::to_string(n));
  std::vector<std::vector<double>> sorted(x);
  std::vector<double> scale(channels);
  for (std::size_t c = 0; c < channels; ++c) {
    std::sort(sorted[c].begin(), sorted[c].end());
    if (sorted[c].front() == sorted[c].back())
      throw InputError(channels > 1 ? fmt::format("a surrogate of a constant channel is the channel itself: channel {} is constant", c)
                                    : std::string("a surrogate of a constant series is the series itself"));
    // Scaled by the largest |x|: squares of 1e200 would overflow, of 1e-200 underflow.
    scale[c] = std::max(std::abs(sorted[c].front()), std::abs(sorted[c].back()));
  }
  const std::size_t nc = n / 2 + 1;
  std::unique_ptr<double, decltype(&fftw_free)> real(fftw_alloc_real(n), &fftw_free);
  std::unique_ptr<fftw_complex, decltype(&fftw_free)> spectrum(fftw_alloc_complex(nc), &fftw_free);
  const detail::Plan forward = detail::forward_plan(n, real.get(), spectrum.get());
  const detail::Plan backward = detail::backward_plan(n, spectrum.get(), real.get());
  const auto bin = [&spectrum](std::size_t k) { return std::complex<double>(spectrum.get()[k][0], spectrum.get()[k][1]); };
  const auto set_bin = [&spectrum](std::size_t k, std::complex<double> v) {
    spectrum.get()[k][0] = v.real(), spectrum.get()[k][1] = v.imag();
  };
  // The series' Fourier transforms (amplitudes, and for several channels their phases too).
  std::vector<std::vector<std::complex<double>>> target(channels, std::vector<std::complex<double>>(nc));
  for (std::size_t c = 0; c < channels; ++c) {
    for (std::size_t i = 0; i < n; ++i) real.get()[i] = x[c][i] / scale[c];
    forward.execute();
    for (std::size_t k = 0; k < nc; ++k) target[c][k] = bin(k);
  }
  std::vector<double> amplitude(channels == 1 ? nc : 0);  // one channel: only the amplitudes are imposed
  for (std::size_t k = 0; k < amplitude.size(); ++k) amplitude[k] = std::hypot(target[0][k].real(), target[0][k].imag());

  std::vector<std::vector<double>> s(x);  // each channel shuffled (Fisher-Yates) on its own: the start
  for (std::size_t c = 0; c < channels; ++c) {
    std::uint64_t state = channel_seed(seed, c);
    for (std::size_t i = n - 1; i > 0; --i)
      std::swap(s[c][i], s[c][static_cast<std::size_t>(uniform01(state) * static_cast<double>(i + 1)) % (i + 1)]);
  }
  // The rank order sorts (value, index) pairs, contiguous in memory: an index sort that looks its
  // values up through a comparator took half the test's time (perf, Lorenz x at 10^4 samples).
  // The pairs enter in the previous pass's rank order, which a pass changes less and less, and
  // pattern-defeating quicksort (Boost.Sort) finishes nearly sorted runs by insertion: 4096 values
  // of Lorenz x nearly sorted 12 us against std::sort's 34 us (65 us in random order). The order is
  // total -- (value, index) -- so the result is std::sort's, whatever order the pairs come in.
  std::vector<std::pair<double, std::size_t>> ranked(n);
  std::vector<std::vector<std::size_t>> order(channels, std::vector<std::size_t>(n)), previous(channels);
  for (auto& o : order) std::iota(o.begin(), o.end(), std::size_t{0});
  // Several channels: the surrogates' current transforms, and per frequency the common rotation.
  std::vector<std::vector<std::complex<double>>> current(channels > 1 ? channels : 0, std::vector<std::complex<double>>(nc));
  std::vector<std::complex<double>> rotation(channels > 1 ? nc : 0);
  // Back from the adjusted spectrum in the FFT buffer to channel c's values in its rank order.
  const auto take_ranks = [&](std::size_t c) {
    backward.execute();  // n times the inverse; only the order of its values is used
    const double* y = real.get();
    for (std::size_t i = 0; i < n; ++i) ranked[i] = {y[order[c][i]], order[c][i]};
    boost::sort::pdqsort(ranked.begin(), ranked.end());  // ties by index, as a stable order would
    for (std::size_t i = 0; i < n; ++i) order[c][i] = ranked[i].second;
    for (std::size_t i = 0; i < n; ++i) s[c][order[c][i]] = sorted[c][i];  // the series' values in that rank order
  };
  for (std::size_t pass = 0; pass < iterations; ++pass) {
    if (channels == 1) {
      for (std::size_t i = 0; i < n; ++i) real.get()[i] = s[0][i] / scale[0];
      forward.execute();
      for (std::size_t k = 0; k < nc; ++k) {  // the series' amplitudes, the surrogate's phases
        double& re = spectrum.get()[k][0];
        double& im = spectrum.get()[k][1];
        // No hypot: every value is scaled to |x| <= 1, so |X_k| <= n, and re^2 + im^2 neither
        // overflows nor (where it matters) underflows; hypot's care took 5 % of the test.
        const double a = std::sqrt(re * re + im * im);
        if (a > 0.0) {
          re *= amplitude[k] / a, im *= amplitude[k] / a;
        } else {
          re = amplitude[k], im = 0.0;
        }
      }
      take_ranks(0);
    } else {
      // Schreiber and Schmitz (2000, Physica D 142, sec. 6.2): the channels keep their cross-spectra
      // when every channel's phases are the series' own, turned by one angle alpha(k) per frequency,
      // the one that brings the result closest to the surrogates' current transforms S_c:
      // min over alpha of sum_c |S_c - X_c e^{i alpha}|^2, e^{i alpha} = w / |w|, w = sum_c S_c conj(X_c).
      // Each channel in units of its own largest |x|, so that no channel's units choose alpha. At
      // DC and Nyquist w is real, and so is every X_c e^{i alpha}.
      for (std::size_t c = 0; c < channels; ++c) {
        for (std::size_t i = 0; i < n; ++i) real.get()[i] = s[c][i] / scale[c];
        forward.execute();
        for (std::size_t k = 0; k < nc; ++k) current[c][k] = bin(k);
      }
      for (std::size_t k = 0; k < nc; ++k) {
        std::complex<double> w = 0.0;
        for (std::size_t c = 0; c < channels; ++c) w += current[c][k] * std::conj(target[c][k]);
        const double a = std::abs(w);
        rotation[k] = a > 0.0 ? w / a : std::complex<double>(1.0, 0.0);
      }
      for (std::size_t c = 0; c < channels; ++c) {
        for (std::size_t k = 0; k < nc; ++k) set_bin(k, target[c][k] * rotation[k]);
        take_ranks(c);
      }
    }
    if (passes) *passes = pass + 1;
    if (order == previous) break;  // converged: no channel's ranks change
    previous = order;
  }
  return s;
}

namespace {

/// Whether some channel's first `count` values are all equal: that channel has no surrogates over them.
bool holds_a_channel_still(const Series& series, std::size_t count) {
  return std::any_of(series.channels.begin(), series.channels.end(), [count](const std::vector<double>& x) {
    const auto end = x.begin() + static_cast<std::ptrdiff_t>(count);
    return std::adjacent_find(x.begin(), end, std::not_equal_to<>()) == end;
  });
}

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
  if (setup.last <= setup.first) throw OptionError("the surrogate test needs a fit region of two steps or more");
  SurrogateTest out;
  out.first = setup.first, out.last = setup.last;
  RosensteinOptions ro;
  ro.dim = setup.dim, ro.delay = setup.delay, ro.theiler = setup.theiler;
  ro.horizon = setup.last;  // the slope reads steps first..last only
  ro.max_references = setup.max_references;
  ro.align_phase = setup.align_phase;
  const std::size_t n = series.size();
  const std::size_t span = (setup.dim - 1) * setup.delay + setup.last + 1;
  out.of_samples = n;
  out.channels = series.channels.size();
  out.samples = options.max_samples == 0 ? n : std::min(n, std::max(options.max_samples, 8 * span));
  // A still leading segment has no surrogates: the whole series.
  if (holds_a_channel_still(series, out.samples)) out.samples = n;
  if (n < 4 || holds_a_channel_still(series, n))
    throw InputError(series.channels.size() > 1
                         ? "the surrogate test needs at least 4 samples, and every channel's not all equal"
                         : "the surrogate test needs a series of at least 4 samples, not all equal");
  Series segment = series;
  for (std::vector<double>& x : segment.channels) x.resize(out.samples);
  if (options.match_ends && series.channels.size() > 1) {
    const EndMatch m = match_ends(series.channels, out.samples, std::min(out.samples, 8 * span));
    Series matched = series;
    for (std::vector<double>& x : matched.channels)
      x = std::vector<double>(x.begin() + static_cast<std::ptrdiff_t>(m.first),
                              x.begin() + static_cast<std::ptrdiff_t>(m.first + m.samples));
    if (!holds_a_channel_still(matched, m.samples)) {  // else the leading segment, which holds none still
      segment = std::move(matched);
      out.first_sample = m.first, out.samples = m.samples, out.end_jump = m.jump;
    }
  }
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
    std::vector<std::vector<std::vector<double>>> made(batch);
    std::vector<std::size_t> made_passes(batch, 0);
#pragma omp parallel for schedule(static, 1) num_threads(static_cast<int>(batch))
    for (std::size_t i = 0; i < batch; ++i)  // cannot throw: the segment has >= 4 values, not all equal
      made[i] = iaaft_surrogates(segment.channels, options.seed + k0 + i, options.iterations, &made_passes[i]);
    for (std::size_t i = 0; i < batch; ++i) {
      surrogate.channels = std::move(made[i]);
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
