#pragma once
// Rosenstein's mean log-divergence curve (paper 001 eqs. 18-23), kept apart from its fit.
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mlce/neighbours.hpp"
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
  /// Neighbour candidates within this share of the reference point's own size repeat it and are
  /// passed over like exact zeros (NeighbourOptions::repeat_resolution). An exactly periodic signal
  /// written to full precision repeats only to the rounding of how it was computed (sin(2 pi i/100):
  /// ~1e-13); its pairs at that level followed the rounding's own drift (a 5000-sample sine read
  /// lambda x period = +0.047, beyond the neutral band) instead of the motion (now a sample of
  /// phase apart: a flat curve, lambda x period ~ 1e-6). No motion puts neighbours that close.
  double repeat_resolution = 1e-10;
  /// Sampled flows: move each neighbour along its own trajectory by the fraction of a sample
  /// (linear interpolation, within one sample either way) that brings it closest to the reference,
  /// and follow it from there. The part of the initial separation along the flow belongs to the
  /// flow's zero exponent: it neither grows nor decays and aligns with the unstable direction only
  /// at the rate lambda_1, so while it is comparable to the transverse part it holds the curve's
  /// slope below lambda_1 (Roessler x at dt = 0.1: ~0.8 lambda_1 over its whole linear region).
  /// Meaningless for maps: the points between two samples are not on the attractor.
  bool align_phase = false;
  /// How a neighbour's trajectory is read between its samples when align_phase moves it.
  /// linear: the straight segment between two samples (error f(1-f)/2 dt^2 |x''|, ~(omega dt)^2 / 8
  /// of the amplitude at most); cubic: the Lagrange cubic through the four samples around it
  /// (error ~(omega dt)^4 / 128), the phase then chosen on the cubic itself (Brent's minimiser over
  /// the two sample intervals around the neighbour). Pairs within two samples of the series'
  /// ends keep the linear segment.
  enum class Interpolation { linear, cubic };
  Interpolation interpolation = Interpolation::linear;
  /// White measurement noise per channel, its standard deviation in units of the channel's own
  /// standard deviation (the units of the curve's distances); empty = none. When given, the curve
  /// is also computed noise-compensated (DivergenceCurve::compensated_log_distance).
  std::vector<double> noise_deviation;
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
  /// The series repeats its points at least once per reference, not as whole stretches: its
  /// resolution (quantum or printed digits) is as coarse as the neighbour distances, which jump in
  /// steps of it (a warning says so; the estimate marks lambda unreliable).
  bool coarse_resolution = false;
  bool phase_aligned = false;           ///< neighbours were moved along their trajectories (align_phase)
  double mean_phase_shift = 0.0;        ///< mean |shift| of the neighbours, samples (align_phase)
  std::size_t cubic_pairs = 0;          ///< pairs followed on the cubic (Interpolation::cubic)
  /// <ln d> over unrelated pairs of embedded points (deterministic pseudo-random pairs, more than
  /// a Theiler window apart): the level a chaotic divergence saturates at, the attractor's scale in
  /// the same units as mean_log_distance. NaN when not computed.
  double attractor_log_distance = std::numeric_limits<double>::quiet_NaN();
  /// With RosensteinOptions::noise_deviation: y_c(i) = ln(<(d_j(i)^2 - n_j(i)) / w_j>) / 2, the log
  /// of the pairs' mean squared distance less the mean square that independent white noise adds to
  /// it, each pair over its own mean square along the curve, w_j = <d_j(i)^2>_i (so that every pair
  /// weighs alike, as in <ln d>; unweighted, the pairs of largest amplitude - a decay's first turns,
  /// where a faster mode still lives - would decide alone). The noise of a pair's two points at one
  /// coordinate adds n = sum_c s_c^2 (1 + the neighbour's interpolation weights squared) in
  /// expectation where the coordinate's samples are fresh; the coordinates whose samples the
  /// neighbour search compared (step i = k x delay, k < m: the search picked the pair for a small
  /// distance, noise included) enter as observed, so step 0 is the plain mean square. For a linear
  /// motion (a decay, a slow growth) every pair's separation follows the same linear map, and the
  /// curve then falls at the rate <ln d> (eq. 23) does without noise, while the noise no longer
  /// holds it up. Empty when not computed, or when the compensated mean square is not positive at
  /// some step (compensation_failed_step: the noise exceeds what the pairs hold there).
  /// compensated_batch_mean: the same per batch of references (NaN where not positive).
  std::vector<double> compensated_log_distance;
  std::vector<std::vector<double>> compensated_batch_mean;
  std::optional<std::size_t> compensation_failed_step;
  /// With compensated_log_distance: at every step, the noise's expected share of the pairs' (weighted)
  /// mean square, sum n_j / w_j over sum d_j^2 / w_j, in [0, 1). It says how much the compensated curve
  /// rests on the noise's measured level: a relative error e of the noise's mean square moves y_c(i) by
  /// -e/2 x share / (1 - share) (to first order), so the slope fitted over a region moves by e times the
  /// slope of that curve over it (noise_level_sensitivity).
  std::vector<double> compensated_noise_share;
  double dt = 1.0;
  std::vector<std::string> warnings;
};

/// How the slope of a noise-compensated curve over steps [first, last] moves, per step, per unit
/// relative error of the noise's measured mean square: the least-squares slope of
/// -share(i) / (2 (1 - share(i))) over the region (DivergenceCurve::compensated_noise_share; first
/// order in the error). 0 when the curve carries no shares.
double noise_level_sensitivity(const DivergenceCurve& curve, std::size_t first, std::size_t last);
/// The per-step curve whose slope noise_level_sensitivity fits: -share(i) / (2 (1 - share(i))) at every
/// step of a compensated curve, empty when it carries no shares. For callers that fit it over many
/// regions.
std::vector<double> noise_level_shift(const DivergenceCurve& curve);

/// Reference points of a curve and the nearest neighbour of each (eq. 18 with the Theiler
/// exclusion of eq. 20), found for the options' m, delay, horizon and Theiler window.
struct NeighbourPairs {
  std::vector<std::uint32_t> references;
  NeighbourResult nearest;
  std::size_t dim = 0, delay = 0, horizon = 0, theiler = 0;
};

NeighbourPairs find_pairs(const Series& series, const RosensteinOptions& options);

/// Mean ln distance between unrelated embedded points (DivergenceCurve::attractor_log_distance): up to
/// 20000 deterministic pseudo-random pairs more than `theiler` samples apart. NaN when no such pair
/// has a positive distance.
double attractor_log_distance(const DelayEmbedding& points, std::size_t theiler);

/// find_pairs for several horizons over one neighbour index: built for options.horizon, whose
/// admissible points include those of every longer horizon (the adaptive horizon's doublings
/// rebuilt the kd-trees at every pass). find(H) gives what find_pairs with horizon H gives.
class PairFinder {
 public:
  PairFinder(const Series& series, const RosensteinOptions& options);
  ~PairFinder();
  PairFinder(const PairFinder&) = delete;
  PairFinder& operator=(const PairFinder&) = delete;
  NeighbourPairs find(std::size_t horizon) const;  ///< horizon >= options.horizon

 private:
  struct State;
  RosensteinOptions options_;
  std::size_t points_ = 0;  // M (eq. 17)
  std::unique_ptr<State> state_;
};

/// Where follow_pairs follows each pair's neighbour from, one entry per reference of the pairs:
/// the sample `base` and the `fraction` of the way to the next sample (the phase closest to the
/// reference when align_phase moves the neighbour; else the neighbour itself, fraction 0), and
/// whether it is read on the cubic through the samples around it (Interpolation::cubic). Distances
/// i steps on are then those of DelayEmbedding::squared_distance_between(j + i, base + i, fraction)
/// over the series in unit-deviation coordinates (linear phases). For diagnostics that follow the
/// pairs one by one (bench/start_up_origin).
struct NeighbourPhases {
  std::vector<std::size_t> base;
  std::vector<double> fraction;
  std::vector<char> cubic;
  double shift_sum = 0.0;  ///< sum over the pairs of |base + fraction - neighbour|, samples
};

NeighbourPhases neighbour_phases(const Series& series, const RosensteinOptions& options, const NeighbourPairs& pairs);

/// Where along its own sampled trajectory neighbour `jn` comes closest to point `j` (align_phase,
/// linear): on the segments [jn - 1, jn] and [jn, jn + 1] by least squares, f = (p_j - p_a).(p_{a+1} -
/// p_a) / |p_{a+1} - p_a|^2 clamped to [0, 1]; a segment whose end cannot be followed for `horizon`
/// more steps within the embedding `all` is not tried. {jn, 0} when neither segment comes closer.
struct SegmentPhase {
  std::size_t base = 0;   ///< the sample the phase lies after
  double fraction = 0.0;  ///< of the way to the next sample, [0, 1]
};
SegmentPhase closest_phase_on_segments(const DelayEmbedding& all, std::size_t j, std::size_t jn, std::size_t horizon);

/// A curve's mean_log_distance, terms and batch_mean from its batches of references: per batch and
/// step the sum of the log distances and its count of terms. The curve at a step is the batches' sums
/// added (compensated) over their terms, each batch's own mean NaN where it has no term. Returns the
/// first step where no batch has a term (the curve is then incomplete), nullopt when none.
std::optional<std::size_t> mean_over_batches(const std::vector<std::vector<double>>& batch_sum,
                                             const std::vector<std::vector<std::size_t>>& batch_terms,
                                             DivergenceCurve& curve);

/// The curve of given pairs (e.g. the same pairs with and without align_phase, one search).
DivergenceCurve follow_pairs(const Series& series, const RosensteinOptions& options, const NeighbourPairs& pairs);

/// find_pairs + follow_pairs.
DivergenceCurve divergence_curve(const Series& series, const RosensteinOptions& options);

/// The pairs' first step against their starting distance: the pairs whose distances d(0) and d(1)
/// (one step on, unit-deviation coordinates as in the curve) are both positive, sorted by d(0) and
/// cut into `groups` groups of equal count; per group the mean ln d(0) and ln d(1). A map stretches
/// a pair by its derivative along the pair's direction whatever the (small) distance, so its one-step
/// stretch <ln d(1) - ln d(0)> hardly depends on d(0); measurement noise does not follow the map, and
/// a pair chosen for a small d(0) one step on has the noise's distance, independent of d(0), so the
/// closest pairs' stretch rises as 1/d(0) (a slope of -1 against ln d(0)). Henon x, N = 10^4, the
/// closest half of 8 groups of the estimator's pairs: clean -0.01 .. 0.00 (m = 2); with white noise
/// of 0.1 % of its standard deviation -0.80 .. -0.81 (m = 2), of 1 % -0.75 .. -0.85 (m = 3)
/// (bench/map_bands noise).
struct StretchByDistance {
  std::vector<double> log_distance;  ///< <ln d(0)> per group, increasing
  std::vector<double> log_next;      ///< <ln d(1)> per group
  std::size_t pairs = 0;             ///< pairs with d(0) > 0 and d(1) > 0
  /// Least-squares slope of <ln d(1) - ln d(0)> against <ln d(0)> over the closest half of the groups
  /// (at least 2); NaN when fewer than 2 groups of kMinStretchGroupPairs pairs each.
  double closest_half_slope = std::numeric_limits<double>::quiet_NaN();
};
/// A group of StretchByDistance holds at least this many pairs (a mean of ln d(1) to ~0.1 at the
/// spread of a map's stretches).
inline constexpr std::size_t kMinStretchGroupPairs = 25;
StretchByDistance stretch_by_distance(const Series& series, const RosensteinOptions& options, const NeighbourPairs& pairs,
                                      std::size_t groups = 8);

}  // namespace mlce
