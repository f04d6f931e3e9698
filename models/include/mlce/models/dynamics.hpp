#pragma once
// Scenes as the Jacobian-based methods see them: the model as an ode::DynamicalSystem, named
// parameters as one-parameter families (for sensitivities), and the time-invariant form used by
// eigenanalysis (multiblade coordinates for an isotropic Hammond rotor, paper 000 eqs. 34-38).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "mlce/models/scene.hpp"
#include "mlce/ode/system.hpp"

namespace mlce::models {

/// The scene's model: rhs, analytic Jacobian, complex rhs, period (Hammond 2 pi / Omega, 0 at
/// rest; flapping 2 pi).
ode::DynamicalSystem dynamical_system(const Scene& scene);

/// Parameters that can be varied by name: hammond rpm, CL (every blade), CL1..CLN, c, c1..cN,
/// k1..kN, cx, cy, kx, ky, mx, my, mb, Sb, Ib, e, chibar; flapping mu, gamma, nu.
std::vector<std::string> parameter_names(const Scene& scene);
double scene_parameter(const Scene& scene, const std::string& name);  ///< throws std::invalid_argument
void set_scene_parameter(Scene& scene, const std::string& name, double value);
ode::ParameterFamily parameter_family(const Scene& scene, const std::string& name);

/// A time-invariant state matrix of the scene's linearisation about x = 0 with the coordinates it
/// is expressed in: an isotropic Hammond rotor in multiblade coordinates (collective, cyclic
/// pairs, reactionless for even N; hub x, y), x = T(t) q with T from the blade azimuths,
/// A_mbc = T^-1 (A(t) T - T'); flapping at mu = 0 as is. Throws std::invalid_argument when the
/// problem is not time-invariant in those coordinates (anisotropic rotor, mu > 0): use Floquet.
struct TimeInvariantForm {
  Eigen::MatrixXd A;
  std::vector<std::string> coordinates;
};
TimeInvariantForm time_invariant_form(const Scene& scene);

}  // namespace mlce::models
