// mlce spectrum | floquet | eigen as an analyst runs them: JSON contract, agreement between the
// three commands, sensitivities against central differences of the commands' own exponents at
// p +- dp (a second computation), files written, and errors.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

using mlce::testing::CliFixture;
using mlce::testing::expect_one_line_error;
using nlohmann::json;

namespace {
const std::string kScenes = std::string(MLCE_DATA_DIR) + "/../scenes/";

}  // namespace

class SpectrumCli : public CliFixture {
 protected:
  json json_of(const std::string& args) {
    const auto r = run(args + " --json --quiet");
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return json::parse(r.out);
  }
};

TEST_F(SpectrumCli, EigenFloquetAndQrAgreeOnTheIsotropicScene) {
  const std::string scene = kScenes + "isotropic_200rpm.scene";
  const json e = json_of("eigen " + scene);
  const json f = json_of("floquet " + scene);
  const json q = json_of("spectrum " + scene);
  ASSERT_EQ(e["exponents"].size(), 12u);
  ASSERT_EQ(e["frequencies"].size(), 12u);
  ASSERT_EQ(f["exponents"].size(), 12u);
  ASSERT_EQ(q["exponents"].size(), 12u);
  int pair = 0;
  for (std::size_t i = 0; i < 12; ++i) {
    EXPECT_NEAR(e["exponents"][i].get<double>(), f["exponents"][i].get<double>(), 1e-7) << i;
    EXPECT_NEAR(q["exponents"][i].get<double>(), e["exponents"][i].get<double>(), 2e-3) << i;
    if (i > 0) {
      EXPECT_LE(e["exponents"][i].get<double>(), e["exponents"][i - 1].get<double>());
    }
    pair += std::abs(e["exponents"][i].get<double>() + 1.875) < 1e-3;
  }
  EXPECT_EQ(pair, 4);  // collective and reactionless: -c / (2 I_b), twice each
  // Liouville: each method's exponents sum to its mean divergence of the vector field, and the
  // divergence (tr A, invariant under the multiblade transformation) is the same for all three.
  for (const json* r : {&e, &f, &q}) {
    const double sum = (*r)["exponent_sum"].get<double>(), div = (*r)["mean_divergence"].get<double>();
    EXPECT_NEAR(sum, div, 1e-8 * std::abs(div));
    EXPECT_NEAR(div, e["mean_divergence"].get<double>(), 1e-6 * std::abs(div));
  }
  EXPECT_EQ(e["coordinates"].size(), 12u);
  EXPECT_TRUE(f.contains("period"));
}

TEST_F(SpectrumCli, FloquetSensitivityToRpmMatchesCentralDifferences) {
  const std::string base = "floquet --c 4067.5,4067.5,0,4067.5";
  const json s = json_of(base + " --rpm 242.4 --sensitivity rpm,c3");
  const json p = json_of(base + " --rpm 242.5");
  const json m = json_of(base + " --rpm 242.3");
  ASSERT_TRUE(s["sensitivities"].contains("rpm"));
  ASSERT_EQ(s["sensitivities"]["rpm"].size(), 12u);
  EXPECT_GT(s["exponents"][0].get<double>(), 0.2);  // inside the unstable band
  const double fd = (p["exponents"][0].get<double>() - m["exponents"][0].get<double>()) / 0.2;
  EXPECT_NEAR(s["sensitivities"]["rpm"][0].get<double>(), fd, 0.02 * std::abs(fd));
  const json c3p = json_of(base.substr(0, base.find(" --c")) + " --c 4067.5,4067.5,10,4067.5 --rpm 242.4");
  const double fd_c3 = (c3p["exponents"][0].get<double>() - s["exponents"][0].get<double>()) / 10.0;
  EXPECT_NEAR(s["sensitivities"]["c3"][0].get<double>(), fd_c3, 0.02 * std::abs(fd_c3));
}

TEST_F(SpectrumCli, EigenSensitivityMatchesCentralDifferences) {
  const std::string scene = kScenes + "isotropic_200rpm.scene";
  const json s = json_of("eigen " + scene + " --sensitivity cy");
  const json p = json_of("eigen " + scene + " --cy 51178.7");
  const json m = json_of("eigen " + scene + " --cy 50978.7");
  const double fd = (p["exponents"][0].get<double>() - m["exponents"][0].get<double>()) / 200.0;
  EXPECT_NEAR(s["sensitivities"]["cy"][0].get<double>(), fd, 0.02 * std::abs(fd) + 1e-12);
}

TEST_F(SpectrumCli, FlappingSpectrumWithSensitivityHistoryAndPlot) {
  const std::string scene = kScenes + "flapping_mu015.scene";
  const auto hist = dir / "hist.csv";
  const auto png = dir / "hist.png";
  const json q = json_of("spectrum " + scene + " --mu 1.0 --sensitivity mu --history " + hist.string() + " --plot " + png.string());
  const json f = json_of("floquet " + scene + " --mu 1.0 --sensitivity mu");
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(q["exponents"][i].get<double>(), f["exponents"][i].get<double>(), 2e-3);
    const double fs = f["sensitivities"]["mu"][i].get<double>();
    EXPECT_NEAR(q["sensitivities"]["mu"][i].get<double>(), fs, 0.02 * std::abs(fs) + 1e-3);
  }
  const std::string csv = mlce::testing::slurp(hist);
  EXPECT_EQ(csv.rfind("time,lambda1,lambda2,dlambda1/dmu,dlambda2/dmu\n", 0), 0u) << csv.substr(0, 80);
  EXPECT_TRUE(std::filesystem::exists(png));
}

TEST_F(SpectrumCli, CountReportsTheLargestExponentsOnly) {
  // The exponents reported; raw_exponents holds the one extra tangent vector; no Liouville check.
  const json one = json_of("spectrum --count 1 --t-end 5");
  const json all = json_of("spectrum --t-end 5 --merge off");
  EXPECT_EQ(one["count"], 1);
  EXPECT_EQ(one["exponents"].size(), 1u);
  EXPECT_EQ(one["raw_exponents"].size(), 2u);
  EXPECT_NEAR(one["raw_exponents"][0].get<double>(), all["raw_exponents"][0].get<double>(), 1e-6);
  EXPECT_TRUE(one["mean_divergence"].is_null());
  EXPECT_TRUE(all["mean_divergence"].is_number());
}

namespace {
/// The exponents of a command's text table (rows "i  lambda ..." after the column header).
std::vector<double> table_exponents(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream row(line);
    int i = 0;
    double lambda = 0;
    if (line.empty() || line[0] == '#' || !(row >> i >> lambda)) continue;
    EXPECT_EQ(i, static_cast<int>(out.size()) + 1) << line;
    out.push_back(lambda);
  }
  return out;
}
}  // namespace

TEST_F(SpectrumCli, TextTablesCarryTheExponentsAndLiouvillesCheck) {
  // The human summary an analyst reads: the isotropic rotor's eigenvalues, twice -c / (2 I_b) =
  // -1.875 1/s among them, and each command's sum of exponents against the mean divergence.
  const std::string scene = kScenes + "isotropic_200rpm.scene";
  for (const std::string command : {"eigen ", "floquet ", "spectrum "}) {
    const auto r = run(command + scene + " --quiet");
    ASSERT_EQ(r.status, 0) << command << r.err;
    const auto ex = table_exponents(r.out);
    ASSERT_EQ(ex.size(), 12u) << command << r.out;
    int pair = 0;
    for (double e : ex) pair += std::abs(e + 1.875) < 2e-3;
    EXPECT_EQ(pair, 4) << command << r.out;
    const auto at = r.out.find("# sum of the exponents ");
    ASSERT_NE(at, std::string::npos) << r.out;
    double sum = 0, div = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + at, "# sum of the exponents %lf 1/s; mean divergence of the vector field (tr A) %lf",
                          &sum, &div), 2) << r.out;
    EXPECT_NEAR(sum, div, 1e-8 * std::abs(div)) << command;
    double table_sum = 0;
    for (double e : ex) table_sum += e;
    EXPECT_NEAR(table_sum, sum, 1e-5 * std::abs(sum)) << command;  // the table's 7 digits
  }
  // --merge with a tolerance wider than the whole spectrum averages all twelve into one group:
  // each is then the mean divergence / 12 (Liouville), whatever the run's own exponents.
  const json merged = json_of("spectrum " + scene + " --t-end 20 --merge 100");
  const double mean = merged["mean_divergence"].get<double>() / 12;
  ASSERT_EQ(merged["exponents"].size(), 12u);
  for (const auto& e : merged["exponents"]) EXPECT_NEAR(e.get<double>(), mean, 1e-8 * std::abs(mean));
  expect_one_line_error(run("spectrum --merge -1"), "--merge '-1': expected auto, off or a positive tolerance", 2);
}

TEST_F(SpectrumCli, ExponentsAsCsvForScriptsAndInTheComplexPlaneForPeople) {
  // The 242.4 rpm rotor with blade 3's damper inoperative: one growing pair (+0.2985 1/s,
  // data/mbdyn/README.md). The CSV holds what the JSON holds, to every digit; a Floquet multiplier's
  // modulus is exp(lambda T) (the definition of the exponent, checked on the CSV's own columns), and
  // the eigenvalues of the isotropic rotor sum to tr A (Liouville) in the CSV as in the JSON.
  const std::string c3 = kScenes + "c3zero_242rpm.scene", iso = kScenes + "isotropic_200rpm.scene";
  const auto csv = dir / "f.csv", png = dir / "f.png";
  const auto r = run("floquet " + c3 + " --quiet --csv " + csv.string() + " --plot " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const json f = json_of("floquet " + c3);
  const double period = f["period"].get<double>();
  std::istringstream rows(mlce::testing::slurp(csv));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "i,lambda,frequency,multiplier_abs");
  std::size_t i = 0, growing = 0;
  for (; std::getline(rows, line); ++i) {
    int index = 0;
    double lambda = 0, frequency = 0, modulus = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%lf,%lf,%lf", &index, &lambda, &frequency, &modulus), 4) << line;
    EXPECT_EQ(index, static_cast<int>(i + 1));
    EXPECT_EQ(lambda, f["exponents"][i].get<double>());
    EXPECT_EQ(frequency, f["frequencies"][i].get<double>());
    EXPECT_NEAR(modulus, std::exp(lambda * period), 1e-12 * modulus) << line;
    if (lambda > 0) {
      EXPECT_NEAR(lambda, 0.2985, 1e-3) << line;
      ++growing;
    }
  }
  EXPECT_EQ(i, 12u);
  EXPECT_EQ(growing, 2u);
  EXPECT_EQ(mlce::testing::slurp(png).substr(1, 3), "PNG");
  const auto eigen_csv = dir / "e.csv";
  ASSERT_EQ(run("eigen " + iso + " --sensitivity rpm --csv " + eigen_csv.string() + " --plot " + (dir / "e.png").string()).status, 0);
  const json e = json_of("eigen " + iso);
  std::istringstream eigen_rows(mlce::testing::slurp(eigen_csv));
  std::getline(eigen_rows, line);
  EXPECT_EQ(line, "i,lambda,frequency,dlambda/drpm");
  double sum = 0;
  for (i = 0; std::getline(eigen_rows, line); ++i) sum += std::stod(line.substr(line.find(',') + 1));
  EXPECT_EQ(i, 12u);
  EXPECT_NEAR(sum, e["mean_divergence"].get<double>(), 1e-10 * std::abs(sum));
  EXPECT_EQ(mlce::testing::slurp(dir / "e.png").substr(1, 3), "PNG");
  // The QR spectrum's final exponents with their sensitivities, one row each (flapping: -1/2 twice).
  const auto qr_csv = dir / "q.csv";
  ASSERT_EQ(run("spectrum " + kScenes + "flapping_mu015.scene --quiet --csv " + qr_csv.string()).status, 0);
  std::istringstream qr_rows(mlce::testing::slurp(qr_csv));
  std::getline(qr_rows, line);
  EXPECT_EQ(line, "i,lambda");
  for (i = 0; std::getline(qr_rows, line); ++i) EXPECT_NEAR(std::stod(line.substr(line.find(',') + 1)), -0.5, 1e-6) << line;
  EXPECT_EQ(i, 2u);
}

TEST_F(SpectrumCli, Errors) {
  expect_one_line_error(run("eigen --c 4067.5,4067.5,0,4067.5"), "not isotropic", 1);
  expect_one_line_error(run("floquet --sensitivity stiffness"), "parameter 'stiffness' is not a hammond parameter", 2);
  expect_one_line_error(run("floquet --sensitivity rpm,c3,rpm"), "--sensitivity rpm,c3,rpm: 'rpm' is given twice", 2);
  expect_one_line_error(run("spectrum --qr-step -1"), "--qr-step", 2);
  expect_one_line_error(run("floquet --orbit 1,2"), "orbit state: expected 12 values", 1);
  expect_one_line_error(run("spectrum --jacobian magic"), "expected analytic, complex-step or jacobian-free", 2);
  expect_one_line_error(run("spectrum --count 0"), "--count 0: expected 1..12", 2);
  expect_one_line_error(run("floquet " + (dir / "missing.scene").string()), "cannot open the scene file", 1);
  // Parameters in the wrong units: refused at once (before: spectrum and floquet ran silently for
  // minutes toward the step budget, or for ever).
  expect_one_line_error(run("spectrum --rpm 1e300"), "right-hand side or its Jacobian is not finite", 1);
  expect_one_line_error(run("floquet --rpm 1e300"), "right-hand side or Jacobian at x = 0 is not finite", 1);
  expect_one_line_error(run("floquet --rpm 1e-300"), "Floquet: one period T = 6e+301: the fastest mode", 1);
  expect_one_line_error(run("spectrum --t-end 1e300"), "run length / qr step = 1e+300 / 0.005 = 2e+302 QR intervals: expected at most 1e9", 1);
  expect_one_line_error(run("spectrum --integrator rk4 --h 1e-12"), "the fixed step h = 1e-12 makes 3e+14 steps over a span of 300", 1);
}

TEST_F(SpectrumCli, FloquetNamesTheExponentsBelowItsResolutionAndQrResolvesThem) {
  // Lag dampers of 3e5 N m s/rad: the multiblade lag modes decay at -276 and -285 1/s, so their
  // Floquet multipliers over T = 0.3 s (e^-83) lie far below the monodromy matrix's integration
  // error: Floquet read them as about -130 (with only the Liouville mismatch to tell). Now a
  // warning names exponents 9..12; the first eight still agree with eigen, and the QR method
  // (tangent columns resolved relative to their own size) gives all twelve.
  const std::string scene = kScenes + "isotropic_200rpm.scene --c 3e5";
  const json e = json_of("eigen " + scene);
  const json f = json_of("floquet " + scene);
  const json q = json_of("spectrum " + scene + " --t-end 10");
  const double floor = f["resolution_floor"].get<double>();
  EXPECT_LT(floor, -50.0);
  EXPECT_GT(floor, -100.0);
  bool named = false;
  for (const auto& w : f["warnings"]) named = named || w.get<std::string>().find("exponents 9..12 lie below") != std::string::npos;
  EXPECT_TRUE(named) << f["warnings"].dump();
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_NEAR(f["exponents"][i].get<double>(), e["exponents"][i].get<double>(), 1e-6) << i;
    EXPECT_GT(f["exponents"][i].get<double>(), floor) << i;
  }
  for (std::size_t i = 8; i < 12; ++i) {
    EXPECT_LT(e["exponents"][i].get<double>(), -270.0) << i;
    EXPECT_NEAR(q["exponents"][i].get<double>(), e["exponents"][i].get<double>(), 1e-4 * 280) << i;
  }
  EXPECT_TRUE(q["warnings"].empty()) << q["warnings"].dump();  // e^-1.4 per step of 0.005
  // A QR step of 0.1 contracts the last direction by e^-28.5 relative to the first, beyond
  // 1/rtol = e^18.4: a warning gives the step to check with (18.42 / 285.3 = 0.0646). At 0.2
  // (e^-57) the direction is lost: one error, not a number.
  const json loose = json_of("spectrum " + scene + " --t-end 10 --qr-step 0.1");
  bool warned = false;
  for (const auto& w : loose["warnings"]) warned = warned || w.get<std::string>().find("check them with a QR step below 0.0646") != std::string::npos;
  EXPECT_TRUE(warned) << loose["warnings"].dump();
  expect_one_line_error(run("spectrum " + scene + " --t-end 10 --qr-step 0.2 --quiet"), "the direction was lost", 1);
}

TEST_F(SpectrumCli, FloquetAtAHighRotorSpeedAgreesWithEigen) {
  // At 10^5 rpm, rounding leaves |f(0, t)| ~ 1e-7 (terms of size Omega^2 cancel): x = 0 is still
  // the trivial solution (it was refused with an absolute tolerance of 1e-9).
  const std::string scene = kScenes + "isotropic_200rpm.scene --rpm 1e5";
  const json e = json_of("eigen " + scene);
  const json f = json_of("floquet " + scene);
  ASSERT_EQ(f["exponents"].size(), 12u);
  for (std::size_t i = 0; i < 12; ++i)
    EXPECT_NEAR(f["exponents"][i].get<double>(), e["exponents"][i].get<double>(), 1e-5) << i;
}

// MBDyn's own eigenanalyses: the files of a set in analysis order, one from the matrices (the mboct-mbdyn-pkg
// loader's two oscillators, s = -d / 2m +- i sqrt(s / m - (d / 2m)^2): largest real part -10 / (2 x 2.5) = -2)
// and one from MBDyn's alpha (Lambda = (1 + c s) / (1 - c s) of s = +0.3 +- 2i and a constraint's Lambda = -1).
TEST_F(SpectrumCli, MbdynEigenanalysisFilesReadAsEigenvalues) {
  write("run_0.m",
        "% time: 0\ndTime = 0;\n% coefficient\ndCoef = 0.05;\n"
        "Aplus = [1 0 -0.05 0 ;\n0 1 0 -0.05 ;\n250 0 3 0 ;\n0 50 0 4 ];\n"
        "Aminus = [1 0 0.05 0 ;\n0 1 0 0.05 ;\n-250 0 2 0 ;\n0 -50 0 2 ];\n");
  const double c = 0.05;
  const std::complex<double> grow(0.3, 2.0), lambda = (1.0 + c * grow) / (1.0 - c * grow);
  std::ostringstream alpha;
  alpha.precision(17);
  alpha << "dTime = 2.5;\ndCoef = " << c << ";\nalpha = [" << lambda.real() << " " << lambda.imag() << " 1;\n"
        << lambda.real() << " " << -lambda.imag() << " 1;\n-2 0 2;\n];\n";
  write("run_1.m", alpha.str());
  const json j = json_of("eigenanalysis " + (dir / "run").string() + " --csv " + (dir / "e.csv").string());
  ASSERT_EQ(j["analyses"].size(), 2u);
  const json& m = j["analyses"][0];
  EXPECT_EQ(m["source"], "matrices");
  EXPECT_EQ(m["time"].get<double>(), 0.0);
  ASSERT_EQ(m["eigenvalues"].size(), 4u);
  EXPECT_NEAR(m["largest_real_part"].get<double>(), -2.0, 1e-9);
  EXPECT_NEAR(m["largest_frequency_hz"].get<double>(), std::sqrt(2000.0 - 4.0) / (2 * M_PI), 1e-8);
  EXPECT_EQ(m["stability"], "stable");
  const json& a = j["analyses"][1];
  EXPECT_EQ(a["source"], "alpha");
  EXPECT_EQ(a["time"].get<double>(), 2.5);
  EXPECT_EQ(a["at_infinity"].get<int>(), 1);
  EXPECT_NEAR(a["largest_real_part"].get<double>(), 0.3, 1e-12);
  EXPECT_NEAR(a["eigenvalues"][0]["imag"].get<double>(), 2.0, 1e-12);
  EXPECT_EQ(a["stability"], "unstable");
  std::ifstream csv(dir / "e.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 1 + 4 + 2);
  // One file named directly reads the same.
  const json one = json_of("eigenanalysis " + (dir / "run_1.m").string());
  EXPECT_EQ(one["analyses"].size(), 1u);
  // Errors: a set without eigenanalysis files; a file with a bad value (named with its line); nothing partial.
  expect_one_line_error(run("eigenanalysis " + (dir / "none").string()), "none: no eigenanalysis (no ");
  write("bad_0.m", "dCoef = 0.5;\nalpha = [1 0 1;\n1 0;\n];\n");
  const auto bad = run("eigenanalysis " + (dir / "bad").string() + " --csv " + (dir / "bad.csv").string());
  expect_one_line_error(bad, "bad_0.m:3: alpha: a row of 2 values");
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.csv"));
}
