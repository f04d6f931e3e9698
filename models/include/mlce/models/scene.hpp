#pragma once
// A scene names a model, its parameters, initial conditions, duration, output step and
// integrator, in Boost.Program_options config-file syntax (`key = value`, `#` comments). Every key
// is also a command-line flag (`--rpm 124.2`) that overrides the file.
#include <Eigen/Core>
#include <boost/program_options/options_description.hpp>
#include <string>
#include <vector>

#include "mlce/models/flapping.hpp"
#include "mlce/models/hammond.hpp"
#include "mlce/ode/runge_kutta.hpp"

namespace mlce::models {

struct Scene {
  std::string source;  ///< file name, for messages
  std::string model;   ///< hammond | flapping
  HammondParameters hammond;
  FlappingParameters flapping;
  Eigen::VectorXd x0;  ///< initial state in the model's order
  double t_end = 30.0;     ///< s (flapping: nondimensional)
  double dt_out = 0.005;   ///< output step
  ode::IntegratorOptions integrator;
  std::size_t samples() const;  ///< t = 0, dt_out, ..., <= t_end
};

/// Every scene key, as string-valued options (the same description serves the file and the CLI).
boost::program_options::options_description scene_options();

/// Reads `path` (may be empty: defaults only) with `overrides` (e.g. {"--rpm", "124.2"}) taking
/// precedence. Throws std::invalid_argument naming the file, key and what was expected.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides);

/// The scene's keys as `key = value` lines (what `mlce simulate` records next to its output).
std::string describe_scene(const Scene& s);

}  // namespace mlce::models
