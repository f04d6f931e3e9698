// MBDyn's eigenanalysis output (.m files: reader/mbdyn_eigenanalysis.hpp) and its map to continuous
// eigenvalues (spectrum/solver_pencil.hpp). Truth: closed-form eigenvalues of damped oscillators written
// in MBDyn's first-order residual form (the mboct-mbdyn-pkg loader's test model: two spring-mass-damper
// abstract nodes), and the eigenvalues of Hammond's isotropic-rotor matrix A by Eigen's EigenSolver
// (a second method) against QZ of the pencil MBDyn would write for x' = A x.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>  // getpid: a temporary directory of this process's own

#include "mlce/models/dynamics.hpp"
#include "mlce/models/scene.hpp"
#include "mlce/reader/mbdyn_eigenanalysis.hpp"
#include "mlce/reader/table.hpp"
#include "mlce/spectrum/solver_pencil.hpp"

namespace {

using namespace mlce;
using cd = std::complex<double>;

/// F(x', x) = E x' + K x of two oscillators m x'' + d x' + s x = 0, states (x1, x2, v1, v2).
struct Pencil {
  std::size_t n = 4;
  std::vector<double> e, k;
};
constexpr double kS1 = 5000, kM1 = 2.5, kD1 = 10, kS2 = 1000, kM2 = 3, kD2 = 20;

Pencil two_oscillators() {
  Pencil p;
  p.e = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, kM1, 0, 0, 0, 0, kM2};
  p.k = {0, 0, -1, 0, 0, 0, 0, -1, kS1, 0, kD1, 0, 0, kS2, 0, kD2};
  return p;
}

/// -d / 2m +- i sqrt(s / m - (d / 2m)^2), positive imaginary part first within a pair, larger real part first.
std::vector<cd> analytic() {
  std::vector<cd> s;
  for (const auto& [stiffness, mass, damping] : {std::array<double, 3>{kS1, kM1, kD1}, {kS2, kM2, kD2}}) {
    const double sigma = -damping / (2 * mass), omega = std::sqrt(stiffness / mass - sigma * sigma);
    s.push_back({sigma, omega});
    s.push_back({sigma, -omega});
  }
  return s;
}

/// The .m text MBDyn writes (OutputEigParams, then OutputEigFullMatrices or OutputEigSparseMatrices).
std::string m_file(const Pencil& p, double coefficient, bool sparse, double time = 1.5) {
  std::ostringstream out;
  out.precision(17);
  out << "% time: " << time << "\ndTime = " << time << ";\n% coefficient\ndCoef = " << coefficient << ";\n";
  for (const int sign : {+1, -1}) {
    const char* name = sign > 0 ? "Aplus" : "Aminus";
    out << "% F/xPrime " << (sign > 0 ? '+' : '-') << " dCoef * F/x\n" << name << " = [";
    for (std::size_t r = 0; r < p.n; ++r) {
      for (std::size_t c = 0; c < p.n; ++c) {
        const double v = p.e[r * p.n + c] + sign * coefficient * p.k[r * p.n + c];
        if (!sparse)
          out << v << ' ';
        else if (v != 0.0)
          out << r + 1 << " " << c + 1 << " " << v << ";\n";
      }
      if (!sparse) out << (r + 1 == p.n ? "];\n" : ";\n");
    }
    if (sparse) out << "];\n" << name << " = spconvert(" << name << ");\n";
  }
  return out.str();
}

/// Within `tolerance` of each |s|, and within the map's own floor: Lambda - 1 ~ 2 c s is a difference of
/// numbers near 1, so s is known to ~eps / c absolutely (1e-9 1/s at c = 1e-7; 4e-13 at MBDyn's usual 5e-4).
void expect_eigenvalues(const spectrum::SolverPencilSpectrum& s, const std::vector<cd>& truth, double tolerance,
                        double coefficient) {
  ASSERT_EQ(s.eigenvalues.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    EXPECT_NEAR(std::abs(s.eigenvalues[i] - truth[i]), 0.0,
                tolerance * std::abs(truth[i]) + 100 * std::numeric_limits<double>::epsilon() / coefficient)
        << i << ": " << s.eigenvalues[i];
}

TEST(Eigenanalysis, MatricesGiveTheOscillatorsEigenvalues) {
  for (const bool sparse : {false, true})
    for (const double coefficient : {0.05, 5e-4, 1e-7}) {
      const auto e = reader::parse_mbdyn_eigenanalysis(m_file(two_oscillators(), coefficient, sparse), "run_00.m");
      ASSERT_TRUE(e.time && e.coefficient);
      EXPECT_EQ(*e.time, 1.5);
      EXPECT_EQ(*e.coefficient, coefficient);
      EXPECT_EQ(e.size, 4U);
      EXPECT_EQ(e.sparse, sparse);
      EXPECT_TRUE(e.alpha.empty());
      const auto s = spectrum::spectrum_from_pencil(e.size, e.aplus, e.aminus, *e.coefficient);
      // The map back is exact; what is left is QZ's rounding, relative to |Lambda + 1| ~ 2 at small c s.
      expect_eigenvalues(s, analytic(), 1e-9, coefficient);
      EXPECT_EQ(s.at_infinity, 0U);
      ASSERT_TRUE(s.largest_real_part);
      EXPECT_NEAR(*s.largest_real_part, -kD1 / (2 * kM1), 1e-9 + 100 * std::numeric_limits<double>::epsilon() / coefficient);
    }
}

// MBDyn's own eigenvalues (`output eigenvectors`): alpha rows of (alphar, alphai, beta) with beta at any
// scale (LAPACK's dggev normalises neither); Lambda = -1 (a constraint) and beta = 0 are counted, not listed.
TEST(Eigenanalysis, AlphaRowsGiveTheOscillatorsEigenvalues) {
  const double c = 0.05;
  std::ostringstream text;
  text.precision(17);
  text << "% time: 2\ndTime = 2;\n% coefficient\ndCoef = " << c << ";\n% alphar, alphai, beta\nalpha = [";
  double beta = 0.37;
  for (const cd s : analytic()) {
    const cd lambda = (1.0 + c * s) / (1.0 - c * s);  // the trapezoidal multiplier of a step 2c
    text << lambda.real() * beta << ' ' << lambda.imag() * beta << ' ' << beta << ";\n";
    beta *= 7.0;
  }
  text << "-3.5 0 3.5;\n4.25 0 0;\n];\n% right eigenvectors\nVR = [\n1+i*2 1-i*2 3 4 5 6;\n];\n";
  const auto e = reader::parse_mbdyn_eigenanalysis(text.str(), "run.m");
  ASSERT_EQ(e.alpha.size(), 6U);
  EXPECT_EQ(e.size, 0U);
  const auto s = spectrum::spectrum_from_multipliers(e.alpha, *e.coefficient);
  expect_eigenvalues(s, analytic(), 1e-12, c);
  EXPECT_EQ(s.at_infinity, 2U);
}

// A constraint (an algebraic row: x5 = x1, F/x' = 0 there) adds Lambda = -1 to QZ's rounding: it is left
// out and the oscillators' eigenvalues stay.
TEST(Eigenanalysis, AConstraintIsAtInfinity) {
  const Pencil o = two_oscillators();
  Pencil p;
  p.n = 5;
  p.e.assign(25, 0.0);
  p.k.assign(25, 0.0);
  for (std::size_t r = 0; r < 4; ++r)
    for (std::size_t c = 0; c < 4; ++c) p.e[r * 5 + c] = o.e[r * 4 + c], p.k[r * 5 + c] = o.k[r * 4 + c];
  p.k[4 * 5 + 0] = -1.0, p.k[4 * 5 + 4] = 1.0;
  const auto e = reader::parse_mbdyn_eigenanalysis(m_file(p, 0.005, false), "run.m");
  const auto s = spectrum::spectrum_from_pencil(e.size, e.aplus, e.aminus, *e.coefficient);
  EXPECT_EQ(s.at_infinity, 1U);
  expect_eigenvalues(s, analytic(), 1e-9, 0.005);
}

// A singular Aplus (a row with no x' and no x: beta = 0 there) goes to QZ, which finds the finite
// eigenvalue of the other row exactly: Aminus = diag(a, 1), Aplus = diag(1, 0) gives Lambda = a and beta = 0.
TEST(Eigenanalysis, ASingularAplusIsSolvedByQz) {
  const double c = 0.01, a = 0.9;
  const auto s = spectrum::spectrum_from_pencil(2, std::vector<double>{1, 0, 0, 0}, std::vector<double>{a, 0, 0, 1}, c);
  EXPECT_NE(s.method.find("QZ"), std::string::npos) << s.method;
  EXPECT_EQ(s.at_infinity, 1U);
  ASSERT_EQ(s.eigenvalues.size(), 1U);
  EXPECT_NEAR(s.eigenvalues[0].real(), (a - 1) / (c * (a + 1)), 1e-12);
  // The regular oscillators take the standard route and say so.
  const auto e = reader::parse_mbdyn_eigenanalysis(m_file(two_oscillators(), 0.05, false), "run.m");
  EXPECT_NE(spectrum::spectrum_from_pencil(e.size, e.aplus, e.aminus, *e.coefficient).method.find("LU"), std::string::npos);
}

// A second method on a rotor: the pencil (I - c A, I + c A) of x' = A x for Hammond's isotropic rotor
// (the multiblade time-invariant form, 12 states) against Eigen's EigenSolver on A.
TEST(Eigenanalysis, HammondsPencilGivesTheEigenvaluesOfA) {
  const auto scene = models::load_scene("", {"--rpm", "200"});
  const Eigen::MatrixXd a = models::time_invariant_form(scene).A;
  const auto n = static_cast<std::size_t>(a.rows());
  const double c = 0.5e-3;  // a 1 ms step, as the bundled MBDyn runs
  std::vector<double> plus(n * n), minus(n * n);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t k = 0; k < n; ++k) {
      const double identity = r == k ? 1.0 : 0.0, ark = a(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k));
      plus[r * n + k] = identity - c * ark;  // F = x' - A x: F/x' = I, F/x = -A
      minus[r * n + k] = identity + c * ark;
    }
  const auto s = spectrum::spectrum_from_pencil(n, plus, minus, c);
  Eigen::EigenSolver<Eigen::MatrixXd> direct(a, false);
  std::vector<cd> truth(direct.eigenvalues().data(), direct.eigenvalues().data() + n);
  ASSERT_EQ(s.eigenvalues.size(), n);
  // Matched as sets (four lag modes share one real part: their order is the sort's, not the physics').
  std::vector<cd> left = s.eigenvalues;
  double largest = -1e300;
  for (const cd t : truth) {
    const auto nearest = std::min_element(left.begin(), left.end(), [t](cd x, cd y) { return std::abs(x - t) < std::abs(y - t); });
    EXPECT_NEAR(std::abs(*nearest - t), 0.0, 1e-8 * std::max(1.0, std::abs(t))) << t;
    left.erase(nearest);
    largest = std::max(largest, t.real());
  }
  EXPECT_NEAR(*s.largest_real_part, largest, 1e-8);
  std::printf("Hammond 200 rpm: largest real part %.9f (EigenSolver on A %.9f)\n", *s.largest_real_part, largest);
}

// Huge and tiny time scales: the same oscillators in units where every rate is 1e150 or 1e-150 times
// theirs (E scaled, K kept; c in the new time unit) read the same eigenvalues in those units.
TEST(Eigenanalysis, ScaleOfTimeDoesNotMatter) {
  for (const double scale : {1e150, 1e-150}) {
    Pencil p = two_oscillators();
    for (double& v : p.e) v /= scale;  // x' in the new unit: rates times `scale`
    const auto e = reader::parse_mbdyn_eigenanalysis(m_file(p, 0.05 / scale, false), "run.m");
    const auto s = spectrum::spectrum_from_pencil(e.size, e.aplus, e.aminus, *e.coefficient);
    std::vector<cd> truth = analytic();
    for (cd& v : truth) v *= scale;
    expect_eigenvalues(s, truth, 1e-9, std::numeric_limits<double>::infinity());
  }
}

void expect_error(const std::string& text, const std::string& message) {
  try {
    reader::parse_mbdyn_eigenanalysis(text, "bad.m");
    ADD_FAILURE() << "no error for: " << text;
  } catch (const reader::ReadError& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(Eigenanalysis, BadInputIsOneErrorNamingTheLine) {
  const std::string head = "dTime = 0;\ndCoef = 0.5;\n";
  expect_error(head + "Aplus = [1 2;\n3 x];\nAminus = [1 2;\n3 4];\n", "bad.m:4: Aplus: expected a finite number, found 'x'");
  expect_error(head + "alpha = [1 2;\n];\n", "bad.m:3: alpha: a row of 2 values");
  expect_error(head + "alpha = [1 0 1;\n2 0 1;\n", "bad.m:3: alpha: the matrix is not closed");
  expect_error(head + "Aplus = [1 2 3;\n4 5 6];\nAminus = [1 2 3;\n4 5 6];\n", "bad.m:3: Aplus: 2 rows of 3 values");
  expect_error(head + "Aplus = [1 2;\n3 4];\nAminus = [1];\n", "Aplus is 2 x 2, Aminus 1 x 1");
  expect_error(head + "Aplus = [1 2;\n3 4];\n", "holds Aplus but not Aminus");
  expect_error(head + "Aplus = [0 1 2;\n];\nAplus = spconvert(Aplus);\nAminus = [1 1 2;\n];\nAminus = spconvert(Aminus);\n",
               "bad.m:3: Aplus: index 0");
  expect_error(head, "holds neither the eigenvalues");
  expect_error("dTime = 0;\nalpha = [1 0 1;\n];\n", "no dCoef");
  expect_error("dCoef = 0;\nalpha = [1 0 1;\n];\n", "dCoef = 0");
  expect_error("dCoef = nan;\nalpha = [1 0 1;\n];\n", "bad.m:1: dCoef: expected a finite number");
  expect_error(head + "alpha = [1 1 2 3;\n", "bad.m:3: alpha: a row of 4 values");
}

TEST(Eigenanalysis, FilesOfASetInAnalysisOrder) {
  const auto dir = std::filesystem::temp_directory_path() / ("mlce_eig_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* name : {"run_10.m", "run_2.m", "run.m", "run_x.m", "run_00.m", "other_1.m", "run_3.mov"})
    std::ofstream(dir / name) << "dCoef = 1;\n";
  const auto files = reader::mbdyn_eigenanalysis_files((dir / "run").string());
  std::vector<std::string> names;
  for (const auto& f : files) names.push_back(std::filesystem::path(f).filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"run.m", "run_00.m", "run_2.m", "run_10.m"}));
  EXPECT_TRUE(reader::mbdyn_eigenanalysis_files((dir / "none").string()).empty());
  std::filesystem::remove_all(dir);
}

}  // namespace
