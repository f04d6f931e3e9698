#pragma once
// MBDyn orientation parametrizations and the relative rotation of one node about an axis of
// another (the blade lag angle of paper 001 eq. 24 from absolute blade and hub bodies).
#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mlce::reader {

/// As MBDyn's .log names them: euler123, euler313, euler321 (degrees), phi (rotation vector, rad),
/// mat (9 numbers), none (displacement-only nodes: three zeros).
enum class Orientation { euler123, euler313, euler321, phi, mat, none };

/// nullopt for an unknown name.
std::optional<Orientation> orientation_from_name(std::string_view name);
const char* orientation_name(Orientation o);
/// Numbers the parametrization takes in a .mov row (3 or 9).
std::size_t orientation_size(Orientation o);

using Matrix3 = std::array<double, 9>;  ///< row-major R11 R12 R13 R21 ... R33

/// R from the numbers as the text file writes them (angles in degrees; matrix row by row).
/// euler123: R = Rx(a1) Ry(a2) Rz(a3); euler313: Rz Rx Rz; euler321: Rz Ry Rx; phi: exp(phi x).
Matrix3 rotation_matrix(Orientation o, std::span<const double> values);
/// The inverse of rotation_matrix (what MBDyn writes for R), for tests and synthetic files.
std::vector<double> orientation_values(Orientation o, const Matrix3& R);

/// Angle (rad, in (-pi, pi]) of the rotation of A relative to B about `axis` (0,1,2) of B's frame,
/// measured from the initial relative orientation: dR = (R_B^T R_A) (R_B0^T R_A0)^T, the twist
/// of dR about the axis (swing-twist decomposition; exact for a pure rotation about the axis).
double relative_twist(const Matrix3& RA, const Matrix3& RB, const Matrix3& RA0, const Matrix3& RB0, int axis);

/// The whole channel rel:A:B:AXIS: `a` and `b` hold the orientation numbers of A and B as
/// written (one column per number, `n` samples each); the initial relative pose is computed once.
/// Returns the twist angle of every sample, unwrapped.
std::vector<double> relative_angle_series(Orientation oa, const std::vector<std::span<const double>>& a,
                                          Orientation ob, const std::vector<std::span<const double>>& b,
                                          const Matrix3& RA0, const Matrix3& RB0, int axis, std::size_t n);

/// Removes jumps larger than pi between consecutive samples (adds multiples of 2 pi), in place.
void unwrap(std::vector<double>& angle);

}  // namespace mlce::reader
