#include "mlce/modes.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <random>

#include "fftw_plan.hpp"
#include "mlce/mean_period.hpp"
#include "mlce/numerics.hpp"
#include "mlce/transient.hpp"

namespace mlce {

void ModalOptions::validate() const {
  if (order && (*order < 1 || *order > max_order))
    throw OptionError(fmt::format("modes.order = {}: expected 1 .. max_order ({})", *order, max_order));
  if (max_order < 1) throw OptionError("modes.max_order = 0: expected >= 1");
  if (max_columns < 4) throw OptionError(fmt::format("modes.max_columns = {}: expected >= 4", max_columns));
  if (max_rows < max_columns)
    throw OptionError(fmt::format("modes.max_rows = {}: expected >= max_columns ({})", max_rows, max_columns));
  if (max_fit_samples < 16) throw OptionError(fmt::format("modes.max_fit_samples = {}: expected >= 16", max_fit_samples));
  const auto positive = [](double v, const char* name) {
    if (!(v > 0.0 && std::isfinite(v))) throw OptionError(fmt::format("modes.{} = {:g}: expected a finite value > 0", name, v));
  };
  positive(noise_factor, "noise_factor");
  positive(offset_change, "offset_change");
  positive(max_residual, "max_residual");
  positive(halves_tolerance, "halves_tolerance");
  positive(second_half_margin, "second_half_margin");
  positive(max_noise_residual, "max_noise_residual");
  positive(max_residual_correlation, "max_residual_correlation");
  positive(neutral_per_period, "neutral_per_period");
  if (!(alias_share > 0.0 && alias_share < 1.0))
    throw OptionError(fmt::format("modes.alias_share = {:g}: expected 0 < value < 1", alias_share));
  if (!(amplitude_range >= 1.0 && std::isfinite(amplitude_range)))
    throw OptionError(fmt::format("modes.amplitude_range = {:g}: expected a finite value >= 1", amplitude_range));
  if (!(floor_ratio >= 0.0 && floor_ratio < 1.0))
    throw OptionError(fmt::format("modes.floor_ratio = {:g}: expected 0 <= value < 1", floor_ratio));
  if (!(rank_tolerance > 0.0 && rank_tolerance < 1.0))
    throw OptionError(fmt::format("modes.rank_tolerance = {:g}: expected 0 < value < 1", rank_tolerance));
  if (!(min_share >= 0.0 && min_share < 1.0))
    throw OptionError(fmt::format("modes.min_share = {:g}: expected 0 <= value < 1", min_share));
  if (interval_replicates == 1 || interval_replicates > 100000)
    throw OptionError(fmt::format("modes.interval_replicates = {}: expected 0 (no interval) or 2 .. 100000", interval_replicates));
  if (!(warn_share >= 0.0 && warn_share <= min_share))
    throw OptionError(fmt::format("modes.warn_share = {:g}: expected 0 <= value <= min_share ({:g})", warn_share, min_share));
}

namespace {

/// The channels less their means, in units of their RMS deviations: the scale never enters the poles.
struct Normalised {
  std::vector<std::vector<double>> y;
  std::vector<double> mean, deviation;
};

/// `series` passed validate_series (finite samples, equal lengths, no constant channel).
Normalised normalise(const Series& series) {
  Normalised out;
  for (std::size_t c = 0; c < series.channel_count(); ++c) {
    const std::vector<double>& x = series.channels[c];
    // Divide by the largest magnitude first: the squares of 1e200 x would overflow, of 1e-200 x underflow.
    const double scale = max_abs(x);
    CompensatedSum sum;
    for (double v : x) sum.add(v / scale);
    const double mean = sum.value() / static_cast<double>(x.size());
    CompensatedSum squares;
    for (double v : x) squares.add((v / scale - mean) * (v / scale - mean));
    const double deviation = std::sqrt(squares.value() / static_cast<double>(x.size()));
    if (!(deviation > 0.0))  // not constant, yet no spread in doubles: nothing to divide by
      throw InputError(fmt::format("{} is constant to rounding: a modal fit needs a motion", channel_name(series, c)));
    std::vector<double> y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = (x[i] / scale - mean) / deviation;
    out.y.push_back(std::move(y));
    out.mean.push_back(mean * scale);
    out.deviation.push_back(deviation * scale);
  }
  return out;
}

/// One identification over samples [first, first + count) of the normalised channels.
struct Identified {
  std::vector<Mode> modes;  ///< coefficients in normalised units, times from `first`
  std::vector<double> singular_values;  ///< relative to s_1
  double noise_floor = 0.0;
  std::size_t order = 0, columns = 0, rows = 0, zero_poles = 0;
  bool capped = false, rank_deficient = false;
  double residual = 0.0, residual_correlation = 0.0;
  std::vector<double> channel_residual;
};

/// H's singular values and right singular vectors: QR first, then the SVD of the small R (to rounding,
/// not H^T H's squared values). Eigen 3.4.0's divide-and-conquer BDCSVD reads out of bounds
/// (perturbCol0: perm(l - 1) at l = 0) where a deflated entry is tiny but not zero, which a record
/// of fewer modes than columns gives (R's diagonal falls to rounding: fuzz_estimate found one at
/// 1e-16 of its largest); such an R goes to one-sided Jacobi (JacobiSVD), exact there and 2-5 x slower
/// at L = 100-160, and every other R keeps BDCSVD.
/// R's diagonal entry below this share of its largest: H has fewer modes than columns to rounding.
constexpr double kRankDeficient = 1e-10;

struct RightSingular {
  Eigen::VectorXd values;
  Eigen::MatrixXd v;
  bool rank_deficient = false;  ///< R's diagonal fell below kRankDeficient of its largest: JacobiSVD
};
RightSingular right_singular(const Eigen::MatrixXd& hankel) {
  const Eigen::Index l = hankel.cols();
  Eigen::MatrixXd r_factor = Eigen::MatrixXd::Zero(l, l);
  if (hankel.rows() >= l) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(hankel);
    r_factor = qr.matrixQR().topRows(l).triangularView<Eigen::Upper>();
  } else {
    r_factor.topRows(hankel.rows()) = hankel;  // fewer rows than columns: H itself (same V and values)
  }
  const Eigen::VectorXd diagonal = r_factor.diagonal().cwiseAbs();
  if (diagonal.minCoeff() <= kRankDeficient * diagonal.maxCoeff()) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(r_factor, Eigen::ComputeFullV);
    return {svd.singularValues(), svd.matrixV(), true};
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(r_factor, Eigen::ComputeFullV);
  return {svd.singularValues(), svd.matrixV(), false};
}

/// The largest row norm over the 10th percentile of them: how many decades the record's amplitude spans.
double row_norm_range(const Eigen::MatrixXd& hankel) {
  std::vector<double> norms(static_cast<std::size_t>(hankel.rows()));
  for (Eigen::Index row = 0; row < hankel.rows(); ++row) norms[static_cast<std::size_t>(row)] = hankel.row(row).norm();
  const auto tenth = norms.begin() + static_cast<std::ptrdiff_t>(norms.size() / 10);
  std::nth_element(norms.begin(), tenth, norms.end());
  const double low = *tenth, high = *std::max_element(norms.begin(), norms.end());
  return low > 0.0 ? high / low : std::numeric_limits<double>::infinity();
}

struct Pole {
  std::complex<double> s;  ///< per time unit
  bool real = false, nyquist = false;
};

/// Steps 2-4 of modes.hpp: the Hankel matrix, its singular values, the order and the poles.
std::vector<Pole> pencil_poles(const Normalised& data, std::size_t first, std::size_t count, std::size_t stride, double dt,
                               std::optional<std::size_t> order, const ModalOptions& o, Identified& out) {
  const std::size_t strided = (count - 1) / stride + 1;
  const std::size_t columns = std::min(o.max_columns, strided / 3);
  if (columns < 4)
    throw InputError(fmt::format("{} samples at a stride of {} give {} strided samples: a modal fit needs at least 12",
                                 count, stride, strided));
  const std::size_t span = (columns - 1) * stride;
  const std::size_t starts = count - span;  // row k: samples first + k + j * stride, j = 0..L-1
  const std::size_t channels = data.y.size();
  const std::size_t row_stride = (starts * channels + o.max_rows - 1) / o.max_rows;
  const std::size_t rows_per_channel = (starts - 1) / row_stride + 1;
  Eigen::MatrixXd hankel(static_cast<Eigen::Index>(rows_per_channel * channels), static_cast<Eigen::Index>(columns));
  for (std::size_t c = 0; c < channels; ++c)
    for (std::size_t r = 0; r < rows_per_channel; ++r)
      for (std::size_t j = 0; j < columns; ++j)
        hankel(static_cast<Eigen::Index>(c * rows_per_channel + r), static_cast<Eigen::Index>(j)) =
            data.y[c][first + r * row_stride + j * stride];
  out.columns = columns;
  out.rows = rows_per_channel * channels;
  const Eigen::Index l = static_cast<Eigen::Index>(columns);
  RightSingular svd = right_singular(hankel);
  out.rank_deficient = svd.rank_deficient;
  if (o.weighting == RowWeighting::amplitude ||
      (o.weighting == RowWeighting::automatic && row_norm_range(hankel) > o.amplitude_range)) {
    // Every row scaled to unit norm, down to a floor: a row is a sum of the mode patterns z^{jD} whatever its
    // weight, so the poles stay; a decay over decades then weighs its late rows (its least damped modes)
    // as much as its start. The floor, noise_factor x a noise-only row's norm (the median of the lower half
    // of the unweighted singular values over sqrt(rows), times sqrt(L)), keeps rows at a measurement
    // noise floor from being raised to the signal's weight.
    const Eigen::VectorXd& unweighted = svd.values;
    const double floor_value = median(std::vector<double>(unweighted.data() + columns / 2, unweighted.data() + columns));
    const double floor_norm = o.noise_factor * floor_value / std::sqrt(static_cast<double>(hankel.rows())) *
                              std::sqrt(static_cast<double>(columns));
    for (Eigen::Index row = 0; row < hankel.rows(); ++row) {
      const double norm = std::max(hankel.row(row).norm(), floor_norm);
      if (norm > 0.0) hankel.row(row) /= norm;
    }
    svd = right_singular(hankel);
    out.rank_deficient = out.rank_deficient || svd.rank_deficient;
  }
  const Eigen::VectorXd& values = svd.values;
  const double largest = values(0);
  if (!(largest > 0.0)) return {};  // a stretch that sits at the record's mean throughout: no mode, order 0
  out.singular_values.resize(columns);
  for (std::size_t j = 0; j < columns; ++j) out.singular_values[j] = values(static_cast<Eigen::Index>(j)) / largest;
  out.noise_floor = median(std::vector<double>(out.singular_values.begin() + static_cast<std::ptrdiff_t>(columns / 2),
                                               out.singular_values.end()));
  const std::size_t cap = std::min(o.max_order, columns / 2);
  std::size_t n = 0;
  if (order) {
    n = std::min(*order, cap);
  } else {
    const double threshold = std::max(o.noise_factor * out.noise_floor, o.rank_tolerance);
    while (n < columns && out.singular_values[n] > threshold) ++n;
    out.capped = n > cap;
    n = std::min(n, cap);
  }
  out.order = n;
  if (n == 0) return {};
  // Shift invariance (step 4): the right singular vectors one column on are the same, times z^D.
  const Eigen::MatrixXd v = svd.v.leftCols(static_cast<Eigen::Index>(n));
  const Eigen::MatrixXd v1 = v.topRows(l - 1), v2 = v.bottomRows(l - 1);
  const Eigen::MatrixXd a = v1.colPivHouseholderQr().solve(v2);
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(a, /*computeEigenvectors=*/false);
  std::vector<Pole> poles;
  const double step = static_cast<double>(stride) * dt;
  for (Eigen::Index k = 0; k < eigen.eigenvalues().size(); ++k) {
    const std::complex<double> mu = eigen.eigenvalues()(k);
    // A pole at 0 is a part that vanishes within one stride: no rate to read (and no log of 0).
    if (!(std::abs(mu) > 1e-300)) {
      ++out.zero_poles;
      continue;
    }
    const bool real = std::abs(mu.imag()) <= 1e-9 * std::abs(mu);
    if (!real && mu.imag() < 0.0) continue;  // the conjugate of a pair listed once
    Pole p;
    p.real = real && mu.real() > 0.0;
    p.nyquist = real && mu.real() < 0.0;
    p.s = real ? std::complex<double>(std::log(std::abs(mu.real())) / step, p.nyquist ? std::numbers::pi / step : 0.0)
               : std::log(mu) / step;
    poles.push_back(p);
  }
  return poles;
}

/// The sum of squares about each column's own mean.
double variation(const Eigen::Ref<const Eigen::MatrixXd>& x) {
  if (x.rows() == 0) return 0.0;
  return (x.rowwise() - x.colwise().mean()).squaredNorm();
}

/// Step 5: the modes' amplitudes by least squares on at most max_fit_samples evenly strided samples.
void fit_amplitudes(const Normalised& data, std::size_t first, std::size_t count, double dt, const std::vector<Pole>& poles,
                    const ModalOptions& o, Identified& out) {
  const std::size_t fit_stride = (count + o.max_fit_samples - 1) / o.max_fit_samples;
  const std::size_t q_count = (count - 1) / fit_stride + 1;
  const double end = static_cast<double>(count - 1) * dt;
  std::vector<std::size_t> column_of(poles.size());
  std::size_t columns = 0;
  for (std::size_t p = 0; p < poles.size(); ++p) {
    column_of[p] = columns;
    columns += (poles[p].real || poles[p].nyquist) ? 1 : 2;
  }
  const auto qn = static_cast<Eigen::Index>(q_count);
  Eigen::MatrixXd basis(qn, static_cast<Eigen::Index>(columns));
  for (std::size_t p = 0; p < poles.size(); ++p) {
    const double sigma = poles[p].s.real(), omega = poles[p].s.imag();
    const double reference = sigma > 0.0 ? end : 0.0;  // e^{sigma (t - reference)} <= 1: no overflow
    for (std::size_t q = 0; q < q_count; ++q) {
      const double t = static_cast<double>(q * fit_stride) * dt;
      const double envelope = std::exp(sigma * (t - reference));
      const auto row = static_cast<Eigen::Index>(q), col = static_cast<Eigen::Index>(column_of[p]);
      if (poles[p].real) {
        basis(row, col) = envelope;
      } else if (poles[p].nyquist) {
        basis(row, col) = envelope * std::cos(omega * t);
      } else {
        basis(row, col) = envelope * std::cos(omega * t);
        basis(row, col + 1) = envelope * std::sin(omega * t);
      }
    }
  }
  const std::size_t channels = data.y.size();
  Eigen::MatrixXd y(qn, static_cast<Eigen::Index>(channels));
  for (std::size_t c = 0; c < channels; ++c)
    for (std::size_t q = 0; q < q_count; ++q)
      y(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(c)) = data.y[c][first + q * fit_stride];
  const Eigen::MatrixXd coefficients =
      columns > 0 ? Eigen::MatrixXd(basis.colPivHouseholderQr().solve(y)) : Eigen::MatrixXd::Zero(0, y.cols());
  const Eigen::MatrixXd left = columns > 0 ? Eigen::MatrixXd(y - basis * coefficients) : y;
  // Shares and residuals are of the variation about the stretch's own mean: a half or a quarter of a decay
  // sits on the offset the whole record's mean leaves, which is no motion of it.
  double total = 0.0, rest = 0.0;
  out.channel_residual.resize(channels);
  for (std::size_t c = 0; c < channels; ++c) {
    const double sc = variation(y.col(static_cast<Eigen::Index>(c))), rc = left.col(static_cast<Eigen::Index>(c)).squaredNorm();
    out.channel_residual[c] = sc > 0.0 ? std::sqrt(rc / sc) : 0.0;
    total += sc, rest += rc;
  }
  out.residual = total > 0.0 ? std::sqrt(rest / total) : 0.0;
  // What the fit leaves: measurement noise (white: its neighbours on the fit grid uncorrelated) or motion.
  CompensatedSum lagged, squares;
  for (Eigen::Index c = 0; c < left.cols(); ++c)
    for (Eigen::Index q = 0; q < left.rows(); ++q) {
      squares.add(left(q, c) * left(q, c));
      if (q > 0) lagged.add(left(q, c) * left(q - 1, c));
    }
  out.residual_correlation = squares.value() > 0.0 ? lagged.value() / squares.value() : 0.0;
  for (std::size_t p = 0; p < poles.size(); ++p) {
    Mode m;
    const double sigma = poles[p].s.real(), omega = poles[p].s.imag();
    m.sigma = sigma;
    m.frequency = std::abs(omega) / (2.0 * std::numbers::pi);
    m.damping_ratio = std::abs(poles[p].s) > 0.0 ? -sigma / std::abs(poles[p].s) : 0.0;
    m.nyquist = poles[p].nyquist;
    m.reference_time = sigma > 0.0 ? end : 0.0;
    const std::size_t width = (poles[p].real || poles[p].nyquist) ? 1 : 2;
    const auto col = static_cast<Eigen::Index>(column_of[p]);
    const Eigen::MatrixXd part = basis.middleCols(col, static_cast<Eigen::Index>(width)) *
                                 coefficients.middleRows(col, static_cast<Eigen::Index>(width));
    m.share = total > 0.0 ? variation(part) / total : 0.0;
    // A growing mode can hold little of the whole record and most of its end: the largest share of any
    // quarter where the mode stands out of what the fit leaves there (RMS 3x: a pole fitted to a quarter's
    // floor, rounding or noise, holds much of a quiet quarter and no more than its floor).
    for (std::size_t quarter = 0; quarter < 4; ++quarter) {
      const auto from = static_cast<Eigen::Index>(quarter * q_count / 4), to = static_cast<Eigen::Index>((quarter + 1) * q_count / 4);
      const double there = variation(y.middleRows(from, to - from)), mine = variation(part.middleRows(from, to - from));
      if (there > 0.0 && mine >= 9.0 * left.middleRows(from, to - from).squaredNorm())
        m.peak_share = std::max(m.peak_share, mine / there);
    }
    for (std::size_t c = 0; c < channels; ++c) {
      m.cos_coefficient.push_back(coefficients(col, static_cast<Eigen::Index>(c)));
      m.sin_coefficient.push_back(width == 2 ? coefficients(col + 1, static_cast<Eigen::Index>(c)) : 0.0);
    }
    // A real pole that hardly changes over the record is what the mean removal left, or a static offset.
    m.offset = poles[p].real && std::abs(std::expm1(sigma * end)) < o.offset_change;
    out.modes.push_back(std::move(m));
  }
  std::stable_sort(out.modes.begin(), out.modes.end(), [](const Mode& a, const Mode& b) { return a.share > b.share; });
}

Identified identify(const Normalised& data, std::size_t first, std::size_t count, std::size_t stride, double dt,
                    std::optional<std::size_t> order, const ModalOptions& o) {
  Identified out;
  const std::vector<Pole> poles = pencil_poles(data, first, count, stride, dt, order, o, out);
  fit_amplitudes(data, first, count, dt, poles, o, out);
  return out;
}

/// The mode that sets lambda (step 6): the largest sigma among those holding min_share, offsets left out.
std::optional<std::size_t> lambda_mode(const std::vector<Mode>& modes, double min_share) {
  std::optional<std::size_t> best;
  for (std::size_t k = 0; k < modes.size(); ++k)
    if (!modes[k].offset && modes[k].peak_share >= min_share && (!best || modes[k].sigma > modes[*best].sigma)) best = k;
  return best;
}

/// Adds mode m's part of channel c at samples 0..x.size()-1 (t = i dt from the stretch's first sample) to x.
void add_mode_part(const Mode& m, std::size_t c, double dt, std::size_t stride, std::vector<double>& x) {
  const double omega = 2.0 * std::numbers::pi * m.frequency;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i) * dt;
    // A pole at the strided Nyquist frequency alternates in sign from one stride to the next.
    const double wave = m.nyquist ? m.cos_coefficient[c] * std::cos(std::numbers::pi * static_cast<double>(i) / static_cast<double>(stride))
                                  : m.cos_coefficient[c] * std::cos(omega * t) + m.sin_coefficient[c] * std::sin(omega * t);
    x[i] += std::exp(m.sigma * (t - m.reference_time)) * wave;
  }
}

/// The rates that read neutral: |sigma| within neutral_per_period of the mode's frequency (of the record's length's
/// inverse for a real mode).
double neutral_band(const ModalOptions& options, double frequency, double record_length) {
  return options.neutral_per_period * (frequency > 0.0 ? frequency : 1.0 / record_length);
}

/// Bins on either side over which noise_model smooths the residual's periodogram (step 8): 33 bins, in which
/// the few the fit's modes emptied weigh little.
constexpr std::size_t kSpectrumSmoothing = 16;

/// What the fit left in each channel, as a noise model: its periodogram smoothed over +-kSpectrumSmoothing bins.
/// Smoothed, because the fit takes the noise at the modes' own frequencies with them (the residual is
/// orthogonal to the modes' basis): the residual itself, reshuffled, lacks exactly the noise that moves the rates
/// (a circular shift of it kept each record's periodogram and gave 0.45-1.0 of the estimator's spread on the
/// beating decays with 3 % noise: a first version, which held the true rate on 31 of 40 records in
/// bench/modal_accuracy coverage, against 38 now).
struct NoiseModel {
  std::vector<std::vector<double>> amplitude;  ///< per channel, sqrt of the smoothed periodogram, bins 0..n/2
  std::vector<double> mean;                    ///< per channel, what the fit left on average (kept as it is)
};

NoiseModel noise_model(const std::vector<std::vector<double>>& left, std::size_t smoothing) {
  NoiseModel model;
  const std::size_t n = left.front().size(), bins = n / 2 + 1;
  std::unique_ptr<double, decltype(&fftw_free)> real(fftw_alloc_real(n), &fftw_free);
  std::unique_ptr<fftw_complex, decltype(&fftw_free)> spectrum(fftw_alloc_complex(bins), &fftw_free);
  const detail::Plan forward = detail::forward_plan(n, real.get(), spectrum.get());
  for (const std::vector<double>& e : left) {
    CompensatedSum sum;
    for (double v : e) sum.add(v);
    model.mean.push_back(sum.value() / static_cast<double>(n));
    for (std::size_t i = 0; i < n; ++i) real.get()[i] = e[i] - model.mean.back();
    forward.execute();
    std::vector<double> power(bins);
    for (std::size_t k = 0; k < bins; ++k) power[k] = spectrum.get()[k][0] * spectrum.get()[k][0] + spectrum.get()[k][1] * spectrum.get()[k][1];
    // Daniell window over bins 1..bins-1 (the mean is kept apart; at the ends the window is cut, not folded).
    std::vector<double> amplitude(bins, 0.0);
    for (std::size_t k = 1; k < bins; ++k) {
      const std::size_t lo = k > smoothing ? k - smoothing : 1, hi = std::min(bins - 1, k + smoothing);
      CompensatedSum window;
      for (std::size_t j = lo; j <= hi; ++j) window.add(power[j]);
      amplitude[k] = std::sqrt(window.value() / static_cast<double>(hi - lo + 1));
    }
    model.amplitude.push_back(std::move(amplitude));
  }
  return model;
}

/// Step 8 (modes.hpp): lambda's spread over records made of the stretch's fitted modes plus Gaussian noise of
/// the spectrum the fit left there (noise_model), each identified as the stretch was (same stride, options.order).
void lambda_interval(const Normalised& data, std::size_t first, std::size_t count, std::size_t stride, double dt,
                     const Identified& fit, const ModalOptions& o, ModalResult& r) {
  const std::size_t channels = data.y.size(), bins = count / 2 + 1;
  std::vector<std::vector<double>> model(channels, std::vector<double>(count, 0.0)), left(channels);
  for (std::size_t c = 0; c < channels; ++c) {
    for (const Mode& m : fit.modes) add_mode_part(m, c, dt, stride, model[c]);
    left[c].resize(count);
    for (std::size_t i = 0; i < count; ++i) left[c][i] = data.y[c][first + i] - model[c][i];
  }
  const NoiseModel noise = noise_model(left, kSpectrumSmoothing);
  const std::size_t replicates = o.interval_replicates;
  std::vector<double> lambdas(replicates, std::numeric_limits<double>::quiet_NaN());
  const auto signed_count = static_cast<std::ptrdiff_t>(replicates);
  std::atomic<std::size_t> done{0};
#pragma omp parallel
  {
    std::unique_ptr<double, decltype(&fftw_free)> real(fftw_alloc_real(count), &fftw_free);
    std::unique_ptr<fftw_complex, decltype(&fftw_free)> spectrum(fftw_alloc_complex(bins), &fftw_free);
    const detail::Plan backward = detail::backward_plan(count, spectrum.get(), real.get());
    Normalised replica;
    replica.y.assign(channels, std::vector<double>(count));
#pragma omp for schedule(dynamic, 1)
    for (std::ptrdiff_t b = 0; b < signed_count; ++b) {
      // One generator per replicate, seeded by its index: the interval does not depend on the thread count.
      std::mt19937_64 random(o.interval_seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(b));
      std::normal_distribution<double> gauss;
      for (std::size_t c = 0; c < channels; ++c) {
        // Bin k of a record of this spectrum: complex Gaussian of power amplitude^2 (real at 0 and at n/2 of
        // an even n); the unnormalised inverse transform over n gives the record's variance back.
        spectrum.get()[0][0] = spectrum.get()[0][1] = 0.0;
        for (std::size_t k = 1; k < bins; ++k) {
          const bool real_bin = 2 * k == count;
          const double a = noise.amplitude[c][k] * (real_bin ? 1.0 : std::sqrt(0.5));
          spectrum.get()[k][0] = a * gauss(random);
          spectrum.get()[k][1] = real_bin ? 0.0 : a * gauss(random);
        }
        backward.execute();
        for (std::size_t i = 0; i < count; ++i)
          replica.y[c][i] = model[c][i] + noise.mean[c] + real.get()[i] / static_cast<double>(count);
      }
      try {
        const Identified again = identify(replica, 0, count, stride, dt, o.order, o);
        if (const auto k = lambda_mode(again.modes, o.min_share)) lambdas[static_cast<std::size_t>(b)] = again.modes[*k].sigma;
      } catch (const std::exception&) {  // no exception leaves the parallel loop: the replicate counts as one without lambda
      }
      const std::size_t finished = ++done;
      if (o.progress && finished % 10 == 0) {
#pragma omp critical(mlce_modes_progress)
        {
          try {
            o.progress(fmt::format("lambda's interval: {} of {} replicates", finished, replicates),
                       static_cast<double>(finished) / static_cast<double>(replicates));
          } catch (...) {  // a reporter's failure never stops the computation, nor leaves the parallel loop
          }
        }
      }
    }
  }
  std::vector<double> found;
  for (double v : lambdas)
    if (std::isfinite(v)) found.push_back(v);
  r.interval_replicates = replicates;
  r.replicates_without_lambda = replicates - found.size();
  if (found.size() < 2) return;
  // In units of the largest rate found: rates near the largest double (a tiny dt) neither overflow the squares
  // nor the sum.
  const double scale = max_abs(found);
  CompensatedSum sum, squares;
  for (double v : found) sum.add(v / scale);
  const double mean = sum.value() / static_cast<double>(found.size());
  for (double v : found) squares.add((v / scale - mean) * (v / scale - mean));
  r.lambda_spread = scale > 0.0 ? scale * std::sqrt(squares.value() / static_cast<double>(found.size() - 1)) : 0.0;
  // More than the tails' 2.5 % without a lambda: noise like the residual can hide the mode, and no interval
  // of the found ones covers that.
  if (static_cast<double>(r.replicates_without_lambda) > 0.025 * static_cast<double>(replicates)) {
    r.warnings.push_back(fmt::format("{} of {} noise replicates find no mode holding {:g} of a quarter of the record: no interval "
                                     "for lambda (noise like the residual can hide its mode)",
                                     r.replicates_without_lambda, replicates, o.min_share));
    return;
  }
  // The normal interval about lambda: of the three bootstrap intervals measured it held the true rate most
  // often (bench/modal_accuracy coverage; the percentile and basic intervals' quantiles come from the 2nd/3rd
  // and 97th/98th of 100 replicates and scatter more).
  const double low = *r.lambda - 1.96 * r.lambda_spread, high = *r.lambda + 1.96 * r.lambda_spread;
  if (!std::isfinite(low) || !std::isfinite(high)) {
    r.warnings.push_back("lambda's interval exceeds the range of doubles: none given");
    return;
  }
  r.lambda_low = low;
  r.lambda_high = high;
}

}  // namespace

/// Steps 1-7 over the whole of `series` (identify_modes has cut any floor off).
ModalResult identify_record(const Series& series, const ModalOptions& options) {
  const Normalised data = normalise(series);
  const std::size_t n = series.size();
  ModalResult r;
  r.dt = series.dt;
  r.time_unit = series.time_unit;
  r.n_points = n;
  r.channel_mean = data.mean;
  if (n < 12) throw InputError(fmt::format("{} samples: a modal fit needs at least 12", n));
  const MeanPeriodResult period = estimate_mean_period(series, {});
  // By its mean period only: the spectrum's fast share (MeanPeriodResult::map) also counts the white
  // noise of a decay recorded into its noise floor, which the modes fit well.
  r.map = period.mean_period < kMinFlowPeriod;
  if (options.samples_per_mean_period > 0) {
    // samples_per_mean_period in the mean period, and the strided Nyquist frequency 1 / (2 D) at least 1.25 x
    // the band edge (all but alias_share of the power below it): a strong slow part (a drift, the hub's
    // slow mode) makes the mean period long while faster modes still carry the rates.
    const double edge = band_edge_frequency(series, 1.0 - options.alias_share);
    const auto unfolded = static_cast<std::size_t>(std::floor(0.4 / std::max(edge, 1e-300)));
    r.stride = std::max<std::size_t>(1, std::min(period.mean_period / options.samples_per_mean_period, unfolded));
  }
  Identified whole = identify(data, 0, n, r.stride, series.dt, options.order, options);
  r.order = whole.order;
  r.order_automatic = !options.order;
  r.order_capped = whole.capped;
  r.rank_deficient = whole.rank_deficient;
  r.singular_values = whole.singular_values;
  r.noise_floor = whole.noise_floor;
  r.columns = whole.columns;
  r.rows = whole.rows;
  r.residual = whole.residual;
  r.residual_correlation = whole.residual_correlation;
  r.channel_residual = whole.channel_residual;
  r.modes = whole.modes;  // whole keeps its normalised modes for the interval (step 8)
  for (Mode& m : r.modes)  // back to the channels' units
    for (std::size_t c = 0; c < m.cos_coefficient.size(); ++c) {
      m.cos_coefficient[c] *= data.deviation[c];
      m.sin_coefficient[c] *= data.deviation[c];
    }
  if (whole.capped)
    r.warnings.push_back(fmt::format("more than {} singular values stand above the noise floor: the fit keeps the {} strongest",
                                     r.order, r.order));
  if (whole.zero_poles > 0)
    r.warnings.push_back(fmt::format("{} poles at 0 (parts that vanish within one stride) left out", whole.zero_poles));
  r.noise_left = r.residual <= options.max_noise_residual && r.residual_correlation <= options.max_residual_correlation;
  r.linear = r.order > 0 && !r.map && (r.residual <= options.max_residual || r.noise_left);
  r.lambda_mode = lambda_mode(r.modes, options.min_share);
  const double record = static_cast<double>(n - 1) * series.dt;
  // Rates within the neutral band of the mode's period (the record's length for a real mode) read neutral.
  const auto band_of = [&](double frequency) { return neutral_band(options, frequency, record); };
  if (r.lambda_mode) {
    r.lambda = r.modes[*r.lambda_mode].sigma;
    r.lambda_mode_frequency = r.modes[*r.lambda_mode].frequency;
  }
  // Step 7: each half on its own. A half its modes describe (a decay gone into its noise floor is not) gives
  // its own lambda; the second half's replaces the whole record's when it is larger beyond the neutral band:
  // the least damped mode is what a motion ends with, and a record that starts with a larger, faster or
  // nonlinear transient can hide it from the whole record's strongest modes.
  const std::size_t half = n / 2;
  std::optional<Identified> second;  // the second half's identification, when its lambda is taken
  if (options.check_halves && r.linear) {
    try {
      const Identified a = identify(data, 0, half, r.stride, series.dt, options.order, options);
      Identified b = identify(data, n - half, half, r.stride, series.dt, options.order, options);
      // A half's lambda counts when its modes describe it and it spans two periods of its lambda mode (an
      // e-fold of a real one): over less, a noisy half fits a pole to the noise as readily as to the motion.
      const double half_span = static_cast<double>(half - 1) * series.dt;
      const auto half_lambda = [&](const Identified& h) -> std::optional<std::size_t> {
        if (h.residual > options.max_residual) return std::nullopt;
        const auto k = lambda_mode(h.modes, options.min_share);
        if (!k) return std::nullopt;
        const Mode& hm = h.modes[*k];
        const bool spanned = hm.frequency > 0.0 ? hm.frequency * half_span >= 2.0 : std::abs(hm.sigma) * half_span >= 1.0;
        return spanned ? k : std::nullopt;
      };
      const auto la = half_lambda(a), lb = half_lambda(b);
      if (la) r.first_half_lambda = a.modes[*la].sigma;
      if (lb) r.second_half_lambda = b.modes[*lb].sigma;
      if (lb && (!r.lambda || b.modes[*lb].sigma > *r.lambda + std::max(options.second_half_margin * std::abs(*r.lambda),
                                                                         0.1 * band_of(b.modes[*lb].frequency)))) {
        r.lambda = b.modes[*lb].sigma;
        r.lambda_mode_frequency = b.modes[*lb].frequency;
        r.lambda_from_second_half = true;
        r.lambda_mode.reset();  // no mode of the whole record's list
      }
      if (la && lb) {
        const double x = *r.first_half_lambda, y = *r.second_half_lambda;
        r.halves_agree = std::abs(x - y) <= std::max(options.halves_tolerance * std::max(std::abs(x), std::abs(y)),
                                                     band_of(b.modes[*lb].frequency));
      }
      if (r.lambda_from_second_half) second = std::move(b);
    } catch (const InputError&) {
      r.warnings.push_back("the record's halves are too short to identify on their own: lambda is the whole record's");
    }
  }
  if (r.lambda) {
    std::size_t faster = 0;
    const Mode* fastest = nullptr;
    for (const Mode& weak : r.modes)
      if (!weak.offset && weak.peak_share >= options.warn_share && weak.peak_share < options.min_share && weak.sigma > *r.lambda) {
        ++faster;
        if (!fastest || weak.sigma > fastest->sigma) fastest = &weak;
      }
    if (fastest)
      r.warnings.push_back(fmt::format("{} weaker mode{} grow{} faster than lambda, the fastest {:.6g} at {:.6g} cycles per time "
                                       "unit, holding {:.2g} of a quarter of the record (under {:g}: a mode still small, or "
                                       "the fit's correction of a rate that changes)", faster, faster > 1 ? "s" : "",
                                       faster > 1 ? "" : "s", fastest->sigma, fastest->frequency, fastest->peak_share,
                                       options.min_share));
    r.lambda_per_sample = *r.lambda * series.dt;
    // Step 8: the interval, over the stretch lambda was read from (the second half when it was taken there).
    if (options.interval_replicates > 0 && r.linear) {  // a record the modes miss: no noise interval means anything
      if (second)
        lambda_interval(data, n - half, half, r.stride, series.dt, *second, options, r);
      else
        lambda_interval(data, 0, n, r.stride, series.dt, whole, options, r);
    }
    if (r.lambda_mode_frequency > 0.0 && r.lambda_mode_frequency * record < 1.0)
      r.warnings.push_back(fmt::format("the record spans {:.2f} periods of its least damped mode: over less than one, noise "
                                       "moves its rate far (bench/modal_accuracy short)", r.lambda_mode_frequency * record));
  }
  if (r.map) {
    r.reading = fmt::format("undetermined: a mean period of {} samples: a map, noise, or a flow sampled too coarsely (modes "
                            "are a sampled flow's)", period.mean_period);
  } else if (r.order > 0 && !r.linear) {
    r.reading = fmt::format("undetermined: the modes leave {:.1f} % of the record (not a sum of few damped modes: read "
                            "Rosenstein's estimate)", 100.0 * r.residual);
  } else if (r.order == 0 || !r.lambda) {
    r.reading = "undetermined: no mode stands above the noise floor";
  } else {
    const double band = band_of(r.lambda_mode_frequency);
    const int sign = *r.lambda > band ? 1 : (*r.lambda < -band ? -1 : 0);
    r.reading = sign < 0 ? "stable, decaying modes" : (sign > 0 ? "unstable, growing mode" : "neutral, undamped mode");
    r.stability = sign < 0 ? Stability::stable : (sign > 0 ? Stability::unstable : Stability::neutral);
    // A sign the interval contradicts is not read: lambda beyond the band on one side, its interval
    // beyond it on the other. Blade 1's lag over the bundled 1 s isotropic MBDyn run (0.92 periods of
    // its least damped mode) read "unstable, growing mode" at +0.254 1/s with [-0.088, +0.597]; the
    // rotor's slowest eigenvalue is -1.18 (mlce eigen).
    if (r.lambda_low && r.lambda_high && ((sign > 0 && *r.lambda_low < -band) || (sign < 0 && *r.lambda_high > band))) {
      r.reading = fmt::format("undetermined: lambda {:+.4g} 1/{}, but its 95 % interval [{:+.4g}, {:+.4g}] reaches beyond "
                              "the neutral band (+-{:.3g}) on the other side: the record does not resolve the sign (a "
                              "longer run)", *r.lambda, series.time_unit.empty() ? "sample" : series.time_unit,
                              *r.lambda_low, *r.lambda_high, band);
      r.stability = Stability::undetermined;
    }
    if (r.lambda_from_second_half)
      r.reading += fmt::format(" (the least damped mode from the record's second half: the whole record's strongest modes "
                               "decay faster)");
    if (!r.halves_agree)
      r.reading += fmt::format(" (the rate changes over the record: halves {:.6g} and {:.6g}; amplitude-dependent damping, or "
                               "a mode that emerges late?)", *r.first_half_lambda, *r.second_half_lambda);
  }
  if (!r.linear && r.order > 0 && !r.map)
    r.warnings.push_back(fmt::format("the {} modes leave {:.1f} % of the record (RMS): the modal rates do not describe it",
                                     r.order, 100.0 * r.residual));
  return r;
}

namespace {

/// Step 9 (modes.hpp): a growth whose record the modes do not describe to its end (not `linear`, its second half
/// no sum of modes, or its second half growing more slowly than its first) is read over its leading half, quarter
/// or eighth, the longest that grows at one rate (both halves read, and they agree): a growth that saturates into
/// a limit cycle is linear while it is small.
ModalResult read_growth_before_saturation(const Series& series, ModalResult whole, const ModalOptions& options) {
  if (!options.read_leading_growth || !options.check_halves || whole.map) return whole;
  const double band = neutral_band(options, whole.lambda_mode_frequency, static_cast<double>(series.size() - 1) * series.dt);
  const bool growing = whole.lambda && *whole.lambda > band;
  // Tried where the whole record is no sum of modes (a saturated growth leaves 40-50 %: no lambda read), or grows
  // with a second half its modes do not describe, or grows more slowly in its second half than in its first (a
  // growth that saturates; one that emerges late under a decay grows faster in the second).
  const bool slowing = whole.first_half_lambda && whole.second_half_lambda && !whole.halves_agree &&
                       *whole.second_half_lambda < *whole.first_half_lambda && *whole.first_half_lambda > band;
  if (whole.linear && !(growing && !whole.second_half_lambda) && !slowing) return whole;
  ModalOptions trial = options;
  trial.interval_replicates = 0;  // the interval only for the part taken
  Series part = series;
  for (int halving = 1; halving <= 3; ++halving) {
    const std::size_t n = series.size() >> halving;
    for (auto& channel : part.channels) channel.resize(n);
    try {
      ModalResult r = identify_record(part, trial);
      const double part_band = neutral_band(options, r.lambda_mode_frequency, static_cast<double>(n - 1) * series.dt);
      if (r.linear && r.lambda && *r.lambda > part_band && r.first_half_lambda && r.second_half_lambda && r.halves_agree) {
        if (options.interval_replicates > 0) r = identify_record(part, options);
        r.leading_part = true;
        r.warnings.insert(r.warnings.begin(),
                          fmt::format("the growth is no sum of modes to the record's end ({}): read over its first 1/{}, to t = "
                                      "{:.6g}, where it grows at one rate (the whole record reads {})",
                                      !whole.linear ? fmt::format("they leave {:.1f} %", 100.0 * whole.residual)
                                      : slowing     ? fmt::format("its halves grow at {:.6g} and {:.6g}: it slows down",
                                                                  *whole.first_half_lambda, *whole.second_half_lambda)
                                                    : std::string("its second half is no sum of modes"),
                                      1 << halving, series.time(n - 1),
                                      whole.lambda ? fmt::format("{:.6g}", *whole.lambda) : std::string("no lambda")));
        return r;
      }
    } catch (const InputError&) {
      break;  // too short to identify: the whole record's reading stands
    }
  }
  return whole;
}

}  // namespace

ModalResult identify_modes(const Series& series, const ModalOptions& options) {
  options.validate();
  validate_series(series);  // equal lengths, a normal dt, finite samples, no constant channel: one error naming it
  if (series.size() < 12) throw InputError(fmt::format("{} samples: a modal fit needs at least 12", series.size()));
  // A decay written into its floor (rounding, the solver's tolerance, measurement noise) ends in what no
  // mode of the motion describes, and weighed by amplitude that end would count as much as the motion:
  // analysed up to the floor, as the estimate is (detect_floor, MlceOptions::floor_ratio).
  const Floor floor = detect_floor(series, options.floor_ratio, options.record_deviation);
  if (floor.whole)
    throw InputError("the record lies within the floor of a decay that ended before it (rounding, solver tolerance): no "
                     "motion to fit");
  if (floor.index == 0) return read_growth_before_saturation(series, identify_record(series, options), options);
  if (floor.index < 12)
    throw InputError(fmt::format("the record reaches its floor after {} samples: a modal fit needs at least 12 before it",
                                 floor.index));
  Series cut = series;
  for (auto& channel : cut.channels) channel.resize(floor.index);
  ModalResult r = identify_record(cut, options);
  r.floor_start = floor.index;
  r.warnings.insert(r.warnings.begin(),
                    fmt::format("the record decays into a {} floor at t = {:.6g} ({:.2g} of its largest RMS): analysed "
                                "up to it", floor.white_noise ? "white-noise" : (floor.resolution ? "resolution" : "rounding/tolerance"),
                                series.time(floor.index), floor.level));
  return r;
}

std::vector<std::vector<double>> modal_reconstruction(const ModalResult& result) {
  std::vector<std::vector<double>> out;
  for (std::size_t c = 0; c < result.channel_mean.size(); ++c) {
    std::vector<double> x(result.n_points, result.channel_mean[c]);
    for (const Mode& m : result.modes) add_mode_part(m, c, result.dt, result.stride, x);
    out.push_back(std::move(x));
  }
  return out;
}

}  // namespace mlce
