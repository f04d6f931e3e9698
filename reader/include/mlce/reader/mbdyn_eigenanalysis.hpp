#pragma once
// MBDyn's eigenanalysis output: the Octave script PREFIX.m, or PREFIX_<k>.m for the k-th of several
// analyses, that `eigenanalysis: ...` in the initial-value block writes (format doc section 1 lists
// `.m`; the layout below is MBDyn's DataManager::OutputEigParams, OutputEigFullMatrices,
// OutputEigSparseMatrices and OutputEigenvectors):
//   % time: <t>            dTime = <t>;
//   % coefficient          dCoef = <h/2>;
//   `output matrices`:        Aplus = [row; row; ...];  Aminus = [...];   (dense, n x n)
//   `output sparse matrices`: Aplus = [i j v; ...]; Aplus = spconvert(Aplus);  (1-based triplets)
//   `output geometry`:        labels = [...]; idx = [...]; X0 = [...];   (not read)
//   `output eigenvectors`:    alpha = [alphar alphai beta; ...];  VL = [...]; VR = [...];  (VL, VR not read)
// Aplus = F/x' + dCoef F/x and Aminus = F/x' - dCoef F/x are the Jacobians of the residual F(x', x)
// about the state at dTime; alpha holds the generalized eigenvalues Lambda = (alphar + i alphai) / beta
// of Aminus v = Lambda Aplus v. What they mean (s = (Lambda - 1) / (dCoef (Lambda + 1))) is the
// estimators' business (mlce/linearised.hpp); this reader returns what the file holds.
//
// Every analysis also prints its eigenvalues to PREFIX.out (MBDyn's solver.cc, output_eigenvalues),
// whatever else it writes: after LAPACK's status line (`Info: 0, success BALANC="N" ILO=1 IHI=n ...`;
// ARPACK: `INFO: 0`) a table
//   Mode n.       Real          Imag             Damp %     Freq Hz
//          1:          -2 -      44.6766 j      4.47214     -7.11049
// one row per eigenvalue: s = sigma +- i |omega| (the continuous eigenvalue of the Moebius map above,
// 1/time unit and rad/time unit), the damping ratio in per cent and omega / 2 pi, sorted by frequency.
// Older MBDyn (its solver.cc of the 2000s) printed omega with its sign after a `+`, `0 - PI j ... PI`
// where Lambda = -1, and mapped s = ln(Lambda) / h instead (exact for Lambda = e^(s h), not for the
// trapezoidal multiplier: s (1 + (h s)^2 / 12 + ...)). The analysis runs right after the step whose Step
// line precedes the table (Solver::EigAll after the step's output), so that line's time is the
// analysis's. read_mbdyn_out_eigenanalyses reads these tables: the eigenvalues as printed (the .out
// stream's precision: 6 significant digits by default), without dCoef or the matrices.
#include <array>
#include <complex>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mlce::reader {

struct MbdynEigenanalysis {
  std::string source;
  std::optional<double> time;         ///< dTime
  std::optional<double> coefficient;  ///< dCoef (half the step the matrices were built with)
  /// alphar, alphai, beta of each eigenvalue MBDyn computed; empty without `output eigenvectors`.
  std::vector<std::array<double, 3>> alpha;
  std::size_t size = 0;               ///< n of Aplus and Aminus; 0 when the matrices are not in the file
  std::vector<double> aplus, aminus;  ///< row-major n x n (sparse triplets expanded)
  bool sparse = false;                ///< the matrices were written as triplets
  /// From a .out table only (read_mbdyn_out_eigenanalyses): s as MBDyn printed them, and the rows that
  /// hold none (an infinite or NaN real part, or `PI`: Lambda = -1, a constraint's algebraic row).
  std::vector<std::complex<double>> printed;
  std::size_t printed_at_infinity = 0;
};

/// Largest n of Aplus/Aminus read (they are held dense, 2 n^2 doubles, and their eigenvalues cost O(n^3):
/// about 2 min at this n, spectrum/solver_pencil.hpp). A larger model's eigenvalues come from MBDyn's own
/// solution (`output eigenvectors` writes alpha).
inline constexpr std::size_t kLargestEigenanalysisMatrix = 2000;

/// Throws ReadError naming source:line on a value that is no finite number, an alpha row that is not
/// three numbers, matrices that are not square or differ in size, a triplet index below 1, an
/// unterminated matrix, or a file that holds neither alpha nor both matrices.
MbdynEigenanalysis parse_mbdyn_eigenanalysis(std::string_view text, const std::string& source);
MbdynEigenanalysis read_mbdyn_eigenanalysis(const std::string& path);

/// The eigenvalue tables of an MBDyn .out file (layout above), in the order written: each one analysis whose
/// `source` is PATH:LINE of its `Mode n.` header, `time` that of the last Step line before it (none before
/// the first), `printed` its eigenvalues. A status line other than success (`Info: k` with k != 0: the QZ
/// iteration failed, or ARPACK's `INFO: k`) is a warning naming the line. Throws ReadError naming
/// PATH:LINE on a row that is not `k: REAL +|- IMAG j DAMP FREQ` (k counting from 1), a number that is
/// not one, or a Step line without a step and a time.
struct MbdynOutEigenanalyses {
  std::vector<MbdynEigenanalysis> analyses;
  std::vector<std::string> warnings;
};
MbdynOutEigenanalyses parse_mbdyn_out_eigenanalyses(std::string_view text, const std::string& source);
MbdynOutEigenanalyses read_mbdyn_out_eigenanalyses(const std::string& path);

/// The eigenanalysis files of the set at `prefix`: PREFIX.m and PREFIX_<suffix>.m, those with numeric
/// suffixes in numeric order (PREFIX_2.m before PREFIX_10.m). Empty when there is none.
std::vector<std::string> mbdyn_eigenanalysis_files(const std::string& prefix);

}  // namespace mlce::reader
