#pragma once
// Uniformly sampled (possibly multichannel) time series: the only data type the estimators see.
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace mlce {

/// Bad input data. `index` is the 0-based sample index the message is about (npos when the
/// problem is not tied to one sample), so a caller that knows the file can name the line.
class InputError : public std::runtime_error {
 public:
  static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();
  explicit InputError(const std::string& what, std::size_t index = npos)
      : std::runtime_error(what), index_(index) {}
  std::size_t index() const { return index_; }

 private:
  std::size_t index_;
};

/// Bad option value (names the option and the violated constraint).
class OptionError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct Series {
  /// channels[c][i]: sample i of channel c; every channel has the same length.
  std::vector<std::vector<double>> channels;
  /// Sampling step in time units (1 when the series has no time axis: "per sample").
  double dt = 1.0;
  /// Time of sample 0.
  double t0 = 0.0;
  /// Name of the time unit ("s"); empty means the series is indexed by sample only.
  std::string time_unit;
  std::vector<std::string> names;

  std::size_t size() const { return channels.empty() ? 0 : channels.front().size(); }
  std::size_t channel_count() const { return channels.size(); }
  double time(std::size_t i) const { return t0 + dt * static_cast<double>(i); }
};

/// How messages name channel c (0-based): its name when the series has one (a column's header, a
/// channel spec), else "channel c+1".
std::string channel_name(const Series& series, std::size_t c);

/// How a time column becomes a uniform sampling step.
struct SamplingOptions {
  /// Largest accepted |t[i+1]-t[i]-dt| / dt, dt = (t_last - t_0)/(n-1). 1e-2 tolerates the
  /// rounding of times printed with 5-6 significant digits.
  double uniformity_tolerance = 1e-2;
  /// Resample a non-uniform time column onto the uniform grid of its median step (linear
  /// interpolation). Off by default: a non-uniform column is an error.
  bool resample = false;
};

/// Builds a series from an explicit time column (one value per sample). Throws InputError naming
/// the first offending index: fewer than 2 samples, non-increasing time, a non-uniform step
/// (unless options.resample), non-finite values. Times printed with 6 or more significant digits
/// that no longer resolve the step (repeated or uneven at late times) are taken as their
/// least-squares grid when each lies within one unit of its last printed digit of it (series.cpp:
/// grid_within_print), with a warning.
Series make_series_from_time(const std::vector<double>& time, std::vector<std::vector<double>> channels,
                             const SamplingOptions& options, std::vector<std::string>* warnings = nullptr,
                             std::string time_unit = "s");

/// Builds a series with a known sampling step dt > 0.
Series make_series_with_step(std::vector<std::vector<double>> channels, double dt, std::string time_unit = "s");

/// Checks every sample is finite, channels have equal length, and no channel is constant.
/// Throws InputError with the index of the first bad sample.
void validate_series(const Series& series);

/// validate_series but for the constant-channel check: a time history (equal lengths, a normal dt,
/// finite samples, at least two) in which a channel may hold one value throughout (what a reader
/// accepts when the channels are estimated one by one: that channel's own error, not the file's).
void validate_samples(const Series& series);

/// Is channel c constant (every sample equal)?
bool is_constant(const Series& series, std::size_t c);

/// The samples with t0' = time in [from, to] (inclusive, in time units). Throws InputError when
/// the window holds fewer than 2 samples.
Series time_window(const Series& series, double from, double to);

/// The first `count` samples of every channel (count <= size()), with the series' step, start,
/// unit and names.
Series leading_samples(const Series& series, std::size_t count);

/// The given channels (indices < channel_count()), in that order, each named as channel_name names it.
Series channel_subset(const Series& series, const std::vector<std::size_t>& channels);

/// Each channel shifted to zero mean and scaled to unit standard deviation, computed without
/// overflow or underflow for any finite amplitude (1e-300 ... 1e300): the data is first divided
/// by its largest magnitude. All estimators are scale-invariant through this step.
Series standardized(const Series& series);

/// Each channel scaled to unit standard deviation (as standardized) but not shifted: the input for
/// distances, which do not depend on a shift. Shifting by the mean would round every sample smaller
/// than the mean's last digit onto it: a decay that ends 60 decades below its start around a
/// non-zero mean collapsed onto repeated points and read half its exponent.
Series scaled_to_unit_deviation(const Series& series);

/// What scaled_to_unit_deviation divides each channel by: its largest magnitude times the standard
/// deviation of the channel so divided (its largest magnitude for a constant channel, 1 for an
/// all-zero one). A quantity in a channel's units over its divisor is in the curve's units.
std::vector<double> unit_deviation_divisors(const Series& series);

/// Each channel's largest deviation from its mean, in the channel's units (computed over its largest
/// magnitude, as standardized): the scale of a record a window is cut from
/// (MlceOptions::record_deviation). 0 for a constant channel.
std::vector<double> peak_deviations(const Series& series);
/// Each channel's RMS deviation about its mean (its standard deviation), in the channel's units;
/// 0 for a constant channel.
std::vector<double> rms_deviations(const Series& series);

}  // namespace mlce
