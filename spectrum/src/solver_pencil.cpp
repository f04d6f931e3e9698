// Eigenvalues of MBDyn's eigenanalysis pencil (solver_pencil.hpp).
#include "mlce/spectrum/solver_pencil.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mlce::spectrum {

namespace {

/// Largest real part first; real parts equal to 1e-12 of the largest |s| (a conjugate pair's two
/// roundings) count as equal, so a pair lists its positive imaginary part first. Keys on a grid keep
/// the order a strict weak one. Then the largest real part and its frequency.
void order_by_real_part(SolverPencilSpectrum& out) {
  double largest = 0.0;
  for (const auto& v : out.eigenvalues) largest = std::max(largest, std::abs(v));
  const double grid = 1e-12 * largest;
  const auto key = [grid](double re) { return grid > 0.0 ? std::round(re / grid) : re; };
  std::sort(out.eigenvalues.begin(), out.eigenvalues.end(), [&key](const auto& x, const auto& y) {
    const double kx = key(x.real()), ky = key(y.real());
    return kx != ky ? kx > ky : x.imag() > y.imag();
  });
  if (!out.eigenvalues.empty()) {
    out.largest_real_part = out.eigenvalues.front().real();
    out.largest_frequency = std::abs(out.eigenvalues.front().imag()) / (2.0 * std::numbers::pi);
  }
}

}  // namespace

SolverPencilSpectrum spectrum_from_multipliers(std::span<const std::array<double, 3>> alpha, double coefficient,
                                               const SolverPencilOptions& o) {
  if (!(coefficient > 0.0) || !std::isfinite(coefficient))
    throw std::invalid_argument("the eigenanalysis coefficient (dCoef) must be a positive number, got " + std::to_string(coefficient));
  SolverPencilSpectrum out;
  std::size_t singular = 0;
  for (const auto& [re, im, beta] : alpha) {
    const std::complex<double> a(re, im);
    const double scale = std::max(std::abs(a), std::abs(beta));
    if (!(scale > 0.0)) {  // alpha = beta = 0: a singular pencil, no eigenvalue at all
      ++singular, ++out.at_infinity;
      continue;
    }
    // s = (Lambda - 1) / (c (Lambda + 1)) with Lambda = a / beta, written in a and beta so that beta -> 0
    // and large |a| neither overflow nor divide by zero.
    const std::complex<double> sum = a + beta;
    if (std::abs(beta) <= o.zero_beta * std::abs(a) || std::abs(sum) <= o.infinite_tolerance * scale) {
      ++out.at_infinity;
      continue;
    }
    // (Lambda - 1) / (Lambda + 1) ~ c s is of order one where the step resolves the motion: divided by c
    // last, a time scale of 1e-150 or 1e150 neither under- nor overflows on the way.
    out.eigenvalues.push_back(((a - beta) / sum) / coefficient);
  }
  order_by_real_part(out);
  if (singular > 0)
    out.warnings.push_back(std::to_string(singular) +
                           " eigenvalue(s) with alpha = beta = 0: the pencil is singular (a constraint with no equation, or a "
                           "dof no element touches), left out");
  if (out.eigenvalues.empty())
    out.warnings.push_back("every eigenvalue is at infinity (constraints or a singular Aplus): no motion to read");
  out.method = "alpha";
  return out;
}

SolverPencilSpectrum spectrum_from_pencil(std::size_t n, std::span<const double> aplus, std::span<const double> aminus,
                                          double coefficient, const SolverPencilOptions& o) {
  if (n == 0 || aplus.size() != n * n || aminus.size() != n * n)
    throw std::invalid_argument("Aplus and Aminus must both be " + std::to_string(n) + " x " + std::to_string(n));
  const auto as_matrix = [n](std::span<const double> v) {
    const auto e = static_cast<Eigen::Index>(n);
    return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(v.data(), e, e).eval();
  };
  Eigen::MatrixXd minus = as_matrix(aminus), plus = as_matrix(aplus);
  // One scale for both (Lambda unchanged): the QZ's rotations square entries, and a pencil written in
  // a time unit of 1e-150 or 1e150 would under- or overflow there.
  const double scale = std::max(plus.cwiseAbs().maxCoeff(), minus.cwiseAbs().maxCoeff());
  if (!(scale > 0.0) || !std::isfinite(scale)) throw std::invalid_argument("Aplus and Aminus are zero or not finite");
  plus /= scale, minus /= scale;
  std::vector<std::array<double, 3>> alpha(n);
  // Aminus v = Lambda Aplus v. Aplus is the matrix a step of size 2 dCoef factors (the solver's own
  // Jacobian), so it is regular on a run that advanced: Lambda are then the eigenvalues of
  // Aplus^-1 Aminus (LU, then Eigen's EigenSolver: 2.5x faster than its QZ at n = 500, bench_spectrum solver_pencil).
  // Where Aplus is singular to rounding (beta = 0 eigenvalues) QZ, as MBDyn's LAPACK dggev call.
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(plus);
  // A zero pivot makes the LU's condition estimate meaningless (it divides by it): checked first.
  const Eigen::VectorXd pivots = lu.matrixLU().diagonal().cwiseAbs();
  const double rcond = pivots.minCoeff() > 1e-14 * pivots.maxCoeff() ? lu.rcond() : 0.0;
  const Eigen::MatrixXd reduced = rcond > o.regular_aplus ? Eigen::MatrixXd(lu.solve(minus)) : Eigen::MatrixXd();
  if (rcond > o.regular_aplus && reduced.allFinite()) {
    const Eigen::EigenSolver<Eigen::MatrixXd> standard(reduced, false);
    if (standard.info() != Eigen::Success) throw std::invalid_argument("the eigenvalues of Aplus^-1 Aminus did not converge");
    for (std::size_t k = 0; k < n; ++k) {
      const std::complex<double> lambda = standard.eigenvalues()(static_cast<Eigen::Index>(k));
      alpha[k] = {lambda.real(), lambda.imag(), 1.0};
    }
    SolverPencilSpectrum out = spectrum_from_multipliers(alpha, coefficient, o);
    out.method = "LU of Aplus, eigenvalues of Aplus^-1 Aminus";
    return out;
  }
  const Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> qz(minus, plus, false);
  if (qz.info() != Eigen::Success) throw std::invalid_argument("the QZ iteration on (Aminus, Aplus) did not converge");
  for (std::size_t k = 0; k < n; ++k) {
    const auto e = static_cast<Eigen::Index>(k);
    alpha[k] = {qz.alphas()(e).real(), qz.alphas()(e).imag(), qz.betas()(e)};
  }
  SolverPencilSpectrum out = spectrum_from_multipliers(alpha, coefficient, o);
  out.method = "QZ (Aplus singular to rounding: reciprocal condition " + std::to_string(rcond) + ")";
  return out;
}

SolverPencilSpectrum spectrum_from_eigenvalues(std::vector<std::complex<double>> eigenvalues, std::size_t at_infinity) {
  SolverPencilSpectrum out;
  for (const auto& v : eigenvalues)
    if (!std::isfinite(v.real()) || !std::isfinite(v.imag()))
      throw std::invalid_argument("an eigenvalue that is not finite: count it in at_infinity");
  out.eigenvalues = std::move(eigenvalues);
  out.at_infinity = at_infinity;
  order_by_real_part(out);
  if (out.eigenvalues.empty())
    out.warnings.push_back("every eigenvalue is at infinity (constraints or a singular Aplus): no motion to read");
  out.method = "as printed";
  return out;
}

}  // namespace mlce::spectrum
