#pragma once
// Results as text for people, JSON for scripts, CSV for curves.
#include "interrupt.hpp"
#include <nlohmann/json.hpp>
#include <fstream>
#include <ostream>
#include <string>

#include "mlce/estimate.hpp"
#include "mlce/kantz.hpp"
#include "mlce/modes.hpp"
#include "mlce/space_time.hpp"
#include "mlce/convergence.hpp"
#include "mlce/each_channel.hpp"
#include "mlce/reading.hpp"

namespace mlce::cli {

nlohmann::json to_json(const MlceResult& r);
/// The estimate's reading (read_stability): stability, motion, amplitude, rates per mean period, summary.
nlohmann::json reading_json(const MlceResult& r);
nlohmann::json to_json(const AmiResult& r);
nlohmann::json to_json(const FnnResult& r);
/// Cao's E, E1, E2 (mlce fnn --method cao --json).
nlohmann::json to_json(const CaoResult& r);
std::string to_text(const MlceResult& r);
std::string to_text(const AmiResult& r);
std::string to_text(const FnnResult& r);
std::string to_text(const CaoResult& r);
/// The divergence curve as a table: step,time,mean_log_distance,terms,in_fit,fit_line, then
/// plain_mean_log_distance when the curve is phase-aligned, then local_slope (per time unit over
/// one mean period; empty where no centred window fits). The layout is decided here once, for the
/// CSV and for the plot that draws it.
struct CurveTable {
  std::string csv;
  std::size_t plain_column = 0;  ///< 1-based column of plain_mean_log_distance; 0 = absent
  std::size_t slope_column = 0;  ///< 1-based column of local_slope
  bool any_slope = false;        ///< some step has a local slope (the curve is longer than a period)
};
CurveTable curve_table(const MlceResult& r);
/// curve_table(r).csv
std::string curve_csv(const MlceResult& r);
/// "tau,ami,smoothed": the AMI curve in nats (mlce ami --csv; the plot's data).
std::string ami_csv(const AmiResult& r);
/// "m,false_fraction,tested,tree_points" (mlce fnn --csv).
std::string fnn_csv(const FnnResult& r);
/// "d,E,E1,E2,pairs" (mlce fnn --method cao --csv; E1, E2 empty at the last d).
std::string cao_csv(const CaoResult& r);
/// Kantz's curves (mlce kantz): each radius' fit, the median, and the comparison with the estimate.
nlohmann::json to_json(const KantzResult& r);
std::string to_text(const KantzResult& r);
/// "step,time,S_radius_<eps>...": S(eps, i) of every radius (natural log, the curves' units); without the
/// step column for a plot against time.
std::string kantz_csv(const KantzResult& r, bool with_step = true);
/// Linear modal identification (mlce modes): the modes, lambda, the fit's residual and the reading.
nlohmann::json to_json(const ModalResult& r);
std::string to_text(const ModalResult& r);
/// "sigma,frequency,damping_ratio,share,peak_share,offset": a mode a row, largest share first.
std::string modes_csv(const ModalResult& r);
/// Space-time separation plot; `dt` and `time_unit` convert separations to time.
nlohmann::json to_json(const SpaceTimeResult& r, double dt, const std::string& time_unit);
std::string to_text(const SpaceTimeResult& r, double dt, const std::string& time_unit);
/// MLCE of the run's leading parts; `unit` is the rate unit ("1/s" or "1/sample").
nlohmann::json to_json(const ConvergenceResult& r, const std::string& unit);
std::string to_text(const ConvergenceResult& r, const std::string& unit);
/// samples,t_end,lambda,ci95_low,ci95_high,delay,dim,theiler,warnings (empty estimate fields for a part
/// that could not be estimated)
std::string convergence_csv(const ConvergenceResult& r);
/// Whether estimates agree: agree, gap, common_interval ([low, high] or null), median_lambda, tolerance.
nlohmann::json to_json(const Agreement& a);
/// The same as one line for people ("yes: the 3 intervals share ...", "NO: ... apart ...").
std::string agreement_text(const Agreement& a, std::size_t estimates, const std::string& rate_unit);
/// Every channel estimated on its own (mlce estimate --each): each channel's estimate as to_json
/// gives it (or its error), and the verdict.
nlohmann::json to_json(const EachChannelResult& r);
/// A table, a channel a row, then the verdict and the warnings. `from`: where each channel's
/// analysed samples start, in time units (t0, the time of the series' first sample, plus the
/// samples left out because they do not recur, which differ from channel to channel).
std::string to_text(const EachChannelResult& r, double t0);
/// channel,index,step,time,mean_log_distance,terms,in_fit,fit_line: every estimated channel's
/// curve_csv rows one after the other, `index` numbering the channels from 0.
std::string each_channel_curves_csv(const EachChannelResult& r);
/// A CSV field: quoted (with quotes doubled) when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text);
/// separation,time,contour_<fraction>...,pairs
std::string space_time_csv(const SpaceTimeResult& r, double dt);

/// Where an output is finally written. A regular file, or a name not taken yet, is replaced by
/// renaming a finished temporary onto it. A symbolic link keeps pointing where it did: `path` is
/// its target. A device or a pipe (/dev/stdout, /dev/null, a FIFO), and any name under /dev or
/// /proc, is written `in_place`: renamed onto, its name would become a regular file (as root,
/// /dev/stdout itself).
struct OutputTarget {
  std::string path;
  bool in_place = false;
  /// A scratch file for this output ending in `suffix`: beside the target (same file system, so
  /// the rename is atomic), or in the temporary directory for a target written in place.
  std::string scratch(const std::string& suffix) const;
};
OutputTarget output_target(const std::string& path);

/// A file written through a temporary beside it and renamed into place by commit(): a failure
/// (or an exception before commit) leaves no partial file behind, and the content is streamed, never
/// held whole in memory. Errors throw std::runtime_error naming the path.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();
  std::ostream& stream() { return out_; }
  void commit();

 private:
  std::string path_;
  OutputTarget target_;
  std::string tmp_;  // empty for a target written in place
  ScratchGuard scratch_;  // removes tmp_ if the run is interrupted
  std::ofstream out_;
  bool committed_ = false;
};

/// Writes `content` to `path` through an AtomicFile.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace mlce::cli
