#include "mlce/reader/orientation.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "mlce/reader/table.hpp"

namespace mlce::reader {
namespace {

using M3 = Eigen::Matrix3d;
constexpr double kDeg = std::numbers::pi / 180.0;

M3 to_eigen(const Matrix3& r) {
  M3 m;
  for (Eigen::Index i = 0; i < 3; ++i)
    for (Eigen::Index j = 0; j < 3; ++j) m(i, j) = r[static_cast<std::size_t>(3 * i + j)];
  return m;
}
Matrix3 from_eigen(const M3& m) {
  Matrix3 r{};
  for (Eigen::Index i = 0; i < 3; ++i)
    for (Eigen::Index j = 0; j < 3; ++j) r[static_cast<std::size_t>(3 * i + j)] = m(i, j);
  return r;
}
M3 axis_rotation(int axis, double angle) {
  return Eigen::AngleAxisd(angle, M3::Identity().col(axis)).toRotationMatrix();
}

}  // namespace

std::optional<Orientation> orientation_from_name(std::string_view n) {
  if (n == "euler123") return Orientation::euler123;
  if (n == "euler313") return Orientation::euler313;
  if (n == "euler321") return Orientation::euler321;
  if (n == "phi") return Orientation::phi;
  if (n == "mat") return Orientation::mat;
  if (n == "none") return Orientation::none;
  return std::nullopt;
}

const char* orientation_name(Orientation o) {
  switch (o) {
    case Orientation::euler123: return "euler123";
    case Orientation::euler313: return "euler313";
    case Orientation::euler321: return "euler321";
    case Orientation::phi: return "phi";
    case Orientation::mat: return "mat";
    default: return "none";
  }
}

std::size_t orientation_size(Orientation o) { return o == Orientation::mat ? 9 : 3; }

Matrix3 rotation_matrix(Orientation o, std::span<const double> v) {
  if (v.size() != orientation_size(o))
    throw ReadError(std::string("orientation ") + orientation_name(o) + ": expected " +
                    std::to_string(orientation_size(o)) + " numbers");
  M3 R = M3::Identity();
  switch (o) {
    case Orientation::euler123:
      R = axis_rotation(0, v[0] * kDeg) * axis_rotation(1, v[1] * kDeg) * axis_rotation(2, v[2] * kDeg);
      break;
    case Orientation::euler313:
      R = axis_rotation(2, v[0] * kDeg) * axis_rotation(0, v[1] * kDeg) * axis_rotation(2, v[2] * kDeg);
      break;
    case Orientation::euler321:
      R = axis_rotation(2, v[0] * kDeg) * axis_rotation(1, v[1] * kDeg) * axis_rotation(0, v[2] * kDeg);
      break;
    case Orientation::phi: {
      const Eigen::Vector3d phi(v[0], v[1], v[2]);
      const double a = phi.norm();
      R = a > 0 ? M3(Eigen::AngleAxisd(a, phi / a).toRotationMatrix()) : M3::Identity();
      break;
    }
    case Orientation::mat:
      for (Eigen::Index i = 0; i < 3; ++i)
        for (Eigen::Index j = 0; j < 3; ++j) R(i, j) = v[static_cast<std::size_t>(3 * i + j)];
      break;
    case Orientation::none: R = M3::Identity(); break;
  }
  return from_eigen(R);
}

std::vector<double> orientation_values(Orientation o, const Matrix3& r) {
  const M3 R = to_eigen(r);
  auto deg = [](double a) { return a / kDeg; };
  switch (o) {
    case Orientation::euler123:  // R = Rx(a) Ry(b) Rz(c): R13 = sin b, R23 = -sin a cos b, R12 = -cos b sin c
      return {deg(std::atan2(-R(1, 2), R(2, 2))), deg(std::asin(std::clamp(R(0, 2), -1.0, 1.0))),
              deg(std::atan2(-R(0, 1), R(0, 0)))};
    case Orientation::euler313:  // R = Rz(a) Rx(b) Rz(c): R33 = cos b, R13 = sin a sin b, R31 = sin b sin c
      return {deg(std::atan2(R(0, 2), -R(1, 2))), deg(std::acos(std::clamp(R(2, 2), -1.0, 1.0))),
              deg(std::atan2(R(2, 0), R(2, 1)))};
    case Orientation::euler321:  // R = Rz(a) Ry(b) Rx(c): R31 = -sin b, R21 = sin a cos b, R32 = cos b sin c
      return {deg(std::atan2(R(1, 0), R(0, 0))), deg(std::asin(std::clamp(-R(2, 0), -1.0, 1.0))),
              deg(std::atan2(R(2, 1), R(2, 2)))};
    case Orientation::phi: {
      const Eigen::AngleAxisd aa(R);
      const Eigen::Vector3d phi = aa.axis() * aa.angle();
      return {phi(0), phi(1), phi(2)};
    }
    case Orientation::mat: return std::vector<double>(r.begin(), r.end());
    default: return {0.0, 0.0, 0.0};
  }
}

namespace {

/// Twist about `axis` of dR = rel (rel0)^T, rel = R_B^T R_A (B's frame); q = (w, v) of dR gives
/// 2 atan2(v . a, w), wrapped to (-pi, pi].
double twist(const M3& RA, const M3& RB, const M3& rel0_t, int axis) {
  const Eigen::Quaterniond q(M3(RB.transpose() * RA * rel0_t));
  double angle = 2.0 * std::atan2(q.vec()(axis), q.w());
  if (angle > std::numbers::pi) angle -= 2.0 * std::numbers::pi;
  if (angle <= -std::numbers::pi) angle += 2.0 * std::numbers::pi;
  return angle;
}

}  // namespace

double relative_twist(const Matrix3& RA, const Matrix3& RB, const Matrix3& RA0, const Matrix3& RB0, int axis) {
  const M3 rel0 = to_eigen(RB0).transpose() * to_eigen(RA0);
  return twist(to_eigen(RA), to_eigen(RB), rel0.transpose(), axis);
}

std::vector<double> relative_angle_series(Orientation oa, const std::vector<std::span<const double>>& a,
                                          Orientation ob, const std::vector<std::span<const double>>& b,
                                          const Matrix3& RA0, const Matrix3& RB0, int axis, std::size_t n) {
  if (a.size() != orientation_size(oa) || b.size() != orientation_size(ob))
    throw ReadError("relative angle: orientation columns do not match the parametrizations");
  const M3 rel0_t = (to_eigen(RB0).transpose() * to_eigen(RA0)).transpose();
  std::vector<double> angle(n), va(a.size()), vb(b.size());
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t i = 0; i < a.size(); ++i) va[i] = a[i][k];
    for (std::size_t i = 0; i < b.size(); ++i) vb[i] = b[i][k];
    angle[k] = twist(to_eigen(rotation_matrix(oa, va)), to_eigen(rotation_matrix(ob, vb)), rel0_t, axis);
  }
  unwrap(angle);
  return angle;
}

void unwrap(std::vector<double>& a) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  double offset = 0.0;
  for (std::size_t k = 1; k < a.size(); ++k) {
    const double raw = a[k];
    const double prev_raw = a[k - 1] - offset;
    const double jump = raw - prev_raw;
    offset -= two_pi * std::round(jump / two_pi);
    a[k] = raw + offset;
  }
}

}  // namespace mlce::reader
