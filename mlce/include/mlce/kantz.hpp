#pragma once
// Kantz's divergence curves (H. Kantz, Phys. Lett. A 185, 77-87, 1994; TISEAN's lyap_k): a second
// estimate of the MLCE from the same series, beside Rosenstein's curve (paper 001 eqs. 18-23).
// Rosenstein follows each reference point's one nearest neighbour (eq. 23: <ln d_j(i)>); Kantz
// follows every neighbour within a radius eps and averages their distances before the log:
//
//   S(eps, i) = < ln < |x_{n+i} - x_{j+i}| >_{j in U(n)} >_n,
//   U(n) = { j : |x_n - x_j| < eps, |n - j| > Theiler window, x_j no repeat of x_n },
//
// over the references n whose neighbourhood U(n) is not empty. |.| is the Euclidean norm of the
// delay vectors (as TISEAN's lyap_k and this project's Rosenstein curve; Kantz's paper takes the
// difference of the last coordinate alone), the channels in units of their standard deviation;
// natural log. Where the neighbourhoods are small against the attractor, S grows at lambda_1 per
// sample whatever eps: the curves of several radii run parallel over their linear region, the
// method's own check, and a slope that changes with eps says the region is not one of exponential
// divergence. Averaging a neighbourhood before the log follows what the neighbourhood does as a
// whole, where Rosenstein's single pair also carries that pair's own (selection-biased) start.
#include <cstddef>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/fit.hpp"
#include "mlce/progress.hpp"
#include "mlce/reading.hpp"
#include "mlce/rosenstein.hpp"
#include "mlce/series.hpp"

namespace mlce {

struct KantzOptions {
  std::size_t dim = 3;      ///< embedding dimension m
  std::size_t delay = 1;    ///< reconstruction delay J, samples
  std::size_t theiler = 1;  ///< |n - j| > theiler (eq. 20), samples
  std::size_t horizon = 100;  ///< S computed for i = 0..horizon
  /// Neighbourhood radii eps, in the curves' units (Euclidean distance of delay vectors whose channels
  /// are in units of their standard deviation), increasing. Empty = automatic: radius_count radii,
  /// the first the median distance from the references to their nearest admissible neighbour rounded
  /// up to two significant digits (about half the references then have a neighbourhood), each next
  /// radius_factor x the one before.
  /// TISEAN's lyap_k takes 5 radii from 1/1000 to 1/100 of the data's range, in two dimensions; a
  /// fixed share of the range holds no neighbour at all in a higher embedding of a short series.
  std::vector<double> radii;
  std::size_t radius_count = 4;
  double radius_factor = 2.0;
  /// Reference points n, evenly strided over the admissible ones; 0 = all. 4000: the batch means of
  /// 16 batches then average 250 neighbourhoods each, and a curve costs a fifth of all 2 x 10^4.
  std::size_t max_references = 4000;
  /// Neighbours averaged per reference and radius, at most: a larger neighbourhood is thinned to this
  /// many, evenly strided in time (not the closest ones, which would shrink the radius it stands for).
  /// A near-periodic motion brings thousands of passes within eps of each point. 0 = all.
  std::size_t max_neighbours = 64;
  /// Contiguous batches of references for the batch-means interval of the fitted slopes.
  std::size_t batches = 16;
  /// Candidates within this share of the reference point's size repeat it and are no neighbours
  /// (RosensteinOptions::repeat_resolution).
  double repeat_resolution = 1e-10;
  /// Move each neighbour along its own sampled trajectory to the sub-sample phase closest to its
  /// reference before following it (RosensteinOptions::align_phase, linear: closest_phase_on_segments).
  /// automatic: as the estimate's reported curve in estimate_kantz (its phase alignment is for sampled
  /// flows whose curve saturates, and there Kantz's plain neighbourhoods read Roessler x at ~0.83 lambda_1,
  /// aligned ~1.04: bench/kantz_vs_rosenstein); kantz_curves alone aligns only when `on`.
  PhaseAlignment phase_alignment = PhaseAlignment::automatic;
  ProgressCallback progress;  ///< after each radius
  void validate() const;
};

struct KantzCurve {
  double radius = 0.0;  ///< eps, in the curve's units
  /// S(eps, i), i = 0..horizon, in DivergenceCurve's form, so that the estimate's fit rule reads it
  /// as it reads eq. 23's curve: mean_log_distance = S, batch_mean per batch of references, pairs =
  /// references with a neighbourhood, terms per step, attractor_log_distance (the saturation level).
  DivergenceCurve curve;
  double mean_neighbours = 0.0;  ///< neighbours averaged per reference with a neighbourhood (after thinning)
  std::size_t thinned = 0;       ///< neighbourhoods thinned to max_neighbours
};

/// The curves of every radius that gives at least one reference a neighbourhood (a radius that gives
/// none is left out, with a warning in `warnings`); InputError when no radius does, or the series is
/// too short for m, J, the horizon and the Theiler window. Queries run on all cores; the result does
/// not depend on the thread count.
struct KantzCurves {
  std::vector<KantzCurve> curves;
  /// Median distance from the references to their nearest admissible neighbour (the automatic radii's
  /// base), in the curves' units.
  double nearest_distance = 0.0;
  std::vector<std::string> warnings;
};
KantzCurves kantz_curves(const Series& series, const KantzOptions& options);

struct KantzRadius {
  KantzCurve kantz;
  FitResult fit;
  double lambda = 0.0;                     ///< per time unit (slope / dt)
  double ci95_low = 0.0, ci95_high = 0.0;  ///< per time unit
};

struct KantzResult {
  std::vector<KantzRadius> radii;
  /// Median over the radii of their lambda (per time unit; of the middle two, their mean), and its
  /// per-sample value; the smallest and the largest.
  double lambda = 0.0, lambda_per_sample = 0.0;
  double lambda_low = 0.0, lambda_high = 0.0;
  double nearest_distance = 0.0;  ///< KantzCurves::nearest_distance
  std::size_t dim = 1, delay = 1, theiler = 1, horizon = 0;
  std::size_t first_sample = 0, n_points = 0;  ///< the samples analysed: those of the estimate
  double dt = 1.0;
  std::string time_unit;
  bool phase_aligned = false;  ///< the neighbourhoods were moved to their references' phase
  /// The estimate's lambda from Rosenstein's curve treated as the neighbourhoods were (per time unit):
  /// phase-aligned or plain as they, never noise-compensated (Kantz's mean distances carry measurement
  /// noise as eq. 23's do): MlceResult::lambda, or its unaligned_lambda / uncompensated_lambda when the
  /// reported curve was treated otherwise. rosenstein_curve names it: "phase-aligned" or "plain".
  double rosenstein_lambda = 0.0;
  std::string rosenstein_curve;
  double reported_lambda = 0.0;  ///< MlceResult::lambda
  /// Which curve the estimate reports (reported_lambda): "plain", "phase-aligned" or "noise-compensated".
  std::string reported_curve;
  /// The reading's neutral band as a rate (ReadingOptions::neutral_per_period x the mean frequency, per
  /// time unit): rates within it of 0 read neutral, so two rates within twice it may both read so.
  double neutral_band = 0.0;
  /// |lambda - rosenstein_lambda| within the larger of: the two 95 % intervals' half-widths added (the
  /// estimate's when rosenstein_lambda is the reported one, and the median radius'), 5 % of the
  /// larger magnitude, twice the neutral band.
  bool agrees = false;
  std::vector<std::string> warnings;
};

/// Kantz's curves over the samples `estimate` analysed (MlceResult::skipped_start on, n_points of
/// them), with its embedding, Theiler window and horizon (options' own are replaced), each fitted by
/// the estimate's rule with the estimate's fit options (MlceResult::fit_options), the region extended to
/// the whole FitOptions::min_periods (extension_straightness 0: see kantz.cpp). The neighbourhoods are
/// phase-aligned as the estimate's reported curve is (KantzOptions::phase_alignment automatic); noise
/// is never compensated, and the samples are read as given (an estimate's MlceOptions::dither is not
/// repeated).
KantzResult estimate_kantz(const Series& series, const MlceResult& estimate, KantzOptions options);

}  // namespace mlce
