#pragma once
// Eigenvalues of a solver's own linearisation, in its discrete form. MBDyn's eigenanalysis (read by
// reader/mbdyn_eigenanalysis.hpp) builds, about the state at one time, Aplus = F/x' + c F/x and
// Aminus = F/x' - c F/x from the residual F(x', x) = 0 with c = dCoef = h/2, and solves
// Aminus v = Lambda Aplus v. For F = E x' + K x the continuous eigenvalues are those of
// x' = -E^-1 K x, and Lambda = (1 + c s) / (1 - c s): the trapezoidal (Crank-Nicolson) multiplier
// of a step 2c. The Moebius map back, s = (Lambda - 1) / (c (Lambda + 1)), is exact (no step error;
// MBDyn's own `do_eig` prints the same s to the .out). In this toolchain's units: s per time unit of
// the run, real part = the linearisation's exponent, imaginary part rad per time unit.
//
// Two kinds of Lambda are no motion and are counted, not listed: Lambda = -1 (an algebraic row, a
// constraint, where F/x' = 0: s at infinity) and beta = 0 (Lambda at infinity, a singular Aplus:
// s would read 1/c, an artefact of the map).
#include <array>
#include <complex>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mlce::spectrum {

struct SolverPencilOptions {
  /// |Lambda + 1| <= this x max(1, |Lambda|) is Lambda = -1 to rounding: s beyond ~2 / (this c), at infinity.
  double infinite_tolerance = 1e-9;
  /// |beta| <= this x |alpha| is beta = 0 (Lambda at infinity).
  double zero_beta = 1e-14;
  /// Aplus's reciprocal condition number (LU estimate) above which the pencil is solved as the standard
  /// eigenproblem of Aplus^-1 Aminus; at or below it, by QZ.
  double regular_aplus = 1e-10;
};

struct SolverPencilSpectrum {
  /// Finite continuous eigenvalues s (1 / time unit; imaginary part rad / time unit), the largest real
  /// part first (a complex pair: positive imaginary part first).
  std::vector<std::complex<double>> eigenvalues;
  std::size_t at_infinity = 0;  ///< Lambda = -1 (constraints) or beta = 0, left out
  /// The largest real part among `eigenvalues`: the linearisation's largest exponent at that time
  /// (nullopt when every eigenvalue is at infinity).
  std::optional<double> largest_real_part;
  double largest_frequency = 0.0;  ///< |Im s| / 2 pi of that eigenvalue, cycles per time unit
  std::string method;              ///< how Lambda were found ("alpha": as given)
  std::vector<std::string> warnings;
};

/// From MBDyn's alpha rows (alphar, alphai, beta). Throws std::invalid_argument on coefficient <= 0.
SolverPencilSpectrum spectrum_from_multipliers(std::span<const std::array<double, 3>> alpha, double coefficient,
                                               const SolverPencilOptions& options = {});

/// From continuous eigenvalues already mapped (MBDyn's .out table: reader::read_mbdyn_out_eigenanalyses), with
/// `at_infinity` rows that held none: ordered and read as spectrum_from_multipliers' (method "as printed").
/// Throws std::invalid_argument on an eigenvalue that is not finite.
SolverPencilSpectrum spectrum_from_eigenvalues(std::vector<std::complex<double>> eigenvalues, std::size_t at_infinity);
/// From the matrices (row-major n x n): the generalized eigenvalues of (Aminus, Aplus), as the eigenvalues
/// of Aplus^-1 Aminus where Aplus is regular (SolverPencilOptions::regular_aplus), else by QZ (Eigen's
/// GeneralizedEigenSolver), then as spectrum_from_multipliers. Cost O(n^3): bench_spectrum's solver_pencil
/// (coupled oscillators) 1.8 / 39 / 233 ms at n = 100 / 250 / 500 for the first route, 5.3 / 84 / 590 ms for
/// QZ; dense unstructured pencils converge more slowly (a scratch loop on random matrices under load: 15 s
/// and 83 s at n = 1000). Throws std::invalid_argument on sizes that do not match n x n or coefficient <= 0.
SolverPencilSpectrum spectrum_from_pencil(std::size_t n, std::span<const double> aplus, std::span<const double> aminus,
                                          double coefficient, const SolverPencilOptions& options = {});

}  // namespace mlce::spectrum
