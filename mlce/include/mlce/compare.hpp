#pragma once
// Agreement of two time histories of the same quantity (e.g. blade 3's lag from MBDyn and from the
// ad-hoc model): B is interpolated linearly onto A's samples inside the common time span and the
// window [from, to]; reported are the largest and RMS difference, each history's range (max - min,
// the limit-cycle amplitude measure of paper 001 Fig. 9) and their relative difference.
#include <limits>
#include <string>
#include <vector>

namespace mlce {

struct HistoryComparisonOptions {
  double from = -std::numeric_limits<double>::infinity();
  double to = std::numeric_limits<double>::infinity();
};

struct HistoryComparison {
  std::size_t points = 0;  ///< samples of A compared
  double t_first = 0.0, t_last = 0.0;
  double max_abs_difference = 0.0, time_of_max = 0.0;
  double rms_difference = 0.0;
  double min_a = 0.0, max_a = 0.0, min_b = 0.0, max_b = 0.0;
  double range_relative_difference = 0.0;  ///< |range_b - range_a| / range_a (0/0 -> 0)
  std::vector<std::string> warnings;
};

/// Throws std::invalid_argument when a time vector is not increasing, sizes differ, values are not
/// finite, or the histories share fewer than 2 samples in the window.
HistoryComparison compare_histories(const std::vector<double>& time_a, const std::vector<double>& a,
                                    const std::vector<double>& time_b, const std::vector<double>& b,
                                    const HistoryComparisonOptions& options = {});

}  // namespace mlce
