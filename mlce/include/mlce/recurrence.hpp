#pragma once
// Does the start of a series recur? Rosenstein's neighbours (eq. 18 with eq. 20) assume every point
// lies on the attractor, which the rest of the series visits again. A start-up transient (Lorenz
// from (1, 1, 1) spirals out of the fixed point C- for its first ~10 time units) is visited once:
// its points find their nearest neighbours only among themselves, on the spiral's neighbouring
// turns, which separate slowly, and the curve reads low (0.855 instead of 0.906). A start-up as
// short as one window is told from a window that dips by distance: the motion never comes near the
// start-up again, while a dip lies among points it visits again (RecurrenceOptions::far).
#include <cstddef>
#include <vector>

#include "mlce/rosenstein.hpp"

namespace mlce {

struct RecurrenceOptions {
  /// Window length in samples; 0 = max(2 x Theiler window, admissible points / 50).
  std::size_t window = 0;
  /// A window's score: the share of its reference points whose nearest neighbour lies after the
  /// window (beyond the Theiler window), over the share of candidate points there: 1 on an
  /// attractor, on average; a transient's windows score ~0, and the windows in which it joins the
  /// attractor somewhere between. A window scoring at least `recurrent` has joined it; one scoring
  /// below `transient` has not.
  double transient = 0.3, recurrent = 0.8;
  /// A series whose first window scores at least this starts on the attractor (an excursion a few
  /// windows in is not a start-up: Roessler x after 500 time units, first window 0.73, then one
  /// below 0.3).
  double first_below = 0.5;
  /// Windows below `transient` needed before the first recurrent one: on an attractor a single
  /// window may dip (it spans only a few mean periods: Roessler x after 500 time units scored 0.21
  /// in its first window and 0.18 in its 18th, ~1 elsewhere); a start-up that lasts shorter than
  /// two windows is not told from such a dip, and is kept.
  std::size_t min_windows = 2;
  /// Windows with fewer reference points (after striding) are not judged.
  std::size_t min_references = 20;
  /// The distance test (recurrent_start given the embedding) tells a start-up that lasts one
  /// window, which the scores alone keep (min_windows), from a window that dips. It runs when the
  /// first window scores below `first_below` and the scores cut nothing. A window's distance ratio:
  /// the median over its points of the distance to the nearest point of the series' second half
  /// (admissible points [A/2, A)), over the same median over points of the first half (up to a
  /// Theiler window before the second). About 1 where the motion passes again; 4.7-10 over the
  /// first four windows of Lorenz's start-up spiral from near the origin (test_recurrence), which
  /// it never comes near again. Of the 128 Lorenz x and 128 Roessler x series of
  /// `finite_time_spread starts`, already on their attractors, one is cut (Lorenz seed 4 #19: its
  /// first window scores 0.00 and two windows stay 7.4 and 3.05 typical distances away, a passage
  /// not made again within its 100 time units). The windows from the start whose ratio is at least
  /// `far` are left out.
  double far = 3.0;
  /// First-half points (evenly strided) whose median distance to the second half is the typical one.
  std::size_t typical_points = 2000;
  /// A reference whose nearest candidate lies at most this far (the search's coordinates: every
  /// channel over its standard deviation; an exact repeat passed over, NeighbourResult::repeated,
  /// counts as distance 0) recurs wherever that neighbour lies: the motion passes there again to the
  /// data's resolution. Negative = off: neighbours judged by their index alone. An exactly periodic
  /// signal finds its neighbours one period on, inside the same window whenever the window spans
  /// more than a period; judged by index alone, sin 2 pi t + 0.5 sin 6 pi t at dt = 0.01, N = 10^4,
  /// lost its first 2618 samples as a "start-up" (test_recurrence prints its windows' scores both
  /// ways). A start-up's points stay a finite distance from
  /// every other point (Lorenz x from (1, 1, 1), N = 10^4: geometric mean of the neighbour distances
  /// 0.015; the 256 series of finite_time_spread starts and those of start_variants credit no point);
  /// 1e-5 is above the rounding of six printed digits (MBDyn's default) on a signal whose mean is
  /// within ~10 deviations of 0. Six printed digits make a periodic signal repeat its points
  /// exactly: its zero distances are passed over and the neighbour found is another phase, but the
  /// exact repeat says the point recurs (cos / sin of period 80 or 100 samples: test_recurrence).
  double repeat_distance = 1e-5;
  void validate() const;
};

struct RecurrenceResult {
  /// First sample of the part analysed: the end of the last window scoring below `transient`
  /// before the first window scoring at least `recurrent` (0 = the series recurs from its start, or
  /// no window recurs clearly and nothing can be told).
  std::size_t start = 0;
  std::size_t window = 0;      ///< window length used, samples
  std::vector<double> ratio;   ///< per window, from the start, over the series' first half
  /// The distance test's ratios (options.far), from the start up to the first window below `far`,
  /// when the test ran; `by_distance` when it decided `start`.
  std::vector<double> distance_ratio;
  bool by_distance = false;
};

/// The rule: consecutive windows from sample 0, while a window ends (with the Theiler window
/// after it) in the first half of the admissible points, so that at least half of the candidates
/// lie after it; for window w, ratio = (share of its references whose neighbour index is >= the
/// window's end + Theiler window, or that repeats: RecurrenceOptions::repeat_distance)
/// / (share of admissible points there). A series whose first window
/// scores below `first_below` does not start on the attractor, and the start that does not recur
/// ends with the last window scoring below `transient` before the first one scoring at least
/// `recurrent`, when at least `min_windows` windows score below `transient` before it: a window in between is where the motion joins the attractor, and is kept; a low
/// window after the first recurrent one is an excursion the series visits once, not a start.
/// `admissible` = number of candidate points of the neighbour search (DelayEmbedding::max_points -
/// horizon). With `embedding` (its first `admissible` points those of the search), a series that
/// does not start on the attractor but whose scores cut nothing is judged by the distance test
/// (RecurrenceOptions::far): its leading windows that stay far from the second half are left out.
RecurrenceResult recurrent_start(const NeighbourPairs& pairs, std::size_t admissible, const RecurrenceOptions& options,
                                 const DelayEmbedding* embedding = nullptr);

/// Does the series' level drift beneath its neighbour pairs? Eq. 18's neighbours are meant to be
/// near in state; when the level of a channel moves over the run (a slow trend, a quantity that
/// creeps), two points Delta samples apart also differ by the level's change over Delta, the same in
/// every delay coordinate. That offset neither grows nor decays, so it holds the divergence curve's
/// start up and flattens it, and the search prefers neighbours close in time. Per channel c, the
/// pairs' mean coordinate difference s_qc (the m delay coordinates of the neighbour minus the
/// reference's, in the search's unit-deviation coordinates) is regressed through the origin on the
/// signed time apart Delta_q: a_c = sum s_qc Delta_q / sum Delta_q^2. That part of every pair's
/// separation, m a_c^2 Delta_q^2 summed, over the pairs' summed squared distances, is the share.
/// Unlike the straight line through the whole series (Drift), it is not fooled by the slow swings a
/// stationary motion makes by chance (Lorenz x over 100 time units: lines of R^2 up to 0.025, whose
/// removal made 16 series read 0.637-0.953 lambda_1), since neighbours are near in state wherever in
/// the swing they lie: at most 0.010 over 240 stationary Lorenz and Roessler series, 8e-4 over 32
/// maps (bench/level_drift).
struct NeighbourDrift {
  double share = 0.0;          ///< summed over the channels, in [0, 1]
  std::size_t channel = 0;     ///< 0-based: the channel whose drift makes most of it
  double rate_per_sample = 0.0;  ///< that channel's drift, its own units per sample
  /// That channel's drift over the analysed series' length, in its standard deviations.
  double over_run_in_deviations = 0.0;
  std::size_t pairs = 0;       ///< pairs it was measured on
};
NeighbourDrift neighbour_drift(const Series& series, const NeighbourPairs& pairs);
/// Above this share the estimator warns that the level creeps beneath the neighbours (bench/level_drift,
/// 16 series each): Lorenz x plus a t (N = 10^4, dt = 0.01), a = 0.002 (0.2 over the run, 2.5 % of x's
/// deviation), gives shares 0.005-0.054 and reads 0.876-1.013 lambda_1 (mean 0.953, 6 warned);
/// Roessler x (dt = 0.1) plus 0.0005 t, 0.065-0.126 and 0.591-0.904 (mean 0.742, all warned).
inline constexpr double kNeighbourDriftShare = 0.02;

}  // namespace mlce
