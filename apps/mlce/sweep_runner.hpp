#pragma once
// A parameter grid run point by point on several threads, resumable from a journal.
//
// The grid is the Cartesian product of ranges a:b:step, enumerated with the last parameter
// fastest; point k's values are a + i*step (never accumulated). Each point is computed by a
// caller-supplied function returning its CSV cells; a point's result depends only on its values,
// so the output is the same whatever the job count. Every finished point is appended to
// OUT.partial (one flushed and fsync'ed line each, behind a signature of the sweep's
// configuration); a rerun with the same configuration reads it and computes only the missing
// points; the final CSV is written atomically, ordered by point, and the journal removed.
#include <functional>
#include <string>
#include <vector>

namespace mlce::cli {

struct SweepAxis {
  std::string name;
  double first = 0, last = 0, step = 1;
  std::vector<double> values() const;
};

/// "NAME=a:b:step" (or "NAME=a" for a single value). Throws std::invalid_argument naming the spec.
SweepAxis parse_sweep_axis(const std::string& spec);

struct SweepPlan {
  std::vector<SweepAxis> axes;
  std::vector<std::string> result_columns;  ///< after the parameter columns
  std::string header_comment;               ///< '#'-lines written first (scene, method, preset)
  std::string signature;                    ///< identifies the configuration for resuming
  std::string out_path;
  unsigned jobs = 1;
  std::size_t max_new_points = 0;  ///< stop after computing this many (0 = all): work in chunks
  bool quiet = false;
};

struct SweepOutcome {
  std::size_t points = 0, resumed = 0, computed = 0;
  bool complete = false;  ///< false when max_new_points stopped it (no CSV written yet)
  /// Points whose note says "error: ..." (resumed ones included). When the sweep completes with
  /// every point failed, no CSV is written, the journal is removed (a rerun computes them again),
  /// and all_failed tells the caller to report it as an error: nothing was computed.
  std::size_t failed = 0;
  bool all_failed = false;
  std::vector<std::vector<double>> values;        ///< per point: its parameter values
  std::vector<std::vector<std::string>> results;  ///< per point: its result cells
};

/// Runs the plan; compute(values) returns the point's result cells (size result_columns) and must
/// be thread-safe. An exception from compute leaves the point's cells empty and its last cell "error: ..."
/// when the plan's last column is "note", otherwise it aborts the sweep (journal kept). When every
/// point of a finished sweep failed so, no CSV is written (SweepOutcome::all_failed).
SweepOutcome run_sweep(const SweepPlan& plan,
                       const std::function<std::vector<std::string>(const std::vector<double>&)>& compute);

}  // namespace mlce::cli
