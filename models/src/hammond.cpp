#include "mlce/models/hammond.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mlce::models {
namespace {

inline double re(double v) { return v; }
inline double re(const std::complex<double>& v) { return v.real(); }

/// Nonlinear damper moment on the blade in any scalar type: |z| as z sign(Re z) keeps it
/// analytic for complex-step differentiation; the branch is chosen on the real part.
template <class T>
T damper_moment(const T& z, double C_L, double chibar, double zL) {
  const double chi = chibar - C_L / zL;
  const double s = re(z) >= 0 ? 1.0 : -1.0;
  if (std::abs(re(z)) < zL) return -(chi * z * (s * z) + C_L * z);
  return T(-chibar * s * zL * zL);
}

}  // namespace

double nonlinear_damper_moment(double zetadot, double C_L, double chibar, double zetadot_L) {
  return damper_moment(zetadot, C_L, chibar, zetadot_L);
}

double HammondParameters::omega() const { return rpm * 2.0 * std::numbers::pi / 60.0; }

double HammondParameters::azimuth0(int i) const {
  return 2.0 * std::numbers::pi * (paper_placement ? i + 1 : i) / blades;
}

void HammondParameters::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string(name) + ": expected a positive number");
  };
  auto non_negative = [](double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string(name) + ": expected >= 0");
  };
  if (blades < 1 || blades > 64) throw std::invalid_argument("blades: expected 1..64");
  positive(m_b, "mb"), positive(S_b, "Sb"), positive(I_b, "Ib"), non_negative(e, "e");
  positive(m_x, "mx"), positive(m_y, "my"), non_negative(k_x, "kx"), non_negative(k_y, "ky");
  non_negative(c_x, "cx"), non_negative(c_y, "cy"), positive(chibar, "chibar"), positive(zetadot_L, "zetadot_L");
  if (!std::isfinite(rpm)) throw std::invalid_argument("rpm: expected a finite number");
  if (S_b * S_b >= I_b * m_b) throw std::invalid_argument("Sb^2 >= Ib mb: the blade inertia about the hinge is too small");
  const auto n = static_cast<std::size_t>(blades);
  if (c.size() != n || k.size() != n || damper.size() != n || C_L.size() != n)
    throw std::invalid_argument("c, k, damper and CL need one value per blade (" + std::to_string(blades) + ")");
  for (std::size_t i = 0; i < n; ++i) {
    non_negative(c[i], "c"), non_negative(C_L[i], "CL");
    if (!std::isfinite(k[i])) throw std::invalid_argument("k: expected finite values");
    if (C_L[i] / zetadot_L > chibar)
      throw std::invalid_argument("CL / zetadot_L exceeds chibar: the quadratic coefficient chi would be negative");
  }
}

HammondModel::HammondModel(HammondParameters p, bool check) : p_(std::move(p)) {
  if (check) p_.validate();
}

template <class Vec>
void HammondModel::evaluate(const Vec& x, Vec& dxdt, double t) const {
  using T = typename Vec::Scalar;
  using std::cos;
  using std::sin;
  const int N = p_.blades, nq = N + 2;
  const double W = p_.omega();
  dxdt.resize(2 * nq);
  dxdt.head(nq) = x.tail(nq);
  const T xd = x(nq + N), yd = x(nq + N + 1);
  // Mass matrix blocks: D = I_b, B_i = (-S_b sin u_i, S_b cos u_i), H = diag(m_x + N m_b, m_y + N m_b).
  Eigen::Matrix<T, 2, 2> S;
  S << T(p_.m_x + N * p_.m_b), T(0), T(0), T(p_.m_y + N * p_.m_b);
  Eigen::Matrix<T, 2, 1> Fh(-p_.c_x * xd - p_.k_x * x(N), -p_.c_y * yd - p_.k_y * x(N + 1));
  // Bounded sizes (blades <= 64, validated): no heap allocation in the right-hand side.
  Eigen::Matrix<T, Eigen::Dynamic, 1, 0, 64, 1> Fb(N);
  Eigen::Matrix<T, Eigen::Dynamic, 2, 0, 64, 2> B(N, 2);
  for (int i = 0; i < N; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double psi = W * t + p_.azimuth0(i);
    const T z = x(i), zd = x(nq + i), u = psi + z;
    const T su = sin(u), cu = cos(u), ud = W + zd;
    B(i, 0) = -p_.S_b * su;
    B(i, 1) = p_.S_b * cu;
    T moment = p_.damper[iu] == DamperLaw::linear ? T(-p_.c[iu] * zd)
                                                  : damper_moment(zd, p_.C_L[iu], p_.chibar, p_.zetadot_L);
    Fb(i) = -p_.S_b * p_.e * W * W * sin(z) - p_.k[iu] * z + moment;
    Fh(0) += p_.S_b * ud * ud * cu + p_.m_b * p_.e * W * W * std::cos(psi);
    Fh(1) += p_.S_b * ud * ud * su + p_.m_b * p_.e * W * W * std::sin(psi);
  }
  // Schur complement of the blade block (exact, O(N)): S = H - B^T B / I_b.
  S -= B.transpose() * B / p_.I_b;
  const Eigen::Matrix<T, 2, 1> qh = S.inverse() * (Fh - B.transpose() * Fb / p_.I_b);
  dxdt.segment(nq, N) = (Fb - B * qh) / p_.I_b;
  dxdt.segment(nq + N, 2) = qh;
}

void HammondModel::operator()(const Eigen::VectorXd& x, Eigen::VectorXd& dxdt, double t) const {
  evaluate(x, dxdt, t);
}

void HammondModel::rhs(const Eigen::VectorXcd& x, Eigen::VectorXcd& dxdt, double t) const { evaluate(x, dxdt, t); }

Eigen::MatrixXd HammondModel::jacobian(const Eigen::VectorXd& x, double t) const {
  const int N = p_.blades, nq = N + 2, n = 2 * nq;
  const double W = p_.omega();
  Eigen::VectorXd f(n);
  evaluate(x, f, t);
  const Eigen::VectorXd qdd = f.tail(nq);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(nq, nq), dFdq = M, dFdv = M, G = M;
  M(N, N) = p_.m_x + N * p_.m_b;
  M(N + 1, N + 1) = p_.m_y + N * p_.m_b;
  dFdq(N, N) = -p_.k_x;
  dFdq(N + 1, N + 1) = -p_.k_y;
  dFdv(N, N) = -p_.c_x;
  dFdv(N + 1, N + 1) = -p_.c_y;
  for (int i = 0; i < N; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double psi = W * t + p_.azimuth0(i);
    const double z = x(i), zd = x(nq + i), u = psi + z, su = std::sin(u), cu = std::cos(u), ud = W + zd;
    M(i, i) = p_.I_b;
    M(i, N) = M(N, i) = -p_.S_b * su;
    M(i, N + 1) = M(N + 1, i) = p_.S_b * cu;
    // (dM/dzeta_i) qdd
    G(i, i) = -p_.S_b * cu * qdd(N) - p_.S_b * su * qdd(N + 1);
    G(N, i) = -p_.S_b * cu * qdd(i);
    G(N + 1, i) = -p_.S_b * su * qdd(i);
    // dF/dzeta_i, dF/dzetadot_i
    dFdq(i, i) = -p_.S_b * p_.e * W * W * std::cos(z) - p_.k[iu];
    dFdq(N, i) = -p_.S_b * ud * ud * su;
    dFdq(N + 1, i) = p_.S_b * ud * ud * cu;
    double dmoment = -p_.c[iu];
    if (p_.damper[iu] == DamperLaw::nonlinear) {
      const double chi = p_.chibar - p_.C_L[iu] / p_.zetadot_L;
      dmoment = std::abs(zd) < p_.zetadot_L ? -(2.0 * chi * std::abs(zd) + p_.C_L[iu]) : 0.0;
    }
    dFdv(i, i) = dmoment;
    dFdv(N, i) = 2.0 * p_.S_b * ud * cu;
    dFdv(N + 1, i) = 2.0 * p_.S_b * ud * su;
  }
  const Eigen::LDLT<Eigen::MatrixXd> Mf(M);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
  J.topRightCorner(nq, nq).setIdentity();
  J.bottomLeftCorner(nq, nq) = Mf.solve(dFdq - G);
  J.bottomRightCorner(nq, nq) = Mf.solve(dFdv);
  return J;
}

std::vector<std::string> HammondModel::state_names() const {
  std::vector<std::string> n;
  for (int i = 1; i <= p_.blades; ++i) n.push_back("zeta" + std::to_string(i));
  n.insert(n.end(), {"x_h", "y_h"});
  for (int i = 1; i <= p_.blades; ++i) n.push_back("zetadot" + std::to_string(i));
  n.insert(n.end(), {"xdot_h", "ydot_h"});
  return n;
}

}  // namespace mlce::models
