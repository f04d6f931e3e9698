#pragma once
// Is the run long enough? The MLCE of the run's leading parts, k/parts of it for k = 1..parts.
// Paper 001 (§3.2, Fig. 6) shows an estimate that still moves with the simulated time: it is not
// yet the exponent of the attractor, and a longer run is the only cure. This is the check an
// analyst makes before trusting one number: does lambda settle as the run grows?
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"

namespace mlce {

struct ConvergenceOptions {
  /// The series is estimated on its first k/parts, k = 1..parts (the last is the whole run).
  std::size_t parts = 8;
  /// Options of every estimate. Parameters left automatic are re-estimated for each part, as they
  /// would be for a shorter run.
  MlceOptions estimate;
  /// Verdict: the estimates of the parts k >= parts/2 (half the run and more) agree with the whole run's
  /// when |lambda_k - lambda| <= max(half-width_k, half-width, relative_tolerance x |lambda|,
  /// frequency_tolerance x mean frequency), the half-widths being those of the two 95 % intervals.
  /// (A part shares its samples with the run: their difference scatters less than either; the
  /// sum of the half-widths would pass the drift of paper 001 Fig. 6, whose intervals are wide.)
  /// The batch-means intervals hold the curve's noise, not the fit region's choice, so a part may
  /// differ by a few % where the intervals are narrow (Lorenz x at N = 10^5 from (1, 1, 1): 0.925
  /// +- 0.020 over the first half, 0.894 +- 0.013 over all): 5 % is settled. The last term is the resolution of lambda ~ 0: an
  /// amplitude change of 1 % per cycle.
  /// Nor has it settled when each part from half the run on reads further the same way than the one
  /// before and half the run's lambda differs from the whole's by more than that floor (a drift within
  /// intervals it widens: paper 001 Fig. 6 with the floor left in). Over 64 Lorenz x and 64 Roessler x
  /// series of 10^4 samples (`build/convergence_verdicts`: the first two seeds of `build/finite_time_spread
  /// starts`) this clause adds 4 and 5 to the 12 and 11 that the intervals alone call unsettled.
  double relative_tolerance = 0.05;
  double frequency_tolerance = 0.01;
  /// How every part's estimate is read (reading.hpp). The second verdict: the parts k >= parts/2
  /// read the same stability as the whole run, so the run is long enough to say stable, neutral or
  /// unstable, whether or not lambda itself has settled to its tolerance.
  ReadingOptions reading;
  void validate() const;
};

struct ConvergencePoint {
  std::size_t samples = 0;  ///< length of the part
  double t_end = 0.0;       ///< time of its last sample
  bool estimated = false;   ///< false: `error` says why (a part too short for the estimator)
  double lambda = 0.0, ci95_low = 0.0, ci95_high = 0.0;  ///< per time unit
  std::size_t delay = 0, dim = 0, theiler = 0;
  std::size_t warnings = 0;  ///< how many warnings its estimate carried
  Stability stability = Stability::undetermined;  ///< read_stability of its estimate
  std::string motion;                              ///< and the kind of motion it reads
  /// The part lies in the floor a decay ended in before it (MlceResult::in_decay_floor): lambda is
  /// the residue there, not the motion's.
  bool in_decay_floor = false;
  std::string error;
};

struct ConvergenceResult {
  std::vector<ConvergencePoint> points;  ///< ascending length; the last is the whole run
  /// Every part of at least half the run that could be estimated agrees with the whole run's
  /// estimate (ConvergenceOptions' rule).
  bool converged = false;
  /// Every part of at least half the run that could be estimated reads the whole run's stability
  /// (an undetermined part counts as a different reading).
  bool reading_settled = false;
  double tolerance_floor = 0.0;          ///< max(relative x |lambda|, frequency x mean frequency), per time unit
  std::vector<std::string> warnings;     ///< the whole run's estimate's, then the verdict's
};

/// How finely an exponent near `lambda` is resolved, per time unit: max(relative_tolerance x
/// |lambda|, frequency_tolerance x mean_frequency). Two estimates closer than this are one exponent
/// (the verdicts of estimate_convergence and of estimate_each_channel / judge_agreement).
double exponent_resolution(double lambda, double mean_frequency, double relative_tolerance, double frequency_tolerance);

/// Throws what estimate_mlce throws on the whole series; parts too short are recorded, not thrown.
ConvergenceResult estimate_convergence(const Series& series, const ConvergenceOptions& options);

}  // namespace mlce
