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

/// What makes a few samples an isolated spike (a glitch in the record: a corrupt line, a solver
/// step written unconverged) rather than motion. A property of the record, checked where it is
/// read (the CLI refuses or, with --despike, replaces spikes before any window is cut): the
/// estimators do not look for spikes, because a window of a record cannot tell a glitch from the
/// record's own motion at the window's scale (a decay's floor, written with 1e-5 degree resolution,
/// blips by one sample at ten times its other steps). One such sample moves the estimate far: a single
/// sample of 25 in Lorenz x (range -18 .. 19, N = 10^4) read 0.999 instead of 0.948 (its broadband
/// power shifts the mean period, 171 -> 136 samples), one of 1000 read 18.8 1/s, "chaotic"
/// (README, "Isolated spikes", gives the command).
struct SpikeOptions {
  /// The jumps into and out of a spike each exceed this many times every other jump of the
  /// channel (|x[i+1] - x[i]| outside the spikes). On a sampled motion the largest jumps come in
  /// runs of like size (a flow's fastest stretch spans several samples; a map's jumps reach its
  /// range again and again); a glitch's two jumps stand alone. 8: the real MBDyn runs' channels
  /// that are zero to rounding (1e-19, a constrained rotation) blip at one step by 4.4-7.5 times
  /// their other jumps; a glitch that moves Lorenz x's exponent by 5 % jumps 26.7 times.
  double jump_ratio = 8.0;
  /// Longest spike, in samples.
  std::size_t max_length = 3;
  /// Most spikes in one channel: more are a feature of the motion (impacts, bursts), not glitches.
  std::size_t max_count = 4;
};

/// A run of samples [first, last] of one channel that the series jumps into and back out of.
struct IsolatedSpike {
  std::size_t channel = 0;
  std::size_t first = 0, last = 0;  ///< sample indices, inclusive, each max_length + 1 or more from the ends
  double before = 0.0, after = 0.0;  ///< the samples either side (first - 1, last + 1)
  double peak = 0.0;                 ///< the run's sample farthest from the line between them
  double jump_ratio = 0.0;           ///< the smaller of its two jumps over the largest other jump
};

/// The isolated spikes of every channel, by channel and position. A spike lies inside the record:
/// entered by the jump x[first] - x[first - 1] and left by x[last + 1] - x[last], each more than
/// `jump_ratio` times every jump of the channel outside its spikes, with the series back across
/// the run no further than that many ordinary jumps (|x[last + 1] - x[first - 1]| <= (length + 1)
/// x the largest other jump). Nothing within max_length + 1 samples of either end: a fast start (a
/// map's approach to its cycle, a kick, a solver's start-up ringing) or a growth at the end is
/// motion the estimators and the transient rule read. Found only when the
/// channel holds at most max_count such runs, each at most max_length samples long. Jumps are
/// taken over the channel divided by its largest magnitude (no overflow for any finite samples);
/// a sample that is not finite is an InputError naming it.
std::vector<IsolatedSpike> find_isolated_spikes(const Series& series, const SpikeOptions& options = {});

/// Throws InputError naming the first isolated spike (its channel, sample, time, value and jumps;
/// index = its first sample) and how many more there are. Spikes that start before sample
/// `first_analysed` are left alone: the caller analyses a window that starts after them.
void refuse_isolated_spikes(const Series& series, const SpikeOptions& options = {}, std::size_t first_analysed = 0);

/// Replaces every isolated spike by the straight line between the samples either side of it (the
/// time step stays uniform) and returns one message per spike saying what was replaced.
std::vector<std::string> replace_isolated_spikes(Series& series, const SpikeOptions& options = {});

/// validate_series but for the constant-channel check: a time history (equal lengths, a normal dt,
/// finite samples, at least two) in which a channel may hold one value throughout (what a reader
/// accepts when the channels are estimated one by one: that channel's own error, not the file's).
void validate_samples(const Series& series);

/// Is channel c constant (every sample equal)?
bool is_constant(const Series& series, std::size_t c);

/// The samples with t0' = time in [from, to] (inclusive, in time units). Throws InputError when
/// the window holds fewer than 2 samples.
Series time_window(const Series& series, double from, double to);

/// The first sample at time >= from (within 1e-9 of a step, as time_window takes it); size() when none.
std::size_t first_sample_from(const Series& series, double from);

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
