#pragma once
// Turns the command line's file and column options into a uniform mlce::Series.
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mlce/reader/channel_set.hpp"
#include "mlce/series.hpp"

namespace mlce::cli {

struct SeriesInput {
  std::string file;
  /// Column files: 1-based numbers or names from the file's header line; empty: the file's only
  /// column (or, in a two-column file with a time column, the other one).
  std::vector<std::string> columns;
  std::vector<std::string> channels;       ///< channel specs (node:, joint:, rel:, EXT:, col:)
  std::optional<std::string> time_column;  ///< 1-based number or header name
  std::optional<double> dt;
  std::string time_unit = "s";
  bool resample = false;
  std::string from;  ///< "", a time, or "auto"
  std::optional<double> to;
  /// The channels are estimated one by one (--each): a constant channel (a constrained component
  /// MBDyn writes as zeros) is that channel's error, not the file's; --from auto then finds the
  /// transient on the channels that move.
  bool constant_channels_allowed = false;
  /// --despike: isolated spikes (mlce::find_isolated_spikes) are replaced by the line between their
  /// neighbours, with a warning each, instead of refused.
  bool despike = false;
  /// The user gave no start time (none, or `--from auto`, itself a transient rule): the estimator
  /// may still leave out a start that does not recur (MlceOptions::skip_nonrecurrent_start).
  bool start_is_automatic() const { return from.empty() || from == "auto"; }
};

struct LoadedSeries {
  Series series;
  std::vector<std::string> warnings;
  std::string transient_rule;  ///< how --from auto decided, when used
  /// When --from / --to cut a window: each channel's largest deviation over the record read
  /// (MlceOptions::record_deviation: does the window lie in the floor of a decay?). Empty otherwise.
  std::vector<double> record_deviation;
};

/// The channels of an MBDyn prefix / NetCDF file (or col:K of a column file) with their time;
/// `options.until` leaves out a solver set's later steps.
reader::ChannelSet load_channels(const std::string& file, const std::vector<std::string>& specs,
                                 const reader::ReadOptions& options = {});

/// The options' own mistakes, whatever the file (a channel spec's syntax, --time-column with --dt,
/// a --from that is no time): throws OptionError. load_series checks them first; a command that
/// reads several files checks them once, so that what is left to go wrong is the file's.
void check_series_options(const SeriesInput& in);

/// Throws std::runtime_error with a one-line message naming the file (and line) on bad input, and
/// OptionError when the options do not fit the file (or at all: check_series_options).
LoadedSeries load_series(const SeriesInput& in);

/// Runs an estimation stage on a series loaded from `in`: an InputError it raises about the data
/// (too short for the parameters, too few mean periods, ...) becomes a data error naming the file.
template <class Stage>
auto on_file(const SeriesInput& in, Stage&& stage) -> decltype(stage()) {
  try {
    return stage();
  } catch (const InputError& e) {
    throw std::runtime_error(in.file + ": " + e.what());
  }
}

}  // namespace mlce::cli
