#pragma once
// Space-time separation plot (Provenzale, Smith, Vio & Murante 1992, Physica D 58, 31-49): for
// each time separation D, the distribution of distances between embedded points D samples apart.
// While D is short, points are close because they lie on the same passage of the trajectory; where
// the low contours stop rising (aside from oscillations), points D apart are no more alike than
// unrelated points. A Theiler window (paper 001 eq. 20) shorter than that lets the neighbour search
// pair points of the same passage, whose separation follows the flow, not the attractor's
// divergence. The estimator's default window is the mean period (eq. 19); this is its check.
// Distances are taken between the points of pairs D apart only (no neighbour search): cost
// O(separations x pairs x m), independent of N beyond max_pairs.
#include <optional>
#include <string>
#include <vector>

#include "mlce/series.hpp"

namespace mlce {

struct SpaceTimeOptions {
  std::size_t dim = 1;    ///< embedding dimension m
  std::size_t delay = 1;  ///< reconstruction delay J, samples
  /// Largest separation D, samples. 0 = automatic: 4 mean periods (eq. 19), at most half the
  /// embedded points.
  std::size_t max_separation = 0;
  /// Spacing of the separations D = step, 2 step, ...; 0 = automatic: ceil(max_separation / 200).
  std::size_t step = 0;
  /// Contour levels: the distance below which this fraction of the pairs D apart lie (each in
  /// (0, 1)). The lowest is the one the decorrelation rule reads: nearest neighbours are the closest
  /// pairs, so it is the low contours that a too-short Theiler window corrupts.
  std::vector<double> fractions = {0.01, 0.1, 0.5};
  /// The series' mean period (eq. 19), samples, when the caller has it; 0 = computed here.
  std::size_t mean_period = 0;
  /// Pairs per separation, evenly strided over the embedded points; 0 = all.
  std::size_t max_pairs = 20000;
  /// Decorrelation rule: the lowest contour's plateau P is its median over the second half of the
  /// separations; the pairs are no longer on the same passage from the first separation at which
  /// that contour reaches decorrelation_level x P. (Beyond it the contours of a flow keep
  /// oscillating: points one revolution apart can be close again. Those are neighbours from
  /// another passage, which Rosenstein's method needs, not temporal correlation.)
  double decorrelation_level = 0.5;
  void validate() const;
};

struct SpaceTimeResult {
  std::vector<std::size_t> separation;  ///< D, samples
  std::vector<double> fractions;        ///< contour levels, ascending, each once
  /// contour[k][s]: distance (Euclidean, embedded, in units of each channel's standard deviation,
  /// as the divergence curve) below which fractions[k] of the pairs separation[s] apart lie. The
  /// order statistic at rank floor(fraction x (pairs - 1)) (no interpolation).
  std::vector<std::vector<double>> contour;
  std::vector<std::size_t> pairs;  ///< pairs evaluated at each separation
  double plateau = 0.0;            ///< median of the lowest contour over the second half of the separations
  /// First separation at which the lowest contour reaches decorrelation_level x plateau, samples.
  std::size_t decorrelation = 0;
  double decorrelation_level = 0.5;  ///< the option it was found with
  /// amplitude_ratio (transient.hpp): RMS of the last third over the first. The plot assumes a
  /// stationary motion; one that does not persist (transient.hpp: persists, within (1/2, 2)) is
  /// flagged, not interpreted.
  double amplitude_ratio = 1.0;
  bool stationary = true;
  std::size_t mean_period = 0;  ///< eq. 19, samples: the estimator's automatic Theiler window
  std::size_t dim = 1, delay = 1;
  std::vector<std::string> warnings;
};

/// The space-time separation plot of `series` (all channels embedded jointly).
SpaceTimeResult space_time_separation(const Series& series, const SpaceTimeOptions& options);

}  // namespace mlce
