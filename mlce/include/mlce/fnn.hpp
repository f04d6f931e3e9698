#pragma once
// The embedding dimension m of paper 001 eqs. 15-17: false nearest neighbours (Kennel, Brown &
// Abarbanel 1992), the estimator's rule, and Cao's averaged false neighbours (1997), a second method.
#include <string>
#include <vector>

#include "mlce/progress.hpp"
#include "mlce/series.hpp"

namespace mlce {

/// The neighbour search Kennel's and Cao's tests share: at each dimension, the nearest neighbour
/// of each query point outside the Theiler window, repeats passed over.
struct DimensionSearchOptions {
  /// Theiler window (samples) for the neighbour search; the estimator passes the mean period
  /// (Cao's paper has none: a flow's temporal neighbours would be its nearest).
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
  /// Called after each dimension with the method's stage and the share of max_dim done (mlce fnn
  /// prints it on long series: 10^6 samples take ~5 s over m = 1..10); empty = silent.
  ProgressCallback progress;
  /// OptionError naming `method` ("fnn", "cao") for a bad repeat resolution or tree cap.
  void validate_search(const std::string& method) const;
};

struct FnnOptions : DimensionSearchOptions {
  std::size_t max_dim = 10;
  /// Kennel's first criterion: |x(i+mJ) - x(j+mJ)| / R_m(i) > rtol marks a false neighbour.
  double rtol = 10.0;
  /// Kennel's second criterion: R_{m+1}(i) / R_A > atol, R_A = standard deviation of the series.
  double atol = 2.0;
  /// Chosen m = first m whose false fraction is below this.
  double threshold = 0.05;
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

// Cao's averaged false neighbours (L. Cao, Physica D 110 (1997) 43-50): a second estimate of m
// that needs no distance tolerances, and a test of determinism. For each dimension d, with n(i, d)
// the nearest neighbour of the delay vector y_i(d) outside the Theiler window,
//   a(i, d) = |y_i(d+1) - y_n(d+1)| / |y_i(d) - y_n(d)|,   E(d) = <a(i, d)>,   E1(d) = E(d+1) / E(d),
//   E*(d) = <|x(i + dJ) - x(n + dJ)|>,                    E2(d) = E*(d+1) / E*(d)
// (Cao's eqs. 1-5, with the kd-tree's Euclidean norm instead of his maximum norm, as
// DelayEmbeddings.jl's default; several channels add one coordinate each per delay, as in FNN).
// E1 rises to 1 and stays there once d unfolds the attractor: m is the first d with
// |1 - E1(d)| <= saturation. E2 = 1 at every d when the next value does not depend on the past
// (white noise); a deterministic series has some d with E2 away from 1. With the Euclidean norm E1
// nears 1 gradually (a(i, d)^2 = 1 + e^2 / R_d^2, and R_d grows with d): m reads a d or two above
// FNN's on the reference systems (README, Definitions), while E1 rises most into their dimension.
struct CaoOptions : DimensionSearchOptions {
  /// E is computed for d = 1..max_dim, E1 and E2 for d = 1..max_dim - 1.
  std::size_t max_dim = 10;
  /// E1(d) within this of 1 is saturated (DelayEmbeddings.jl's `thres` default).
  double saturation = 0.05;
  /// The series looks stochastic when every E2(d) is within this of 1 (the same default there).
  double stochastic_tolerance = 0.05;
  void validate() const;
};

struct CaoResult {
  std::vector<double> e;              ///< e[d-1] = E(d), d = 1..max_dim
  std::vector<double> e1;             ///< e1[d-1] = E1(d) (one fewer than e)
  std::vector<double> e2;             ///< e2[d-1] = E2(d)
  std::vector<std::size_t> queries;   ///< pairs averaged at each d
  std::size_t dim = 1;
  /// false when no E1(d) came within `saturation` of 1: dim is then the d whose E1 is closest to
  /// 1, with a warning.
  bool saturated = true;
  bool looks_stochastic = false;      ///< every E2(d) within stochastic_tolerance of 1
  std::size_t zero_distance_pairs = 0;
  std::vector<std::string> warnings;
};

CaoResult estimate_dimension_cao(const Series& series, std::size_t delay, const CaoOptions& options);

}  // namespace mlce
