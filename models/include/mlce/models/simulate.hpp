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

/// Watches the output samples as the integration reaches them (Boost.Odeint's observer): sample k
/// at time t = k dt_out with state x. Writers below are observers, so a run of any length is
/// written as it goes and never held in memory.
using SampleObserver = std::function<void(std::size_t k, double t, const Eigen::VectorXd& x)>;

/// Integrates the scene, handing every output sample to `observe`; progress(fraction) is called
/// now and then. Refuses at once a run that cannot finish within the step budget
/// (ode/step_budget.hpp) and throws where one stops.
ode::IntegrationStats simulate(const Scene& scene, const SampleObserver& observe,
                               const std::function<void(double)>& progress = {});

/// The state names of the scene's model, in the order of its state vector.
std::vector<std::string> state_names(const Scene& scene);

/// Every sample of a run, in memory (tests, sweeps, short runs).
struct Trajectory {
  std::vector<double> time;
  std::vector<Eigen::VectorXd> states;
  std::vector<std::string> names;
  ode::IntegrationStats stats;
};
Trajectory simulate(const Scene& scene, const std::function<void(double)>& progress = {});

/// Observer writing a "# time name..." header and one row per sample (17 significant digits).
/// A stream that fails (a full disk) throws std::runtime_error naming `target` and the sample at
/// once, not after the rest of the run.
class ColumnsWriter {
 public:
  ColumnsWriter(std::ostream& os, const std::vector<std::string>& names, std::string target = "output");
  void operator()(std::size_t k, double t, const Eigen::VectorXd& x);

 private:
  std::ostream* os_;
  std::string target_;
  std::string row_;
};

/// Observer writing PREFIX.log, PREFIX.out and PREFIX.mov (Hammond scenes only), each through a
/// temporary file beside it; commit() renames them into place, and a writer destroyed before that
/// (an error, a run stopped by its step budget) removes them: never a partial set. Throws
/// std::invalid_argument for a scene other than Hammond and std::runtime_error naming the file
/// that cannot be written.
class MbdynSetWriter {
 public:
  MbdynSetWriter(const Scene& scene, const std::string& prefix);
  ~MbdynSetWriter();
  MbdynSetWriter(const MbdynSetWriter&) = delete;
  MbdynSetWriter& operator=(const MbdynSetWriter&) = delete;
  void operator()(std::size_t k, double t, const Eigen::VectorXd& x);
  void commit();
  /// The temporaries the writer for `prefix` writes (.log, .out, .mov, each + ".tmp"), for a caller
  /// that removes them if the process is interrupted: known before the writer exists, so that they
  /// can be registered before the constructor creates them (a signal between the two left them behind).
  static std::vector<std::string> scratch_files(const std::string& prefix);

 private:
  struct File;
  void flush();
  HammondParameters p_;
  std::vector<File> files_;  // .log, .out, .mov
  double previous_t_ = 0.0;
  std::string steps_, rows_;  // .out and .mov text not yet handed to the streams
  bool committed_ = false;
};

}  // namespace mlce::models
