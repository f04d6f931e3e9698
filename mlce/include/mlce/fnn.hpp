#pragma once
// False nearest neighbours (Kennel, Brown & Abarbanel 1992) for the embedding dimension m of
// paper 001 eqs. 15-17.
#include <string>
#include <vector>

#include "mlce/series.hpp"

namespace mlce {

struct FnnOptions {
  std::size_t max_dim = 10;
  /// Kennel's first criterion: |x(i+mJ) - x(j+mJ)| / R_m(i) > rtol marks a false neighbour.
  double rtol = 10.0;
  /// Kennel's second criterion: R_{m+1}(i) / R_A > atol, R_A = standard deviation of the series.
  double atol = 2.0;
  /// Chosen m = first m whose false fraction is below this.
  double threshold = 0.05;
  /// Theiler window (samples) for the neighbour search; the estimator passes the mean period.
  std::size_t theiler = 0;
  /// At most this many query points per m (evenly strided); the kd-tree always holds every point.
  /// 0 = all.
  std::size_t max_queries = 20000;
  /// The kd-tree of each m holds at most this many points, the series' first ones (0 = all). The
  /// trees' build dominates FNN on long series (one per m, single-threaded in nanoflann 1.4): at
  /// N = 10^7 three of them took 14 s. 10^6 points already give the false fractions to well within
  /// the 5 % threshold's resolution; series up to that length are unaffected.
  std::size_t max_points = 1'000'000;
  /// Neighbours within this share of the point's own size are repeats of it, passed over
  /// (NeighbourOptions::repeat_resolution): Kennel's ratio of two rounding errors is noise. An
  /// exactly periodic sine of 100 samples a period, written to 17 digits, repeats to ~1e-13 and
  /// read m = 4 (24 % false at m = 2) with exact zeros only; 1e-10 leaves the rounding of ~10^6
  /// periods' phases behind and is far below any neighbour distance the motion itself gives
  /// (~range / N at m = 1).
  double repeat_resolution = 1e-10;
  /// Stop once the threshold is met (the estimator's use); off: the whole curve up to max_dim.
  bool stop_at_choice = false;
  void validate() const;
};

struct FnnResult {
  /// fraction[m-1]: false-neighbour fraction at dimension m.
  std::vector<double> fraction;
  std::vector<std::size_t> queries;  ///< points tested at each m
  std::vector<std::size_t> points;   ///< points in the kd-tree at each m (FnnOptions::max_points)
  bool capped = false;               ///< the trees held only the series' first max_points points
  std::size_t dim = 1;
  /// false when no m reached the threshold (noise-dominated series): dim is then the m with the
  /// smallest fraction, with a warning.
  bool reached_threshold = true;
  std::size_t zero_distance_pairs = 0;
  std::vector<std::string> warnings;
};

FnnResult estimate_dimension_fnn(const Series& series, std::size_t delay, const FnnOptions& options);

}  // namespace mlce
