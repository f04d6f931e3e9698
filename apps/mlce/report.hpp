#pragma once
// Results as text for people, JSON for scripts, CSV for curves.
#include <nlohmann/json.hpp>
#include <string>

#include "mlce/estimate.hpp"
#include "mlce/space_time.hpp"
#include "mlce/convergence.hpp"

namespace mlce::cli {

nlohmann::json to_json(const MlceResult& r);
nlohmann::json to_json(const AmiResult& r);
nlohmann::json to_json(const FnnResult& r);
std::string to_text(const MlceResult& r);
std::string to_text(const AmiResult& r);
std::string to_text(const FnnResult& r);
/// step,time,mean_log_distance,terms,in_fit,fit_line
std::string curve_csv(const MlceResult& r);
/// Space-time separation plot; `dt` and `time_unit` convert separations to time.
nlohmann::json to_json(const SpaceTimeResult& r, double dt, const std::string& time_unit);
std::string to_text(const SpaceTimeResult& r, double dt, const std::string& time_unit);
/// MLCE of the run's leading parts; `unit` is the rate unit ("1/s" or "1/sample").
nlohmann::json to_json(const ConvergenceResult& r, const std::string& unit);
std::string to_text(const ConvergenceResult& r, const std::string& unit);
/// samples,t_end,lambda,ci95_low,ci95_high,delay,dim,theiler,warnings (empty estimate fields for a part
/// that could not be estimated)
std::string convergence_csv(const ConvergenceResult& r);
/// separation,time,contour_<fraction>...,pairs
std::string space_time_csv(const SpaceTimeResult& r, double dt);

/// Writes `content` to `path` through a temporary file and a rename: no partial file is left
/// behind on failure. Throws std::runtime_error naming the path.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace mlce::cli
