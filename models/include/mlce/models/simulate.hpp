#pragma once
// Runs a scene and exports its time history: plain columns, or the MBDyn text set of the same
// bodies as an MBDyn model with absolute blade bodies (labels below), so that one reader path and
// one channel spec (rel:13:4:z = lag of blade 3) serve ad-hoc and MBDyn runs alike.
//
//   label | body (same labels as ../shared/data/mbdyn and mbdyn-models/hammond)
//   2     | airframe x-part: position (x_h, 0, 0)
//   3     | airframe y-part: position (x_h, y_h, 0)
//   4     | hub (massless), spun about z: orientation euler123 (0, 0, Omega t)
//   10+i  | blade i at its lag hinge: position hub + e (cos psi_i, sin psi_i, 0),
//         | orientation euler123 (0, 0, psi_i + zeta_i), angular velocity (0, 0, Omega + zeta_i')
#include <Eigen/Core>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "mlce/models/scene.hpp"
#include "mlce/ode/runge_kutta.hpp"

namespace mlce::models {

struct Trajectory {
  std::vector<double> time;
  std::vector<Eigen::VectorXd> states;
  std::vector<std::string> names;
  ode::IntegrationStats stats;
};

/// Integrates the scene; progress(fraction) is called now and then.
Trajectory simulate(const Scene& scene, const std::function<void(double)>& progress = {});

/// Writes a "# time name..." header and one row per sample (17 significant digits).
void write_trajectory_columns(const Trajectory& t, std::ostream& os);

/// Writes PREFIX.log, PREFIX.out, PREFIX.mov (Hammond scenes only), each through a temporary file
/// renamed at the end. Throws std::runtime_error naming the file on failure.
void write_mbdyn_set(const Scene& scene, const Trajectory& t, const std::string& prefix);

}  // namespace mlce::models
