#pragma once
// Rosenstein's mean log-divergence curve (paper 001 eqs. 18-23), kept apart from its fit.
#include <limits>
#include <string>
#include <vector>

#include "mlce/series.hpp"

namespace mlce {

struct RosensteinOptions {
  std::size_t dim = 3;      ///< embedding dimension m
  std::size_t delay = 1;    ///< reconstruction delay J, samples
  std::size_t theiler = 1;  ///< |j - jhat| > theiler (eq. 20), samples
  std::size_t horizon = 100;  ///< curve computed for i = 0..horizon
  /// Reference points j (evenly strided over all admissible points); 0 = every point. The
  /// kd-tree always holds every admissible point, so neighbours are as close as with all points.
  std::size_t max_references = 0;
  /// Contiguous batches of references for the batch-means confidence interval of the slope.
  std::size_t batches = 16;
  double eps = 0.0;  ///< approximate neighbour search (speed study only); 0 = exact
  void validate() const;
};

/// Smallest series length accepted for these options: (m-1)J + horizon + theiler + 2 samples so
/// that at least a pair of points can be followed for the whole horizon.
std::size_t minimum_length(const RosensteinOptions& options);

struct DivergenceCurve {
  /// y(i) = <ln d_j(i)>, i = 0..horizon: natural log of Euclidean distances between the pair's
  /// points i steps later, averaged over the pairs j (eq. 23 without the 1/dt factor; distances in
  /// units of the channel's standard deviation). Only pairs that can be followed for the whole
  /// horizon are used, so every y(i) averages the same pairs.
  std::vector<double> mean_log_distance;
  std::vector<std::size_t> terms;  ///< terms averaged at each i (pairs minus zero distances)
  /// batch_mean[b][i]: the same average over the b-th contiguous batch of references.
  std::vector<std::vector<double>> batch_mean;
  std::size_t pairs = 0;
  std::size_t references = 0;
  std::size_t admissible_points = 0;
  std::size_t zero_distance_terms = 0;  ///< d_j(i) = 0 terms left out of the average (never log 0)
  std::size_t zero_distance_candidates = 0;
  /// <ln d> over unrelated pairs of embedded points (deterministic pseudo-random pairs, more than
  /// a Theiler window apart): the level a chaotic divergence saturates at, the attractor's scale in
  /// the same units as mean_log_distance. NaN when not computed.
  double attractor_log_distance = std::numeric_limits<double>::quiet_NaN();
  double dt = 1.0;
  std::vector<std::string> warnings;
};

DivergenceCurve divergence_curve(const Series& series, const RosensteinOptions& options);

}  // namespace mlce
