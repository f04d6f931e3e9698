#pragma once
// Liouville's formula as a check on every spectrum: det of the tangent flow grows like the
// integral of tr A = div f, so the exponents of any method (discrete QR, Floquet, eigenvalues of
// a constant A) sum to the mean divergence of the vector field over the same window. Nothing
// else in the computation is checked this cheaply, and the sum does not depend on how the
// exponents separate from each other (the orthonormalisation, pairing or sorting).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace mlce::spectrum {

/// Largest accepted |sum lambda_i - <tr A>|, relative to sum |lambda_i| (or to |<tr A>| when
/// larger). The analytic route on the bundled scenes agrees to ~1e-10 relative (`mlce spectrum
/// SCENE` prints both); loose tolerances (rtol 1e-2, QR step 0.1 s) miss by 2e-3.
inline constexpr double kLiouvilleTolerance = 1e-6;

/// The warning for exponents that do not sum to the mean divergence, or nothing.
inline std::optional<std::string> liouville_mismatch(const Eigen::VectorXd& exponents, double mean_divergence,
                                                     const char* remedy) {
  const double sum = exponents.sum(), magnitude = std::max(exponents.cwiseAbs().sum(), std::abs(mean_divergence));
  if (std::abs(sum - mean_divergence) <= kLiouvilleTolerance * magnitude) return std::nullopt;
  return "the exponents sum to " + std::to_string(sum) + ", the mean divergence of the vector field (tr A) is " +
         std::to_string(mean_divergence) + " (Liouville: they should agree): " + remedy;
}

}  // namespace mlce::spectrum
