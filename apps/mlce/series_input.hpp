#pragma once
// Turns the command line's file and column options into a uniform mlce::Series.
#include <optional>
#include <string>
#include <vector>

#include "mlce/series.hpp"

namespace mlce::cli {

struct SeriesInput {
  std::string file;
  std::vector<std::size_t> columns;        ///< 1-based; empty: the file's only column
  std::optional<std::size_t> time_column;  ///< 1-based
  std::optional<double> dt;
  std::string time_unit = "s";
  bool resample = false;
  std::string from;  ///< "", a time, or "auto"
  std::optional<double> to;
};

struct LoadedSeries {
  Series series;
  std::vector<std::string> warnings;
  std::string transient_rule;  ///< how --from auto decided, when used
};

/// Throws std::runtime_error with a one-line message naming the file (and line) on bad input.
LoadedSeries load_series(const SeriesInput& in);

}  // namespace mlce::cli
