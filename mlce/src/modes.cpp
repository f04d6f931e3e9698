#include "mlce/modes.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <numeric>

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
  bool capped = false;
  double residual = 0.0, residual_correlation = 0.0;
  std::vector<double> channel_residual;
};

/// H's singular values and right singular vectors: QR first, then the SVD of the small R (to rounding,
/// not H^T H's squared values).
Eigen::BDCSVD<Eigen::MatrixXd> right_singular(const Eigen::MatrixXd& hankel) {
  const Eigen::Index l = hankel.cols();
  Eigen::MatrixXd r_factor = Eigen::MatrixXd::Zero(l, l);
  if (hankel.rows() >= l) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(hankel);
    r_factor = qr.matrixQR().topRows(l).triangularView<Eigen::Upper>();
  } else {
    r_factor.topRows(hankel.rows()) = hankel;  // fewer rows than columns: H itself (same V and values)
  }
  return Eigen::BDCSVD<Eigen::MatrixXd>(r_factor, Eigen::ComputeFullV);
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
  Eigen::BDCSVD<Eigen::MatrixXd> svd = right_singular(hankel);
  if (o.weighting == RowWeighting::amplitude ||
      (o.weighting == RowWeighting::automatic && row_norm_range(hankel) > o.amplitude_range)) {
    // Every row scaled to unit norm, down to a floor: a row is a sum of the mode patterns z^{jD} whatever its
    // weight, so the poles stay; a decay over decades then weighs its late rows (its least damped modes)
    // as much as its start. The floor, noise_factor x a noise-only row's norm (the median of the lower half
    // of the unweighted singular values over sqrt(rows), times sqrt(L)), keeps rows at a measurement
    // noise floor from being raised to the signal's weight.
    const Eigen::VectorXd& unweighted = svd.singularValues();
    const double floor_value = median(std::vector<double>(unweighted.data() + columns / 2, unweighted.data() + columns));
    const double floor_norm = o.noise_factor * floor_value / std::sqrt(static_cast<double>(hankel.rows())) *
                              std::sqrt(static_cast<double>(columns));
    for (Eigen::Index row = 0; row < hankel.rows(); ++row) {
      const double norm = std::max(hankel.row(row).norm(), floor_norm);
      if (norm > 0.0) hankel.row(row) /= norm;
    }
    svd = right_singular(hankel);
  }
  const Eigen::VectorXd& values = svd.singularValues();
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
  const Eigen::MatrixXd v = svd.matrixV().leftCols(static_cast<Eigen::Index>(n));
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
  r.singular_values = whole.singular_values;
  r.noise_floor = whole.noise_floor;
  r.columns = whole.columns;
  r.rows = whole.rows;
  r.residual = whole.residual;
  r.residual_correlation = whole.residual_correlation;
  r.channel_residual = whole.channel_residual;
  r.modes = std::move(whole.modes);
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
  const auto band_of = [&](double frequency) {
    return options.neutral_per_period * (frequency > 0.0 ? frequency : 1.0 / record);
  };
  if (r.lambda_mode) {
    r.lambda = r.modes[*r.lambda_mode].sigma;
    r.lambda_mode_frequency = r.modes[*r.lambda_mode].frequency;
  }
  // Step 7: each half on its own. A half its modes describe (a decay gone into its noise floor is not) gives
  // its own lambda; the second half's replaces the whole record's when it is larger beyond the neutral band:
  // the least damped mode is what a motion ends with, and a record that starts with a larger, faster or
  // nonlinear transient can hide it from the whole record's strongest modes.
  if (options.check_halves && r.linear) {
    const std::size_t half = n / 2;
    try {
      const Identified a = identify(data, 0, half, r.stride, series.dt, options.order, options);
      const Identified b = identify(data, n - half, half, r.stride, series.dt, options.order, options);
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
  if (floor.index == 0) return identify_record(series, options);
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
    for (const Mode& m : result.modes) {
      const double omega = 2.0 * std::numbers::pi * m.frequency;
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double t = static_cast<double>(i) * result.dt;
        const double wave = m.nyquist ? std::cos(std::numbers::pi * static_cast<double>(i) / static_cast<double>(result.stride))
                                      : m.cos_coefficient[c] * std::cos(omega * t) + m.sin_coefficient[c] * std::sin(omega * t);
        x[i] += std::exp(m.sigma * (t - m.reference_time)) * (m.nyquist ? m.cos_coefficient[c] * wave : wave);
      }
    }
    out.push_back(std::move(x));
  }
  return out;
}

}  // namespace mlce
