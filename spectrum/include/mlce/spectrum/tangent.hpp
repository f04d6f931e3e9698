#pragma once
// Products with the Jacobian A = df/dx along a trajectory, by one of three routes (all tested
// against each other): the model's analytic Jacobian; complex-step differentiation (Squire & Trapp,
// paper 001 ref. 36: A e_k = Im f(x + i h e_k) / h, exact to rounding for any h, here 1e-30; for
// fewer directions than states, A z = Im f(x + i h z) / h direction by direction);
// Jacobian-free directional central differences A z = (f(x + e z) - f(x - e z)) / 2e, which never
// forms A (the perturbed-trajectory approach of Dieci, paper 001 ref. 35, in differential form).
#include <Eigen/Core>
#include <string>

#include "mlce/ode/system.hpp"

namespace mlce::spectrum {

enum class JacobianMethod { analytic, complex_step, jacobian_free };

/// "analytic", "complex-step", "jacobian-free"; throws std::invalid_argument otherwise.
JacobianMethod jacobian_method_from_name(const std::string& name);
const char* jacobian_method_name(JacobianMethod m);

/// Throws std::invalid_argument when `sys` lacks what `m` needs.
void require(const ode::DynamicalSystem& sys, JacobianMethod m);

/// AZ = A(x, t) Z. `f0` = f(x, t) (unused by the explicit methods).
void tangent_product(const ode::DynamicalSystem& sys, JacobianMethod m, const Eigen::VectorXd& x, double t,
                     const Eigen::Ref<const Eigen::MatrixXd>& Z, Eigen::Ref<Eigen::MatrixXd> AZ);

/// The Jacobian itself (analytic, complex step, or central differences column by column).
Eigen::MatrixXd jacobian(const ode::DynamicalSystem& sys, JacobianMethod m, const Eigen::VectorXd& x, double t);

}  // namespace mlce::spectrum
