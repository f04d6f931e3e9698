// MBDyn's eigenanalysis output (.m files: reader/mbdyn_eigenanalysis.hpp) and its map to continuous
// eigenvalues (spectrum/solver_pencil.hpp). Truth: closed-form eigenvalues of damped oscillators written
// in MBDyn's first-order residual form (the mboct-mbdyn-pkg loader's test model: two spring-mass-damper
// abstract nodes), and the eigenvalues of Hammond's isotropic-rotor matrix A by Eigen's EigenSolver
// (a second method) against QZ of the pencil MBDyn would write for x' = A x. The same oscillators in a
// NetCDF file laid out as MBDyn writes its eig.* variables (reader/mbdyn_netcdf.hpp), in the eigenvalue
// tables MBDyn prints to the .out, and through the CLI.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <netcdf.h>
#include <nlohmann/json.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>  // getpid: a temporary directory of this process's own

#include "mlce/models/dynamics.hpp"
#include "mlce/models/scene.hpp"
#include "cli_harness.hpp"
#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/mbdyn_eigenanalysis.hpp"
#include "mlce/reader/mbdyn_netcdf.hpp"
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

/// `parse(text)` throws a ReadError whose message holds `message`.
template <class Parse>
void expect_read_error(Parse parse, const std::string& text, const std::string& message) {
  try {
    parse(text);
    ADD_FAILURE() << "no error for: " << text;
  } catch (const reader::ReadError& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

void expect_error(const std::string& text, const std::string& message) {
  expect_read_error([](const std::string& t) { return reader::parse_mbdyn_eigenanalysis(t, "bad.m"); }, text, message);
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

// ---- the .out's eigenvalue tables -----------------------------------------------------------------------

/// The eigenvalue table MBDyn's solver.cc prints to the .out (output_eigenvalues after do_eig), from alpha
/// rows: s = (2 / h) (Lambda - 1) / (Lambda + 1) in do_eig's real arithmetic, sorted by frequency then real
/// part, each row `setw(8) k ": " setw(12) sigma " + "|" - " setw(12) |omega| " j    " setw(12) csi "    "
/// setw(12) freq` at the stream's `precision`. MBDyn's own formatting, replayed: the reader's truth is
/// the oscillators' closed form, which the alpha rows are made from.
std::string out_table(const std::vector<std::array<double, 3>>& alpha, double h, int precision) {
  struct Row {
    double sigma, omega, csi, freq;
  };
  std::vector<Row> rows;
  for (const auto& [re, im, b] : alpha) {
    double d = re + b;
    d *= d;
    d += im * im;
    d *= h / 2.;
    Row r{(re * re - b * b + im * im) / d, 2. * b * im / d, 0.0, 0.0};
    if (im != 0.) {
      const double m = r.sigma * r.sigma + r.omega * r.omega;
      r.csi = m > std::numeric_limits<double>::epsilon() ? -100 * r.sigma / std::sqrt(m) : 0.;
      r.freq = r.omega / (2 * M_PI);
    } else {
      r.csi = std::abs(r.sigma) < std::numeric_limits<double>::epsilon() ? 0. : -100. * std::copysign(1, r.sigma);
    }
    rows.push_back(r);
  }
  std::sort(rows.begin(), rows.end(), [](const Row& x, const Row& y) { return x.freq == y.freq ? x.sigma < y.sigma : x.freq < y.freq; });
  std::ostringstream out;
  out.precision(precision);
  out << "Mode n. " "  " "    Real    " "   " "    Imag    " "  " "    " "   Damp %   " "  Freq Hz" << '\n';
  for (std::size_t k = 0; k < rows.size(); ++k)
    out << std::setw(8) << k + 1 << ": " << std::setw(12) << rows[k].sigma << (rows[k].omega >= 0. ? " + " : " - ") << std::setw(12)
        << std::fabs(rows[k].omega) << " j" << "    " << std::setw(12) << rows[k].csi << "    " << std::setw(12) << rows[k].freq << '\n';
  return out.str();
}

/// The oscillators' multipliers Lambda = (1 + c s) / (1 - c s) at c = h / 2, as alpha rows (beta = 1), and
/// a constraint's Lambda = -1.
std::vector<std::array<double, 3>> oscillator_alpha(double h) {
  std::vector<std::array<double, 3>> alpha;
  for (const cd s : analytic()) {
    const cd lambda = (1.0 + h / 2 * s) / (1.0 - h / 2 * s);
    alpha.push_back({lambda.real(), lambda.imag(), 1.0});
  }
  alpha.push_back({-1.0, 0.0, 1.0});
  return alpha;
}

std::string step_line(long step, double time) {
  return fmt::format("Step {} {} 0.001 2 1e-12 0 0 1\n", step, time);
}

TEST(EigenanalysisOut, TablesGiveTheOscillatorsEigenvaluesAtTheirStepTimes) {
  const double h = 1e-3;
  std::string text = "# Key for lines starting with \"Step\":\n# Step Time TStep NIter ResErr SolErr SolConv Out\n";
  text += step_line(0, 0) + step_line(1, 0.001) + step_line(2, 0.002);
  text += "Info: 0, success BALANC=\"N\" ILO=1 IHI=5 ABNRM=-1 BBNRM=-1\n" + out_table(oscillator_alpha(h), h, 6);
  text += step_line(3, 0.003) + step_line(2, 0.0025) + step_line(4, 0.004);  // a debug build's step 2 again: not a time
  const std::size_t failed_line = 16;  // 2 comments, 3 Step lines, a status line, a header, 5 rows, 3 Step lines
  text += "Info: 3, the QZ iteration failed, but eigenvalues 4->5 should be correct\n" + out_table(oscillator_alpha(h), h, 16);
  // Older MBDyn: omega printed with its sign after " + ", and Lambda = -1 as "0 - PI j ... PI".
  text += step_line(5, 0.005) + "Info: 0, success\nMode n.       Real          Imag             Damp %     Freq Hz\n"
          "       1:          -2 +     -44.6766 j      4.47214     -7.11049\n"
          "       2:    -3.33333 +     -17.9505 j      18.2574     -2.85691\n"
          "       3:            0 -           PI j            0    PI\n"
          "       4:    -3.33333 +      17.9505 j      18.2574      2.85691\n"
          "       5:          -2 +      44.6766 j      4.47214      7.11049\n"
          "End of simulation\n";
  const auto r = reader::parse_mbdyn_out_eigenanalyses(text, "run.out");
  ASSERT_EQ(r.analyses.size(), 3U);
  const std::vector<double> times = {0.002, 0.004, 0.005}, tolerance = {1e-5, 1e-12, 1e-5};
  const std::vector<std::size_t> header_lines = {7, failed_line + 1, failed_line + 9};  // 5 rows, a Step line, a status line
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& e = r.analyses[k];
    EXPECT_EQ(e.source, "run.out:" + std::to_string(header_lines[k])) << k;
    ASSERT_TRUE(e.time.has_value());
    EXPECT_EQ(*e.time, times[k]);
    EXPECT_FALSE(e.coefficient.has_value());
    EXPECT_EQ(e.printed.size(), 4U);
    EXPECT_EQ(e.printed_at_infinity, 1U) << k;  // the constraint: NaN (0 / 0) in do_eig, or PI
    const auto s = spectrum::spectrum_from_eigenvalues(e.printed, e.printed_at_infinity);
    EXPECT_EQ(s.at_infinity, 1U);
    expect_eigenvalues(s, analytic(), tolerance[k], std::numeric_limits<double>::infinity());
    EXPECT_NEAR(*s.largest_real_part, -kD1 / (2 * kM1), 1e-5);
  }
  ASSERT_EQ(r.warnings.size(), 1U);
  EXPECT_NE(r.warnings[0].find("run.out:" + std::to_string(failed_line) + ": MBDyn's eigensolver reported 'Info: 3, the QZ"),
            std::string::npos)
      << r.warnings[0];
  // A table before any Step line has no time; a .out without tables has no analysis.
  const auto early = reader::parse_mbdyn_out_eigenanalyses(out_table(oscillator_alpha(h), h, 6), "early.out");
  ASSERT_EQ(early.analyses.size(), 1U);
  EXPECT_FALSE(early.analyses[0].time.has_value());
  EXPECT_TRUE(reader::parse_mbdyn_out_eigenanalyses(step_line(0, 0) + step_line(1, 0.1), "plain.out").analyses.empty());
  // Beyond the double range (a hand-edited table): 1e-400 reads 0, 1e400 is infinite, so at infinity.
  const auto extreme = reader::parse_mbdyn_out_eigenanalyses(
      step_line(0, 0) + "Mode n. Real Imag Damp % Freq Hz\n  1: 1e-400 + 44.6766 j 0 7.11049\n  2: 1e400 + 0 j -100 0\n", "x.out");
  ASSERT_EQ(extreme.analyses.size(), 1U);
  ASSERT_EQ(extreme.analyses[0].printed.size(), 1U);
  EXPECT_EQ(extreme.analyses[0].printed[0], cd(0.0, 44.6766));
  EXPECT_EQ(extreme.analyses[0].printed_at_infinity, 1U);
}

void expect_out_error(const std::string& text, const std::string& message) {
  expect_read_error([](const std::string& t) { return reader::parse_mbdyn_out_eigenanalyses(t, "bad.out"); }, text, message);
}

TEST(EigenanalysisOut, BadRowsAreOneErrorNamingTheLine) {
  const std::string head = step_line(0, 0) + "Mode n.       Real          Imag             Damp %     Freq Hz\n";
  expect_out_error(head + "       1:          -2 +      44.6766 j      4.47214\n", "bad.out:3: 6 fields where 7 were; expected 'k: REAL +|- IMAG j");
  expect_out_error(head + "       1:          -2 +      44.6766 j      4.47214  7.1\n       3:  -2 - 44.6766 j 4.47 -7.1\n",
                   "bad.out:4: row 3: where row 2: was next");
  expect_out_error(head + "       1:          x2 +      44.6766 j      4.47214  7.1\n", "bad.out:3: real part: expected a number, found 'x2'");
  expect_out_error(head + "       1:          -2 *      44.6766 j      4.47214  7.1\n", "bad.out:3: '*' where the imaginary part's sign");
  expect_out_error(head + "       1:          -2 +      44.6766 i      4.47214  7.1\n", "bad.out:3: 'i' where 'j' was");
  expect_out_error(head + "       1:          -2 +      44.6766 j      4.47214  Hz\n", "bad.out:3: frequency: expected a number, found 'Hz'");
  expect_out_error("Step x 0.1 0.1 1 0 0 0 1\n", "bad.out:1: expected 'Step STEP TIME");
  expect_out_error("Step 1 nan 0.1 1 0 0 0 1\n", "bad.out:1: expected 'Step STEP TIME");
}

// ---- NetCDF (eig.* variables) ------------------------------------------------------------------------

#define NC_OK(call) ASSERT_EQ((call), NC_NOERR) << #call

/// Options of the file below: what to break for the error tests.
struct EigNetcdf {
  double coefficient = 5e-4;
  bool dense_minus = true;       ///< eig.0.Aminus present
  double alpha_fill_row = -1;    ///< >= 0: eig.2.alpha's row left unwritten (fill value)
  double triplet_index = 0;      ///< > 0: eig.1.Aplus's first row index replaced by this
  int format = 0;                ///< NC_NETCDF4: HDF5 underneath (read in a child process)
};

/// A classic NetCDF file laid out as MBDyn 1.7 writes it (OutputHandler::Open: `time` unlimited, `vec3`;
/// DataManager::OutputEigPrepare: `eigensolutions`, `eig_iSize`, eig.step/time/dCoef/idx; then per analysis
/// OutputEigFullMatrices, OutputEigSparseMatrices, OutputEigenvectors), two output records of node 1:
///   eig.0 at t = 0: dense Aplus/Aminus as FullMatrixHandler stores them, column by column;
///   eig.1 at t = 0.01: sparse triplets along the record dimension (8: they grow it past the 2 outputs);
///   eig.2 at t = 0.02: alpha (the 4 eigenvalues at beta scales 0.37 ... 0.37 * 7^3, Lambda = -1, beta = 0);
///   eig.3 at t = 5: planned, never performed (its time and dCoef hold the fill value).
void write_eig_netcdf(const std::string& path, const EigNetcdf& o = {}) {
  const Pencil p = two_oscillators();
  const double c = o.coefficient;
  int id = 0, t_dim = 0, v3 = 0, eig_dim = 0, size_dim = 0, cplx = 0, idx_dim = 0, nvec = 0;
  NC_OK(nc_create(path.c_str(), NC_CLOBBER | o.format, &id));
  NC_OK(nc_def_dim(id, "time", NC_UNLIMITED, &t_dim));
  NC_OK(nc_def_dim(id, "vec3", 3, &v3));
  NC_OK(nc_def_dim(id, "eigensolutions", 4, &eig_dim));
  NC_OK(nc_def_dim(id, "eig_iSize", 4, &size_dim));
  NC_OK(nc_def_dim(id, "complex_var_dim", 2, &cplx));
  NC_OK(nc_def_dim(id, "eig_iIdxSize", 1, &idx_dim));
  NC_OK(nc_def_dim(id, "eig_2_iNVec_out", 6, &nvec));
  int time = 0, x = 0, step = 0, etime = 0, coef = 0, idx = 0, a0p = 0, a0m = 0, a1p = 0, a1m = 0, alpha = 0, vr = 0;
  const int tv3[] = {t_dim, v3}, sq[] = {size_dim, size_dim}, eig_idx[] = {eig_dim, idx_dim}, al[] = {nvec, v3},
            vrd[] = {cplx, nvec, size_dim};
  NC_OK(nc_def_var(id, "time", NC_DOUBLE, 1, &t_dim, &time));
  NC_OK(nc_def_var(id, "node.struct.1.X", NC_DOUBLE, 2, tv3, &x));
  NC_OK(nc_def_var(id, "eig.step", NC_INT, 1, &eig_dim, &step));
  NC_OK(nc_def_var(id, "eig.time", NC_DOUBLE, 1, &eig_dim, &etime));
  NC_OK(nc_def_var(id, "eig.dCoef", NC_DOUBLE, 1, &eig_dim, &coef));
  NC_OK(nc_def_var(id, "eig.idx", NC_INT, 2, eig_idx, &idx));
  NC_OK(nc_def_var(id, "eig.0.Aplus", NC_DOUBLE, 2, sq, &a0p));
  if (o.dense_minus) {
    NC_OK(nc_def_var(id, "eig.0.Aminus", NC_DOUBLE, 2, sq, &a0m));
  }
  NC_OK(nc_def_var(id, "eig.1.Aplus", NC_DOUBLE, 2, tv3, &a1p));
  NC_OK(nc_def_var(id, "eig.1.Aminus", NC_DOUBLE, 2, tv3, &a1m));
  NC_OK(nc_def_var(id, "eig.2.alpha", NC_DOUBLE, 2, al, &alpha));
  NC_OK(nc_def_var(id, "eig.2.VR", NC_DOUBLE, 3, vrd, &vr));
  NC_OK(nc_enddef(id));
  for (std::size_t r = 0; r < 2; ++r) {
    const std::size_t start[] = {r, 0}, count[] = {1, 3};
    const double t = 0.01 * static_cast<double>(r), pos[] = {1.0 + t, 2.0, 3.0};
    NC_OK(nc_put_var1_double(id, time, &r, &t));
    NC_OK(nc_put_vara_double(id, x, start, count, pos));
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const double t = 0.01 * static_cast<double>(k);
    const int s = static_cast<int>(k);
    NC_OK(nc_put_var1_double(id, etime, &k, &t));
    NC_OK(nc_put_var1_double(id, coef, &k, &c));
    NC_OK(nc_put_var1_int(id, step, &k, &s));
  }
  for (const int sign : {+1, -1}) {
    std::vector<double> column_major(16);
    std::size_t record = 0;
    for (std::size_t r = 0; r < 4; ++r)
      for (std::size_t col = 0; col < 4; ++col) {
        const double v = p.e[r * 4 + col] + sign * c * p.k[r * 4 + col];
        column_major[col * 4 + r] = v;
        if (v == 0.0) continue;
        double t[] = {static_cast<double>(r + 1), static_cast<double>(col + 1), v};
        if (record == 0 && sign > 0 && o.triplet_index > 0) t[0] = o.triplet_index;
        const std::size_t start[] = {record++, 0}, count[] = {1, 3};
        NC_OK(nc_put_vara_double(id, sign > 0 ? a1p : a1m, start, count, t));
      }
    if (sign > 0 || o.dense_minus) {
      NC_OK(nc_put_var_double(id, sign > 0 ? a0p : a0m, column_major.data()));
    }
  }
  double beta = 0.37;
  std::size_t row = 0;
  const auto put_alpha = [&](double ar, double ai, double b) {
    const std::size_t start[] = {row, 0}, count[] = {1, 3};
    const double v[] = {ar, ai, b};
    if (static_cast<double>(row) != o.alpha_fill_row) {
      NC_OK(nc_put_vara_double(id, alpha, start, count, v));
    }
    ++row;
  };
  for (const cd s : analytic()) {
    const cd lambda = (1.0 + c * s) / (1.0 - c * s);
    put_alpha(lambda.real() * beta, lambda.imag() * beta, beta);
    beta *= 7.0;
  }
  put_alpha(-3.5, 0, 3.5);
  put_alpha(4.25, 0, 0);
  NC_OK(nc_close(id));
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("mlce_eig_nc_" + std::to_string(::getpid()) + "_" + name)).string();
}

TEST(EigenanalysisNetcdf, EveryLayoutGivesTheOscillatorsEigenvalues) {
  const std::string path = temp_path("run.nc");
  write_eig_netcdf(path);
  const auto r = reader::read_mbdyn_netcdf_eigenanalyses(path);
  ASSERT_EQ(r.analyses.size(), 3U);
  ASSERT_EQ(r.warnings.size(), 1U);
  EXPECT_NE(r.warnings[0].find(path + ":eig.3: planned but not performed"), std::string::npos) << r.warnings[0];
  const Pencil p = two_oscillators();
  const double c = 5e-4;
  for (std::size_t k = 0; k < 2; ++k) {  // dense (stored transposed) and sparse: the same matrices, row-major
    const auto& e = r.analyses[k];
    EXPECT_EQ(e.source, path + ":eig." + std::to_string(k));
    EXPECT_EQ(*e.time, 0.01 * static_cast<double>(k));
    EXPECT_EQ(*e.coefficient, c);
    EXPECT_EQ(e.sparse, k == 1);
    ASSERT_EQ(e.size, 4U);
    for (std::size_t i = 0; i < 16; ++i) {
      EXPECT_EQ(e.aplus[i], p.e[i] + c * p.k[i]) << k << ", " << i;
      EXPECT_EQ(e.aminus[i], p.e[i] - c * p.k[i]) << k << ", " << i;
    }
    expect_eigenvalues(spectrum::spectrum_from_pencil(e.size, e.aplus, e.aminus, c), analytic(), 1e-9, c);
  }
  const auto& a = r.analyses[2];
  EXPECT_EQ(a.size, 0U);
  ASSERT_EQ(a.alpha.size(), 6U);
  const auto s = spectrum::spectrum_from_multipliers(a.alpha, *a.coefficient);
  expect_eigenvalues(s, analytic(), 1e-12, c);
  EXPECT_EQ(s.at_infinity, 2U);

  // The 8 triplets grew the record dimension past the 2 outputs: the time histories still read, 2 records.
  const auto set = reader::read_mbdyn_netcdf(path, {reader::parse_channel_spec("node:1:x")});
  ASSERT_EQ(set.time.size(), 2U);
  EXPECT_EQ(set.values[0][1], 1.01);
  ASSERT_FALSE(set.warnings.empty());
  EXPECT_NE(set.warnings[0].find("records 2..7 hold no time"), std::string::npos) << set.warnings[0];
  // ... and the inventory lists no eigenanalysis variable as a time history.
  for (const auto& v : reader::describe_mbdyn_netcdf(path).variables) EXPECT_NE(v.name.rfind("eig.", 0), 0U) << v.name;

  // The same file as netCDF-4 (HDF5): read in a child process, handed back through a pipe, the same numbers.
  const std::string path4 = temp_path("run4.nc");
  write_eig_netcdf(path4, {.format = NC_NETCDF4});
  const auto r4 = reader::read_mbdyn_netcdf_eigenanalyses(path4);
  ASSERT_EQ(r4.analyses.size(), 3U);
  EXPECT_EQ(r4.warnings.size(), 1U);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(r4.analyses[k].source, path4 + ":eig." + std::to_string(k));
    EXPECT_EQ(r4.analyses[k].time, r.analyses[k].time);
    EXPECT_EQ(r4.analyses[k].coefficient, r.analyses[k].coefficient);
    EXPECT_EQ(r4.analyses[k].alpha, r.analyses[k].alpha);
    EXPECT_EQ(r4.analyses[k].size, r.analyses[k].size);
    EXPECT_EQ(r4.analyses[k].aplus, r.analyses[k].aplus);
    EXPECT_EQ(r4.analyses[k].aminus, r.analyses[k].aminus);
    EXPECT_EQ(r4.analyses[k].sparse, r.analyses[k].sparse);
  }
  std::filesystem::remove(path);
  std::filesystem::remove(path4);
}

TEST(EigenanalysisNetcdf, BadInputIsOneErrorNamingTheVariable) {
  const std::string path = temp_path("bad.nc");
  const auto expect_error = [&](const EigNetcdf& o, const std::string& what) {
    write_eig_netcdf(path, o);
    try {
      (void)reader::read_mbdyn_netcdf_eigenanalyses(path);
      ADD_FAILURE() << "no error, expected: " << what;
    } catch (const reader::ReadError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error({.coefficient = 0.0}, path + ":eig.0: 'eig.dCoef' = 0");
  expect_error({.coefficient = -1e-3}, "expected a positive number (half a time step)");
  expect_error({.dense_minus = false}, path + ":eig.0: holds Aplus but not Aminus");
  expect_error({.alpha_fill_row = 2}, "'eig.2.alpha' number 6: holds the NetCDF fill value");
  expect_error({.triplet_index = 5}, path + ": eig.1.Aplus: index 5");
  expect_error({.triplet_index = 1.5}, "expected a whole number from 1 to 4");
  // A size beyond what the reader holds dense is refused as the size, before any index is read against it.
  {
    int id = 0, t_dim = 0, v3 = 0, eig_dim = 0, size_dim = 0, etime = 0, coef = 0, plus = 0, minus = 0;
    NC_OK(nc_create(path.c_str(), NC_CLOBBER, &id));
    NC_OK(nc_def_dim(id, "time", NC_UNLIMITED, &t_dim));
    NC_OK(nc_def_dim(id, "vec3", 3, &v3));
    NC_OK(nc_def_dim(id, "eigensolutions", 1, &eig_dim));
    NC_OK(nc_def_dim(id, "eig_iSize", 2500, &size_dim));
    const int tv3[] = {t_dim, v3};
    NC_OK(nc_def_var(id, "eig.time", NC_DOUBLE, 1, &eig_dim, &etime));
    NC_OK(nc_def_var(id, "eig.dCoef", NC_DOUBLE, 1, &eig_dim, &coef));
    NC_OK(nc_def_var(id, "eig.0.Aplus", NC_DOUBLE, 2, tv3, &plus));
    NC_OK(nc_def_var(id, "eig.0.Aminus", NC_DOUBLE, 2, tv3, &minus));
    NC_OK(nc_enddef(id));
    const std::size_t first = 0, start[] = {0, 0}, one[] = {1, 3};
    const double zero = 0.0, c = 1e-3, triplet[] = {2400, 2400, 1.0};
    NC_OK(nc_put_var1_double(id, etime, &first, &zero));
    NC_OK(nc_put_var1_double(id, coef, &first, &c));
    NC_OK(nc_put_vara_double(id, plus, start, one, triplet));
    NC_OK(nc_put_vara_double(id, minus, start, one, triplet));
    NC_OK(nc_close(id));
    try {
      (void)reader::read_mbdyn_netcdf_eigenanalyses(path);
      ADD_FAILURE() << "no error for a 2500 x 2500 matrix";
    } catch (const reader::ReadError& e) {
      EXPECT_NE(std::string(e.what()).find("eig.0.Aplus: 2500 x 2500: more than the 2000 this reader holds dense"),
                std::string::npos)
          << e.what();
    }
  }
  // A file with no eigenanalysis is none, not an error: the CLI says so.
  {
    int id = 0, dim = 0, v = 0;
    NC_OK(nc_create(path.c_str(), NC_CLOBBER, &id));
    NC_OK(nc_def_dim(id, "time", NC_UNLIMITED, &dim));
    NC_OK(nc_def_var(id, "time", NC_DOUBLE, 1, &dim, &v));
    NC_OK(nc_close(id));
    const auto none = reader::read_mbdyn_netcdf_eigenanalyses(path);
    EXPECT_TRUE(none.analyses.empty());
    EXPECT_TRUE(none.warnings.empty());
  }
  std::filesystem::remove(path);
}

// A sparse matrix of more triplets than the reader takes in one block (2^16 records), in a file whose
// record dimension they grow: every triplet read, in order, and nothing after the last one.
TEST(EigenanalysisNetcdf, ManyTripletsAreReadAcrossBlocks) {
  const std::string path = temp_path("many.nc");
  constexpr std::size_t n = 300;
  int id = 0, t_dim = 0, v3 = 0, eig_dim = 0, size_dim = 0, time = 0, etime = 0, coef = 0, plus = 0, minus = 0;
  NC_OK(nc_create(path.c_str(), NC_CLOBBER, &id));
  NC_OK(nc_def_dim(id, "time", NC_UNLIMITED, &t_dim));
  NC_OK(nc_def_dim(id, "vec3", 3, &v3));
  NC_OK(nc_def_dim(id, "eigensolutions", 1, &eig_dim));
  NC_OK(nc_def_dim(id, "eig_iSize", n, &size_dim));
  const int tv3[] = {t_dim, v3};
  NC_OK(nc_def_var(id, "time", NC_DOUBLE, 1, &t_dim, &time));
  NC_OK(nc_def_var(id, "eig.time", NC_DOUBLE, 1, &eig_dim, &etime));
  NC_OK(nc_def_var(id, "eig.dCoef", NC_DOUBLE, 1, &eig_dim, &coef));
  NC_OK(nc_def_var(id, "eig.0.Aplus", NC_DOUBLE, 2, tv3, &plus));
  NC_OK(nc_def_var(id, "eig.0.Aminus", NC_DOUBLE, 2, tv3, &minus));
  NC_OK(nc_enddef(id));
  const double zero = 0.0, c = 1e-3;
  const std::size_t first = 0;
  NC_OK(nc_put_var1_double(id, etime, &first, &zero));
  NC_OK(nc_put_var1_double(id, coef, &first, &c));
  NC_OK(nc_put_var1_double(id, time, &first, &zero));
  std::vector<double> triplets, diagonal;  // Aplus: every entry (n^2 = 90000 triplets); Aminus: its diagonal
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const double v = i == j ? 1.0 + c : c / static_cast<double>(1 + i + 2 * j);
      triplets.insert(triplets.end(), {static_cast<double>(i + 1), static_cast<double>(j + 1), v});
      if (i == j) diagonal.insert(diagonal.end(), {static_cast<double>(i + 1), static_cast<double>(j + 1), 1.0 - c});
    }
  const std::size_t start[] = {0, 0}, all[] = {n * n, 3}, diag[] = {n, 3};
  NC_OK(nc_put_vara_double(id, plus, start, all, triplets.data()));
  NC_OK(nc_put_vara_double(id, minus, start, diag, diagonal.data()));
  NC_OK(nc_close(id));
  const auto r = reader::read_mbdyn_netcdf_eigenanalyses(path);
  ASSERT_EQ(r.analyses.size(), 1U);
  const auto& e = r.analyses[0];
  ASSERT_EQ(e.size, n);
  EXPECT_TRUE(e.sparse);
  for (std::size_t k = 0; k < n * n; ++k) ASSERT_EQ(e.aplus[k], triplets[3 * k + 2]) << k;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) ASSERT_EQ(e.aminus[i * n + j], i == j ? 1.0 - c : 0.0) << i << ", " << j;
  std::filesystem::remove(path);
}

class EigenanalysisCli : public mlce::testing::CliFixture {};

TEST_F(EigenanalysisCli, NetcdfFileAndSetRead) {
  write_eig_netcdf((dir / "run.nc").string());
  for (const std::string arg : {"run.nc", "run", "run.mov"}) {  // the file, or the set whose .nc holds eig.*
    std::filesystem::remove(dir / "e.png");
    const auto r = run("eigenanalysis " + (dir / arg).string() + " --json --csv " + (dir / "e.csv").string() + " --plot " +
                       (dir / "e.png").string());
    EXPECT_EQ(mlce::testing::slurp(dir / "e.png").substr(1, 3), "PNG") << arg;
    ASSERT_EQ(r.status, 0) << arg << ": " << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["analyses"].size(), 3U) << arg;
    EXPECT_EQ(j["analyses"][0]["file"], (dir / "run.nc").string() + ":eig.0");
    EXPECT_EQ(j["analyses"][1]["source"], "matrices");
    EXPECT_EQ(j["analyses"][2]["source"], "alpha");
    for (const auto& a : j["analyses"]) {
      EXPECT_NEAR(a["largest_real_part"].get<double>(), -kD1 / (2 * kM1), 1e-6);
      EXPECT_EQ(a["stability"], "stable");
    }
    ASSERT_EQ(j["warnings"].size(), 1U);
    EXPECT_NE(j["warnings"][0].get<std::string>().find("eig.3: planned but not performed"), std::string::npos);
    EXPECT_NE(r.err.find("planned but not performed"), std::string::npos) << r.err;
    std::ifstream csv(dir / "e.csv");
    std::string line;
    int lines = 0;
    while (std::getline(csv, line)) ++lines;
    EXPECT_EQ(lines, 1 + 3 * 4);
  }
  // `mlce channels` counts the analyses performed (eig.3 never was) and names the command.
  const auto listed = run("channels " + (dir / "run.nc").string() + " --json");
  ASSERT_EQ(listed.status, 0) << listed.err;
  EXPECT_EQ(nlohmann::json::parse(listed.out)["eigenanalyses"], 3);
  EXPECT_NE(run("channels " + (dir / "run.nc").string()).out.find("MBDyn eigenanalyses: 3 (mlce eigenanalysis "),
            std::string::npos);
  // Where the .nc holds none: the set's .m files are read; with neither, one error naming both.
  int id = 0, dim = 0, v = 0;
  NC_OK(nc_create((dir / "plain.nc").c_str(), NC_CLOBBER, &id));
  NC_OK(nc_def_dim(id, "time", NC_UNLIMITED, &dim));
  NC_OK(nc_def_var(id, "time", NC_DOUBLE, 1, &dim, &v));
  NC_OK(nc_close(id));
  mlce::testing::expect_one_line_error(run("eigenanalysis " + (dir / "plain.nc").string()), "plain.nc: no eigenanalysis (no 'eig.time')");
  mlce::testing::expect_one_line_error(run("eigenanalysis " + (dir / "plain").string()), "or eig.* in");
  write("plain.m", m_file(two_oscillators(), 0.05, false));
  const auto m = run("eigenanalysis " + (dir / "plain").string() + " --json");
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_EQ(nlohmann::json::parse(m.out)["analyses"][0]["file"], (dir / "plain.m").string());
  // A set with neither .nc nor .m: the tables of its .out; the .out named itself too; a .out without a table: one error.
  write("table.out", step_line(0, 0) + step_line(1, 0.25) + out_table(oscillator_alpha(1e-3), 1e-3, 6) + step_line(2, 0.5) +
                         out_table(oscillator_alpha(1e-3), 1e-3, 6));
  for (const std::string arg : {"table", "table.out", "table.mov"}) {
    const auto t = run("eigenanalysis " + (dir / arg).string() + " --json");
    ASSERT_EQ(t.status, 0) << arg << ": " << t.err;
    const auto j = nlohmann::json::parse(t.out);
    ASSERT_EQ(j["analyses"].size(), 2U) << arg;
    EXPECT_EQ(j["analyses"][0]["file"], (dir / "table.out").string() + ":3");
    EXPECT_EQ(j["analyses"][1]["time"], 0.5);
    for (const auto& a : j["analyses"]) {
      EXPECT_EQ(a["source"], "out");
      EXPECT_TRUE(a["coefficient"].is_null());
      EXPECT_EQ(a["size"], 5);
      EXPECT_EQ(a["at_infinity"], 1);
      EXPECT_NEAR(a["largest_real_part"].get<double>(), -kD1 / (2 * kM1), 1e-5);
      EXPECT_EQ(a["stability"], "stable");
    }
  }
  const auto text_run = run("eigenanalysis " + (dir / "table").string());
  EXPECT_NE(text_run.out.find("t = 0.25, eigenvalues from the .out's table, as printed: 4 finite, 1 at infinity"), std::string::npos)
      << text_run.out;
  write("notable.out", step_line(0, 0));
  mlce::testing::expect_one_line_error(run("eigenanalysis " + (dir / "notable.out").string()), "notable.out: no eigenvalue table");
  mlce::testing::expect_one_line_error(run("eigenanalysis " + (dir / "notable").string()), "no eigenvalue table in");
  // Nothing finite to plot (every eigenvalue at infinity): one error naming the PNG, none written.
  write("infinite.m", "dTime = 0;\ndCoef = 0.5;\nalpha = [-2 0 2;\n1 0 0;\n];\n");
  mlce::testing::expect_one_line_error(run("eigenanalysis " + (dir / "infinite.m").string() + " --plot " + (dir / "i.png").string()),
                                       "i.png: nothing to plot: no analysis has a finite eigenvalue");
  EXPECT_FALSE(std::filesystem::exists(dir / "i.png"));
  // A bad file: one error naming the variable, no CSV left.
  write_eig_netcdf((dir / "bad.nc").string(), {.coefficient = -1.0});
  mlce::testing::expect_one_line_error(run("eigenanalysis " + (dir / "bad.nc").string() + " --csv " + (dir / "bad.csv").string()),
                                       "bad.nc:eig.0: 'eig.dCoef' = -1");
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.csv"));
}

}  // namespace
