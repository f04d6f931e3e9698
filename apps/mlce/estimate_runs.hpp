#pragma once
// mlce estimate RUN1 RUN2 ...: the same channel(s) of several runs, one estimate each, as a table.
//
// Paper 001 reads the MLCE of MBDyn runs over a range of rotor speeds (§5, Figs. 11-12): `mlce
// sweep` does that for the ad-hoc models, this for runs made elsewhere. Every run is loaded and
// estimated with the same options; a run that cannot be (missing, too short, ...) keeps its row
// with the error, the others are still estimated, and the command then exits with the data-error
// status, naming every such run on stderr (a script must not take a table with a hole in it for the
// whole answer).
#include <optional>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "series_input.hpp"

namespace mlce::cli {

/// The value of one parameter for each run, in the order the runs are given (--param).
struct RunParameter {
  std::string name;
  std::vector<double> values;
};

/// "NAME=v1,v2,..." or "NAME=first:last:step" (as mlce sweep's --param), `runs` values.
/// Throws std::invalid_argument naming the spec and the counts.
RunParameter parse_run_parameter(const std::string& spec, std::size_t runs);

struct RunsOutput {
  bool json = false;
  bool quiet = false;
  std::string csv_path;   ///< the table as CSV
  std::string plot_path;  ///< lambda and its 95 % interval against the parameter (or the run's number)
};

/// Estimates `input` (its file replaced by each of `files`) with `options`; prints the table (or
/// one JSON object) on stdout. Returns the exit status: 0, or kExitData when a run failed.
int estimate_runs(const std::vector<std::string>& files, const SeriesInput& input, const MlceOptions& options,
                  const std::optional<RunParameter>& parameter, const RunsOutput& output);

}  // namespace mlce::cli
