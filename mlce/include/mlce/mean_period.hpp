#pragma once
// Mean frequency of the power spectrum and the mean period (paper 001 eq. 19), the default
// Theiler window of the neighbour search (eq. 20).
#include <string>
#include <vector>

#include "mlce/series.hpp"

namespace mlce {

enum class SpectralWindow { rectangular, hann };

struct MeanPeriodOptions {
  /// Taper applied before the FFT. Hann (default) limits leakage of strong low-frequency
  /// content; for a sinusoid on a Fourier bin both windows give its exact frequency.
  SpectralWindow window = SpectralWindow::hann;
  /// Upper clamp of the mean period as a fraction of the series length (a window wider than this
  /// leaves too few neighbour candidates). Clamping is reported as a warning.
  double max_fraction = 0.25;
  void validate() const;
};

/// A series whose mean period (eq. 19) is shorter than this many samples is treated as a map (or a
/// flow sampled too coarsely to interpolate between samples): no phase alignment (estimate.hpp),
/// its curve held to FitOptions::map_straightness (fit.hpp), and no AMI minimum beyond its mean
/// period taken for the delay (AmiOptions::mean_period).
inline constexpr std::size_t kMinFlowPeriod = 8;

struct MeanPeriodResult {
  /// Power-weighted mean frequency sum(P_k f_k)/sum(P_k) over the one-sided periodogram of the
  /// mean-removed series, DC bin excluded; in cycles per time unit. For several channels, the
  /// largest of the channels' values (eq. 19: max over the columns).
  double mean_frequency = 0.0;
  double mean_frequency_per_sample = 0.0;   ///< cycles per sample
  std::vector<double> channel_frequency;    ///< per channel, cycles per time unit
  /// ceil(fs / mean_frequency) in samples (eq. 19), after clamping to [1, max_fraction * N].
  std::size_t mean_period = 1;
  bool clamped = false;
  std::vector<std::string> warnings;
};

MeanPeriodResult estimate_mean_period(const Series& series, const MeanPeriodOptions& options);

}  // namespace mlce
