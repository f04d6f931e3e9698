// The command line as an analyst meets it: bad input gives one clear line and a non-zero exit.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <numeric>
#include <random>
#include <regex>
#include <sstream>
#include <thread>

#include "cli_harness.hpp"
#include "reference_systems.hpp"

namespace {

class Cli : public mlce::testing::CliFixture {
 protected:
  /// A column file `name`: the header line, then time (step dt) and one column per channel, at 17 digits.
  std::string columns_file(const std::string& name, const std::string& header, double dt,
                           const std::vector<std::vector<double>>& channels) {
    std::ostringstream s;
    s.precision(17);
    s << header << "\n";
    for (std::size_t i = 0; i < channels.front().size(); ++i) {
      s << dt * static_cast<double>(i);
      for (const auto& c : channels) s << " " << c[i];
      s << "\n";
    }
    return write(name, s.str()).string();
  }
  std::string series_file(const std::vector<double>& x, double dt) { return columns_file("series.txt", "# time value", dt, {x}); }
};

using mlce::testing::CliRun;
using mlce::testing::expect_one_line_error;
using mlce::testing::slurp;
namespace fs = std::filesystem;

/// The CSV file at `path` (as slurp gives it): its first line is `header` and it has `lines` lines,
/// the header included.
std::string expect_csv(const fs::path& path, const std::string& header, long lines) {
  std::string text = slurp(path);
  EXPECT_EQ(text.substr(0, text.find('\n')), header) << path;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), lines) << path;
  return text;
}

}  // namespace

TEST_F(Cli, NoiseCompensationSwitch) {
  // A slow decay (zeta 0.01, lambda = -0.0628 1/s) under 1 % white noise: automatic compensation
  // reads the rate and reports the plain curve's lambda; off gives that lambda; the curve CSV
  // carries the plain curve next to the compensated one; the human summary says so; a bad value is
  // one error.
  const auto f = series_file(mlce::reference::noisy_decay(8000, 0.01, 0.01, 2 * M_PI, 0.01), 0.01);
  const auto on = nlohmann::json::parse(run("estimate " + f + " --column 2 --time-column 1 --json --quiet").out);
  const auto off = nlohmann::json::parse(
      run("estimate " + f + " --column 2 --time-column 1 --json --quiet --noise-compensation off").out);
  EXPECT_TRUE(on["noise_compensated"].get<bool>());
  EXPECT_FALSE(off["noise_compensated"].get<bool>());
  EXPECT_TRUE(off["uncompensated_lambda"].is_null());
  EXPECT_DOUBLE_EQ(on["uncompensated_lambda"].get<double>(), off["lambda"].get<double>());
  EXPECT_NEAR(on["lambda"].get<double>() / (-0.02 * M_PI), 1.0, 0.1);
  EXPECT_LT(off["lambda"].get<double>() / (-0.02 * M_PI), 0.6);
  // The noise's measured mean square, from 8000 - 4 third differences of the whole record: relative
  // error sqrt(4.62 / k) = 2.4 %; lambda's part from it is within the interval; the noise's share of
  // the pairs' mean square over the fit is a fraction. Not compensated: null, absent.
  const double half = 0.5 * (on["ci95"][1].get<double>() - on["ci95"][0].get<double>());
  EXPECT_NEAR(on["noise_variance_error"].get<double>(), std::sqrt(4.62 / 7996.0), 0.1 * std::sqrt(4.62 / 7996.0));
  EXPECT_GT(on["noise_lambda_stderr"].get<double>(), 0.0);
  EXPECT_LE(1.96 * on["noise_lambda_stderr"].get<double>(), half);
  ASSERT_EQ(on["noise_share"].size(), 2u);
  for (const auto& share : on["noise_share"]) EXPECT_TRUE(share.get<double>() > 0.0 && share.get<double>() < 1.0) << share;
  EXPECT_TRUE(off["noise_variance_error"].is_null());
  EXPECT_TRUE(off["noise_lambda_stderr"].is_null());
  EXPECT_FALSE(off.contains("noise_share"));
  const auto curve = (dir / "compensated.csv").string();
  const auto human = run("estimate " + f + " --column 2 --time-column 1 --quiet --curve " + curve);
  ASSERT_EQ(human.status, 0) << human.err;
  EXPECT_NE(human.out.find("noise           compensated"), std::string::npos) << human.out;
  EXPECT_NE(human.out.find("its share of the pairs' mean square"), std::string::npos) << human.out;
  const std::string c = slurp(curve);
  EXPECT_EQ(c.substr(0, c.find('\n')),
            "step,time,mean_log_distance,terms,in_fit,fit_line,plain_mean_log_distance,local_slope,noise_share");
  const auto bad = run("estimate " + f + " --column 2 --time-column 1 --noise-compensation on");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--noise-compensation 'on': expected auto or off"), std::string::npos) << bad.err;
}

TEST_F(Cli, EstimateJsonHasEveryField) {
  const auto f = series_file(mlce::reference::henon_x(5000), 1.0);
  const CliRun r = run("estimate " + f + " --column 2 --time-column 1 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* k : {"lambda", "lambda_per_sample", "delay", "dim", "theiler", "horizon", "fit", "r2", "ci95",
                        "n_points", "dt", "warnings"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_NEAR(j["lambda"].get<double>(), 0.419, 0.02);
  EXPECT_EQ(j["fit"].size(), 2u);
  EXPECT_EQ(j["n_points"].get<int>(), 5000);
}

// A map's settled cycle in the JSON (map_cycle.hpp): the logistic map at r = 3.83 from x0 = 0.1, its
// approach to the 3-cycle in the record. Hénon's chaotic x has none (null).
TEST_F(Cli, AMapsCycleIsInTheJsonWithItsApproach) {
  std::vector<double> x(2000);
  double v = 0.1;
  for (double& s : x) s = v, v = 3.83 * v * (1.0 - v);
  const auto j = nlohmann::json::parse(run("estimate " + series_file(x, 1.0) + " --column 2 --time-column 1 --json").out);
  ASSERT_TRUE(j["map_cycle"].is_object()) << j.dump();
  EXPECT_EQ(j["map_cycle"]["period"].get<int>(), 3);
  EXPECT_EQ(j["lambda"].get<double>(), j["map_cycle"]["approach_rate"].get<double>());
  EXPECT_NEAR(j["lambda"].get<double>(), -0.3697, 0.001);  // the cycle's exponent (test_map_cycle computes it)
  EXPECT_TRUE(j["map_cycle"]["curve_lambda"].is_number());
  EXPECT_EQ(j["map_cycle"]["approach_samples"].size(), 2u);
  EXPECT_EQ(j["reading"]["stability"], "stable");
  EXPECT_EQ(j["reading"]["motion"], "periodic orbit");
  const auto chaotic =
      nlohmann::json::parse(run("estimate " + series_file(mlce::reference::henon_x(5000), 1.0) + " --column 2 --json").out);
  EXPECT_TRUE(chaotic["map_cycle"].is_null());
}

// The surrogate test in the JSON and the text: by default where the curve reads chaos, on the first
// 4096 samples; --surrogates K on the whole series; 0 never. A bad count is one error line.
TEST_F(Cli, SurrogatesAreInTheJsonAndABadCountIsOneError) {
  const auto f = series_file(mlce::reference::henon_x(3000), 1.0);
  const auto j = nlohmann::json::parse(run("estimate " + f + " --column 2 --json --quiet --surrogates 7").out);
  ASSERT_TRUE(j["surrogates"].is_object()) << j.dump();
  EXPECT_EQ(j["surrogates"]["count"].get<int>(), 7);
  EXPECT_EQ(j["surrogates"]["surrogate_slopes"].size(), 7u);
  EXPECT_EQ(j["surrogates"]["samples"].get<int>(), 3000);  // the whole series
  EXPECT_DOUBLE_EQ(j["surrogates"]["p_value"].get<double>(), 0.125);
  EXPECT_TRUE(nlohmann::json::parse(run("estimate " + f + " --column 2 --json --quiet --surrogates 0").out)["surrogates"].is_null());
  // By default: Henon x reads chaos, so its divergence is tested, and told from linear noise.
  const auto by_default = nlohmann::json::parse(run("estimate " + f + " --column 2 --json --quiet").out);
  ASSERT_TRUE(by_default["surrogates"].is_object()) << by_default.dump();
  EXPECT_EQ(by_default["surrogates"]["count"].get<int>(), 19);
  EXPECT_TRUE(by_default["surrogates"]["distinguished"].get<bool>());
  EXPECT_DOUBLE_EQ(by_default["surrogates"]["p_value"].get<double>(), 0.05);
  EXPECT_EQ(by_default["reading"]["motion"], "chaotic");
  EXPECT_EQ(nlohmann::json::parse(run("estimate " + f + " --column 2 --json --quiet --surrogates auto").out)["surrogates"],
            by_default["surrogates"]);
  const CliRun text = run("estimate " + f + " --column 2 --quiet --surrogates 19");
  EXPECT_NE(text.out.find("surrogates      slope"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("told from linear noise"), std::string::npos) << text.out;
  expect_one_line_error(run("estimate " + f + " --column 2 --surrogates many"),
                        "--surrogates 'many': expected auto or a count", 2);
}

// A level that creeps beneath the neighbour pairs, in the JSON and in the summary: Roessler x plus
// 0.0005 t (time column in s, dt = 0.1). The rate is per time unit, seen with its sign and at most
// at the true creep (the search prefers pairs whose own separation offsets it).
TEST_F(Cli, ALevelCreepingBeneathTheNeighboursIsInTheJsonAndTheSummary) {
  std::vector<double> x = mlce::reference::roessler_x(10000, 0.1, {1.3, -2.1, 0.0});
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += 5e-4 * 0.1 * static_cast<double>(i);
  const auto f = series_file(x, 0.1);
  const CliRun r = run("estimate " + f + " --column 2 --time-column 1 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("neighbour_drift")) << r.out;
  EXPECT_GT(j["neighbour_drift"]["share"].get<double>(), 0.02);
  EXPECT_EQ(j["neighbour_drift"]["channel"].get<int>(), 1);
  EXPECT_GT(j["neighbour_drift"]["rate"].get<double>(), 0.0);
  EXPECT_LE(j["neighbour_drift"]["rate"].get<double>(), 5e-4);
  EXPECT_NE(j["warnings"].dump().find("creeps beneath the neighbour pairs"), std::string::npos) << j["warnings"].dump();
  const CliRun human = run("estimate " + f + " --column 2 --time-column 1");
  ASSERT_EQ(human.status, 0) << human.err;
  EXPECT_NE(human.out.find("creeps beneath the neighbour pairs"), std::string::npos) << human.out;
  EXPECT_NE(human.out.find("per s"), std::string::npos) << human.out;
}

TEST_F(Cli, AWidenedDimensionSaysWhyInTheJsonAndTheSummary) {
  // Roessler (x, y) jointly (the start of EstimateSystems.AFlowThatDivergesIsNeverReconstructedIn
  // FewerThanThreeCoordinates): FNN's m = 1 leaves a plane, widened to m = 2.
  const std::array<double, 3> x0{1.8165450207445701, -2.4431951381544246, 0.03630509678848215};
  auto flow = [](const std::array<double, 3>& s) { return mlce::reference::roessler_rhs(s); };
  const auto f = columns_file("xy.txt", "# t x y", 0.1,
                              {mlce::reference::sample_flow<3>(flow, x0, 0.1, 10000, 500.0, 10, 0),
                               mlce::reference::sample_flow<3>(flow, x0, 0.1, 10000, 500.0, 10, 1)});
  const CliRun r = run("estimate " + f + " --time-column 1 --column 2 --column 3 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["dim"].get<int>(), 2) << r.out;
  EXPECT_EQ(j["dim_widened_from"].get<int>(), 1) << r.out;
  EXPECT_EQ(j["dim_widened_because"].get<std::string>(), "flow_in_a_plane");
  const CliRun human = run("estimate " + f + " --time-column 1 --column 2 --column 3");
  ASSERT_EQ(human.status, 0) << human.err;
  EXPECT_NE(human.out.find("false nearest neighbours chose 1, too few coordinates for a flow that diverges"),
            std::string::npos)
      << human.out;
}

TEST_F(Cli, ReferenceCountIsAtLeastOneOrAll) {
  // --refs 0 once meant "all" silently; a count must be >= 1, and 'all' is said in words.
  const auto f = series_file(mlce::reference::henon_x(3000), 1.0);
  expect_one_line_error(run("estimate " + f + " --time-column 1 --column 2 --refs 0"), "--refs '0'", 2);
  CliRun r = run("estimate " + f + " --time-column 1 --column 2 --refs all --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto all = nlohmann::json::parse(r.out);
  r = run("estimate " + f + " --time-column 1 --column 2 --refs 100 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto few = nlohmann::json::parse(r.out);
  EXPECT_GT(all["pairs"].get<int>(), 2900);  // every admissible point: 3000 - (m-1) delay - horizon
  EXPECT_EQ(few["pairs"].get<int>(), 100);
  EXPECT_NE(few["warnings"].dump().find("only 100 neighbour pair(s)"), std::string::npos) << few["warnings"];
  EXPECT_NE(few["warnings"].dump().find("--refs"), std::string::npos) << few["warnings"];
}

TEST_F(Cli, MissingGnuplotIsOneErrorAndLeavesNothing) {
  const auto f = series_file(mlce::reference::henon_x(3000), 1.0);
  const auto png = dir / "curve.png";
  // --quiet: on a slow build (sanitizers, a loaded machine) the estimate passes 1 s and its progress
  // lines would join the error on stderr.
  const CliRun r = run("estimate " + f + " --time-column 1 --column 2 --json --quiet --plot " + png.string(), "PATH=/nonexistent");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;  // the shell's "gnuplot: not found" went to stdout once
  EXPECT_NE(r.err.find("curve.png: gnuplot failed to draw the plot (is gnuplot installed?)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not found"), std::string::npos) << r.err;  // the shell's word, in the one line
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  for (const auto& e : fs::directory_iterator(dir))  // no plot, no temporary file (nor gnuplot's log)
    EXPECT_EQ(e.path().filename().string().find("curve.png"), std::string::npos) << e.path();
  // A plot that is drawn brings no word from gnuplot (a one-row record: "empty x range" warnings).
  const CliRun one = run("extract " + write("one.txt", "1 2\n").string() + " --channel col:2 --plot " +
                         (dir / "one.png").string());
  EXPECT_EQ(one.status, 0) << one.err;
  EXPECT_TRUE(one.err.empty()) << one.err;
  EXPECT_EQ(slurp(dir / "one.png").substr(1, 3), "PNG");
}

TEST_F(Cli, PlotPathsWithAQuoteOrAMissingFolder) {
  const auto f = series_file(mlce::reference::henon_x(3000), 1.0);
  // A quote ends a gnuplot string unless written twice: the plot is drawn where it was asked.
  const auto png = dir / "blade's lag.png";
  const CliRun r = run("estimate " + f + " --time-column 1 --column 2 --quiet --time-unit \"o'clock\" --plot \"" +
                       png.string() + "\"");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(png).substr(1, 3), "PNG");
  // A folder that does not exist: the error names the plot, not the scratch file beside it.
  const auto lost = dir / "no-such-folder" / "curve.png";
  expect_one_line_error(run("estimate " + f + " --time-column 1 --column 2 --quiet --plot " + lost.string()),
                        lost.string() + ": cannot write the file");
}

TEST_F(Cli, VersionIsPrinted) {
  const CliRun r = run("--version");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::regex_match(r.out, std::regex("mlce [0-9]+\\.[0-9]+\\.[0-9]+\n"))) << r.out;
}

TEST_F(Cli, OneColumnFileIsTheSeriesPerSample) {
  std::ostringstream s;
  s.precision(17);
  for (double v : mlce::reference::logistic(4000)) s << v << "\n";
  const CliRun r = run("estimate " + write("one.txt", s.str()).string() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["lambda_unit"], "1/sample");
  EXPECT_NEAR(j["lambda"].get<double>(), std::log(2.0), 0.03);
}

TEST_F(Cli, TextColumnsBesideTheSeriesAreNoError) {
  // A spreadsheet / pandas export with a datetime and a label column beside the numbers: the
  // numbers are analysed, text is refused only in a column asked for, and a run that overflowed
  // into Fortran's "*****" after --to reads up to it.
  const auto henon = mlce::reference::henon_x(4000);
  std::ostringstream s;
  s.precision(17);
  s << "when,t,henon,note\n";
  for (std::size_t i = 0; i < henon.size(); ++i)
    s << "2026-11-27 01:00:" << i % 60 << "," << i << "," << henon[i] << "," << (i % 7 ? "ok" : "") << "\n";
  s << "2026-11-27 02:07:00,4000,*****,overflow\n";
  const auto f = write("labelled.csv", s.str()).string();
  CliRun r = run("estimate " + f + " --time-column t --column henon --to 3999 --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["lambda"].get<double>(), 0.419, 0.02);
  expect_one_line_error(run("estimate " + f + " --time-column t --column henon"),
                        "labelled.csv:4002: column 3: '*****' is not a number");
  expect_one_line_error(run("estimate " + f + " --time-column t --column note"),
                        "labelled.csv:2: column 4: empty field: expected a number");
  expect_one_line_error(run("estimate " + f + " --time-column when --column henon"),
                        "labelled.csv:2: column 1: '2026-11-27 01:00:0' is not a number");
  r = run("channels " + f);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* said : {"col:1 (when) can be analysed only before its first field that is no number: ",
                           "labelled.csv:2: column 1: '2026-11-27 01:00:0' is not a number",
                           "col:3 (henon) can be analysed only before", "labelled.csv:4002: column 3: '*****'",
                           "col:4 (note) can be analysed only before"})
    EXPECT_NE(r.err.find(said), std::string::npos) << said << "\n" << r.err;
  EXPECT_EQ(r.err.find("col:2"), std::string::npos) << r.err;
}

TEST_F(Cli, ColumnsAreNamedByTheHeaderLine) {
  // A spreadsheet / pandas export: comma-separated, a header naming the columns.
  const auto henon = mlce::reference::henon_x(4000);
  const auto logistic = mlce::reference::logistic(4000);
  std::ostringstream s;
  s.precision(17);
  s << "t,henon,logistic\n";
  for (std::size_t i = 0; i < henon.size(); ++i) s << i << "," << henon[i] << "," << logistic[i] << "\n";
  const auto f = write("named.csv", s.str()).string();
  CliRun r = run("estimate " + f + " --time-column t --column logistic --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["lambda"].get<double>(), std::log(2.0), 0.03);
  r = run("estimate " + f + " --time-column t --column henon --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["lambda"].get<double>(), 0.419, 0.02);
  // Names and numbers mix; a number is always the 1-based position.
  r = run("estimate " + f + " --time-column 1 --column logistic --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["lambda"].get<double>(), std::log(2.0), 0.03);
  expect_one_line_error(run("estimate " + f + " --time-column t --column x"),
                        "named.csv: --column 'x': no such column; the header names t, henon, logistic");
  expect_one_line_error(run("estimate " + f + " --time-column time --column 2"),
                        "named.csv: --time-column 'time': no such column");
  // `mlce channels` lists the names beside the col:K they stand for.
  r = run("channels " + f);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("col:1    t\n  col:2    henon\n  col:3    logistic\n"), std::string::npos) << r.out;
  // R's write.csv quotes the header and the row names: the names read without their quotes.
  std::ostringstream q;
  q.precision(17);
  q << "\"\",\"t\",\"henon\"\n";
  for (std::size_t i = 0; i < henon.size(); ++i) q << '"' << i + 1 << "\"," << i << "," << henon[i] << "\n";
  r = run("estimate " + write("r.csv", q.str()).string() + " --time-column t --column henon --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["lambda"].get<double>(), 0.419, 0.02);
  // Names in the last comment before the data, one per column (`# time value`, as make_series,
  // `mlce simulate --format columns` and numpy.savetxt write them), name the columns too.
  const auto g = series_file(henon, 1.0);
  r = run("estimate " + g + " --time-column time --column value --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["lambda"].get<double>(), 0.419, 0.02);
  expect_one_line_error(run("estimate " + g + " --time-column 1 --column x"),
                        "series.txt: --column 'x': no such column; the header names time, value");
  // A comment of other words, or of another count, stays a comment: without a header a name
  // cannot be resolved.
  for (const char* comment : {"# henon x, 4000 iterations", "# t x y", "# time\n# 1 2"}) {
    std::string text = std::string(comment) + "\n";
    for (std::size_t i = 0; i < henon.size(); ++i) text += std::to_string(i) + " " + std::to_string(henon[i]) + "\n";
    const auto plain = write("plain.txt", text).string();
    expect_one_line_error(run("estimate " + plain + " --time-column 1 --column x"),
                          "plain.txt: --column 'x': expected a 1-based column number (the file has no header line");
  }
  // A name the header gives twice is not silently the first of them.
  const auto twice = write("twice.csv", "t,x,x\n" + s.str().substr(s.str().find('\n') + 1)).string();
  expect_one_line_error(run("estimate " + twice + " --time-column t --column x"),
                        "twice.csv: --column 'x': 2 columns are named so (2, 3): give the column's number");
  r = run("estimate " + twice + " --time-column t --column 3 --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["lambda"].get<double>(), std::log(2.0), 0.03);
}

TEST_F(Cli, CurveCsvAndGivenParameters) {
  const auto f = series_file(mlce::reference::henon_x(3000), 1.0);
  const auto csv = dir / "curve.csv";
  const CliRun r = run("estimate " + f + " --column 2 --dt 1 --delay 1 --dim 2 --theiler 5 --horizon 30 --fit 1:9 --curve " +
                    csv.string() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["horizon"], 30);
  EXPECT_EQ(j["fit"][0], 1);
  EXPECT_EQ(j["fit"][1], 9);
  expect_csv(csv, "step,time,mean_log_distance,terms,in_fit,fit_line,local_slope", 32);
}

// The curve CSV's local slope (per time unit, over one mean period) of a damped oscillator's curve
// is its exponent -zeta omega wherever the window fits, and empty within half a period of the ends.
TEST_F(Cli, CurveCsvLocalSlopeIsTheDecayRate) {
  const double dt = 0.01, zeta = 0.05, omega = 2 * M_PI;
  const auto f = series_file(mlce::reference::damped_oscillator(2000, dt, zeta, omega), dt);
  const auto csv = dir / "decay.csv";
  ASSERT_EQ(run("estimate " + f + " --column 2 --time-column 1 --quiet --curve " + csv.string()).status, 0);
  std::istringstream lines(slurp(csv));
  std::string line;
  std::getline(lines, line);
  ASSERT_EQ(line, "step,time,mean_log_distance,terms,in_fit,fit_line,local_slope");
  std::size_t with_slope = 0, empty = 0;
  while (std::getline(lines, line)) {
    const std::string last = line.substr(line.rfind(',') + 1);
    if (last.empty()) {
      ++empty;
      continue;
    }
    ++with_slope;
    EXPECT_NEAR(std::stod(last), -zeta * omega, 0.005 * zeta * omega) << line;
  }
  EXPECT_GT(with_slope, 100u);
  EXPECT_GT(empty, 0u);
}

TEST_F(Cli, AmiSaysTheCurvesScatterWhereItsMinimumWasAccepted) {
  // A sine of 200 samples per period: its histogram AMI zigzags from lag to lag, and the minimum
  // taken (near the quarter period, 50) had to rise above that scatter (AmiOptions::noise_rise).
  std::vector<double> x(10000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * std::numbers::pi * static_cast<double>(i) / 200.0 + 0.3);
  const auto f = series_file(x, 1.0);
  CliRun r = run("ami " + f + " --column 2 --time-column 1 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["scatter"].get<double>(), 0.0);
  EXPECT_GE(j["delay"].get<int>(), 38);
  EXPECT_LE(j["delay"].get<int>(), 62);
  r = run("ami " + f + " --column 2 --time-column 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("# the raw curve scatters by "), std::string::npos) << r.out.substr(r.out.size() - 300);
}

TEST_F(Cli, AmiAndFnnPrintTheirCurves) {
  const auto f = series_file(mlce::reference::henon_x(3000), 1.0);
  CliRun r = run("ami " + f + " --column 2 --time-column 1 --json --max-delay 20");
  ASSERT_EQ(r.status, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["ami"].size(), 21u);
  EXPECT_EQ(j["delay"], 1);
  r = run("fnn " + f + " --column 2 --time-column 1 --json --max-dim 4");
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["dim"], 2);
  EXPECT_EQ(j["fraction"].size(), 4u);
  // The same curves as CSV (equal to the JSON's values) and as PNG.
  const auto ami_csv = dir / "ami.csv", ami_png = dir / "ami.png", fnn_csv = dir / "fnn.csv", fnn_png = dir / "fnn.png";
  r = run("ami " + f + " --column 2 --time-column 1 --max-delay 20 --json --csv " + ami_csv.string() + " --plot " +
          ami_png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto ami = nlohmann::json::parse(r.out)["ami"];
  std::istringstream rows(slurp(ami_csv));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "tau,ami,smoothed");
  for (std::size_t tau = 0; tau < ami.size(); ++tau) {
    ASSERT_TRUE(std::getline(rows, line)) << tau;
    EXPECT_EQ(std::stoul(line), tau);
    EXPECT_NEAR(std::stod(line.substr(line.find(',') + 1)), ami[tau].get<double>(), 1e-9 * ami[0].get<double>());
  }
  EXPECT_EQ(slurp(ami_png).substr(1, 3), "PNG");
  r = run("fnn " + f + " --column 2 --time-column 1 --max-dim 4 --json --csv " + fnn_csv.string() + " --plot " +
          fnn_png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto fraction = nlohmann::json::parse(r.out)["fraction"];
  std::istringstream fnn_rows(slurp(fnn_csv));
  std::getline(fnn_rows, line);
  EXPECT_EQ(line, "m,false_fraction,tested,tree_points");
  for (std::size_t m = 1; m <= fraction.size(); ++m) {
    ASSERT_TRUE(std::getline(fnn_rows, line)) << m;
    EXPECT_EQ(std::stoul(line), m);
    EXPECT_NEAR(std::stod(line.substr(line.find(',') + 1)), fraction[m - 1].get<double>(), 1e-9);
  }
  EXPECT_EQ(slurp(fnn_png).substr(1, 3), "PNG");
  // Without --json: the curve as commented columns a plotting tool reads, then the choice (Henon is
  // a map: delay 1, whatever the AMI's noise floor does; its attractor unfolds in m = 2).
  r = run("ami " + f + " --column 2 --time-column 1 --max-delay 20");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream ami_text(r.out);
  std::size_t ami_rows = 0;
  while (std::getline(ami_text, line)) {
    if (!line.empty() && line[0] != '#') {
      EXPECT_EQ(std::stoul(line), ami_rows) << line;
      ++ami_rows;
    }
  }
  EXPECT_EQ(ami_rows, 21u);
  EXPECT_NE(r.out.find("\n# delay = 1 ("), std::string::npos) << r.out;
  r = run("fnn " + f + " --column 2 --time-column 1 --max-dim 4");
  ASSERT_EQ(r.status, 0) << r.err;
  char first[64];
  std::snprintf(first, sizeof first, "\n1 %.6f ", fraction[0].get<double>());
  EXPECT_NE(r.out.find(first), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n# dim = 2\n"), std::string::npos) << r.out;
}

TEST_F(Cli, FnnByCaosMethodPrintsE1AndE2AsJsonCsvAndPlot) {
  const auto f = series_file(mlce::reference::henon_x(3000), 1.0);
  const auto csv = dir / "cao.csv", png = dir / "cao.png";
  CliRun r = run("fnn " + f + " --column 2 --time-column 1 --method cao --max-dim 5 --json --csv " + csv.string() +
                 " --plot " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["e"].size(), 5u);
  ASSERT_EQ(j["e1"].size(), 4u);
  EXPECT_EQ(j["delay"], 1);
  EXPECT_FALSE(j["looks_stochastic"].get<bool>());  // Henon is deterministic
  EXPECT_GE(j["dim"].get<int>(), 2);                // its attractor needs two dimensions
  std::istringstream rows(slurp(csv));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "d,E,E1,E2,pairs");
  for (std::size_t d = 1; d <= 4; ++d) {
    ASSERT_TRUE(std::getline(rows, line)) << d;
    EXPECT_EQ(std::stoul(line), d);
    const auto e1_field = line.substr(line.find(',', line.find(',') + 1) + 1);
    EXPECT_NEAR(std::stod(e1_field), j["e1"][d - 1].get<double>(), 1e-9);
  }
  EXPECT_EQ(slurp(png).substr(1, 3), "PNG");
  r = run("fnn " + f + " --column 2 --time-column 1 --method cao --max-dim 5");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("# d E E1 E2 pairs\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("deterministic"), std::string::npos) << r.out;
  r = run("fnn " + f + " --column 2 --time-column 1 --method cau");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--method 'cau': expected kennel or cao"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST_F(Cli, KantzPrintsEachRadiusBesideRosensteinAsJsonCsvAndPlot) {
  // Henon x: every radius' curve grows at 0.4189 per iteration (within 4 %), as Rosenstein's does.
  const auto f = series_file(mlce::reference::henon_x(5000), 1.0);
  const auto csv = dir / "kantz.csv", png = dir / "kantz.png";
  CliRun r = run("kantz " + f + " --column 2 --json --radii 0.005,0.01,0.02 --csv " + csv.string() + " --plot " +
                 png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "kantz");
  EXPECT_EQ(j["lambda_unit"], "1/sample");
  ASSERT_EQ(j["radii"].size(), 3u);
  for (const auto& k : j["radii"]) EXPECT_NEAR(k["lambda"].get<double>() / 0.4189, 1.0, 0.04) << k.dump();
  EXPECT_EQ(j["radii"][1]["radius"].get<double>(), 0.01);
  EXPECT_TRUE(j["agrees"].get<bool>());
  EXPECT_EQ(j["reported_curve"], "plain");  // a map: no phase alignment, for the estimate
  EXPECT_EQ(j["rosenstein_curve"], "plain");
  EXPECT_FALSE(j["phase_aligned"].get<bool>());  // nor for the neighbourhoods
  EXPECT_NEAR(j["rosenstein_lambda"].get<double>() / 0.4189, 1.0, 0.03);
  std::istringstream rows(slurp(csv));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "step,time,S_radius_0.005,S_radius_0.01,S_radius_0.02");
  std::size_t steps = 0;
  while (std::getline(rows, line)) ++steps;
  EXPECT_EQ(steps, j["horizon"].get<std::size_t>() + 1);
  EXPECT_EQ(slurp(png).substr(1, 3), "PNG");
  r = run("kantz " + f + " --column 2");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("lambda (Kantz)  "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("agree           yes"), std::string::npos) << r.out;
  for (const std::string bad : {"0.02,0.01", "0.01,-1", "0.01,x"}) {
    r = run("kantz " + f + " --column 2 --radii " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("--radii '" + bad + "': expected 'auto' or increasing comma-separated radii > 0"),
              std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  r = run("kantz " + f + " --column 2 --align-phase maybe");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--align-phase 'maybe': expected auto, on or off"), std::string::npos) << r.err;
  r = run("kantz " + f + " --column 2 --radii 1e-9 --csv " + csv.string() + ".new");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("no radius up to 1e-09 gives any reference point a neighbourhood"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(csv.string() + ".new"));  // no partial output
}

TEST_F(Cli, SpaceTimeSeparationPlotInEveryForm) {
  // A sine of period 100 samples: every pair one period apart coincides (the contours fall to 0
  // there); the embedding is the estimator's (AMI delay, FNN dimension) unless given.
  std::vector<double> x(5000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * M_PI * static_cast<double>(i) / 100.0);
  const auto f = series_file(x, 0.01);
  const auto csv = dir / "stp.csv", png = dir / "stp.png";
  CliRun r = run("stsp " + f + " --time-column 1 --column 2 --step 1 --fractions 0.5,0.05 --json --csv " +
                 csv.string() + " --plot " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["mean_period"], 100);
  EXPECT_EQ(j["separation"].size(), 400u);  // 4 mean periods, step 1
  EXPECT_EQ(j["fractions"], nlohmann::json::parse("[0.05, 0.5]"));
  EXPECT_LT(j["contours"]["0.5"][99].get<double>(), 1e-9);
  EXPECT_NEAR(j["decorrelation_time"].get<double>(), 0.01 * j["decorrelation"].get<double>(), 1e-12);
  for (const char* k : {"dim", "delay", "plateau", "pairs", "stationary", "warnings"}) EXPECT_TRUE(j.contains(k)) << k;
  expect_csv(csv, "separation,time,contour_0.05,contour_0.5,pairs", 401);
  EXPECT_TRUE(fs::exists(png));
  r = run("stsp " + f + " --time-column 1 --column 2 --dim 2 --delay 25 --max-separation 150");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("m = 2, delay = 25"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("# decorrelation = "), std::string::npos) << r.out;
  expect_one_line_error(run("stsp " + f + " --time-column 1 --column 2 --fractions 0.5,2"), "--fractions '0.5,2'", 2);
  expect_one_line_error(run("stsp " + f + " --time-column 1 --column 2 --max-separation 4950 --dim 1"),
                        "series.txt: series too short: 5000 samples");
}

TEST_F(Cli, ConvergenceTableInEveryForm) {
  // A damped oscillator (lambda = -zeta w = -0.314159 1/s exactly): settled from the first quarter.
  const auto f = series_file(mlce::reference::damped_oscillator(4000, 0.01, 0.05, 2 * M_PI), 0.01);
  const auto csv = dir / "conv.csv", png = dir / "conv.png";
  CliRun r = run("convergence " + f + " --time-column 1 --column 2 --parts 4 --json --quiet --csv " + csv.string() +
                 " --plot " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["points"].size(), 4u);
  EXPECT_EQ(j["points"][0]["samples"], 1000);
  for (const auto& p : j["points"]) EXPECT_NEAR(p["lambda"].get<double>(), -0.1 * M_PI, 0.003) << p;
  EXPECT_TRUE(j["converged"].get<bool>());
  for (const auto& p : j["points"]) EXPECT_EQ(p["stability"], "stable") << p;  // lambda T = -0.314
  EXPECT_TRUE(j["reading_settled"].get<bool>());
  EXPECT_EQ(j["lambda_unit"], "1/s");
  expect_csv(csv, "samples,t_end,lambda,ci95_low,ci95_high,delay,dim,theiler,warnings,stability,motion,in_decay_floor", 5);
  EXPECT_TRUE(fs::exists(png));
  r = run("convergence " + f + " --time-column 1 --column 2 --parts 2 --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("settled: every part"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reading settled: stable (decays to rest) on every part of at least half the run"), std::string::npos)
      << r.out;
  expect_one_line_error(run("convergence " + f + " --time-column 1 --column 2 --parts 1"), "convergence.parts = 1", 2);
  const auto tiny = series_file(mlce::reference::henon_x(12), 1.0);
  expect_one_line_error(run("convergence " + tiny + " --time-column 1 --column 2"), "series.txt: AMI needs at least 16 samples");
  // Fewer samples than the default 8 parts: the data's error, as for every command (it was a usage
  // error, "convergence.parts = 8: more parts than the series has samples (3)", naming no file).
  expect_one_line_error(run("convergence " + write("three.txt", "1\n2\n3\n").string()),
                        "three.txt: mean frequency needs at least 4 samples, the series has 3");
}

TEST_F(Cli, EachChannelInEveryForm) {
  // Two decays in one file, lambda = -zeta w exactly: 0.05 and 0.15 x 2 pi (a channel that does not
  // see the least damped mode reads another rate): each channel right, and they disagree.
  const double dt = 0.01;
  const auto a = mlce::reference::damped_oscillator(2000, dt, 0.05, 2 * M_PI);
  const auto b = mlce::reference::damped_oscillator(2000, dt, 0.15, 2 * M_PI);
  const auto f = columns_file("two.txt", "t slow fast", dt, {a, b});
  const auto csv = dir / "each.csv", png = dir / "each.png";
  CliRun r = run("estimate " + f + " --time-column t --column slow --column fast --each --json --quiet --curve " +
                 csv.string() + " --plot " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["channels"].size(), 2u);
  EXPECT_EQ(j["channels"][0]["channel"], "slow");
  EXPECT_EQ(j["channels"][1]["channel"], "fast");
  EXPECT_NEAR(j["channels"][0]["lambda"].get<double>(), -0.05 * 2 * M_PI, 0.03 * 0.05 * 2 * M_PI);
  EXPECT_NEAR(j["channels"][1]["lambda"].get<double>(), -0.15 * 2 * M_PI, 0.03 * 0.15 * 2 * M_PI);
  EXPECT_FALSE(j["agree"].get<bool>());
  EXPECT_TRUE(j["common_interval"].is_null());
  EXPECT_NE(j["warnings"].dump().find("disagree"), std::string::npos) << j["warnings"];
  EXPECT_EQ(j["file"], f);
  // The curves, one channel after the other, as many rows as the two horizons hold.
  const auto rows = j["channels"][0]["horizon"].get<long>() + j["channels"][1]["horizon"].get<long>() + 2;
  const std::string curves =
      expect_csv(csv, "channel,index,step,time,mean_log_distance,terms,in_fit,fit_line,local_slope", rows + 1);
  EXPECT_NE(curves.find("\nfast,1,0,0,"), std::string::npos);
  EXPECT_TRUE(fs::exists(png));
  // The table for people says it too.
  r = run("estimate " + f + " --time-column t --column slow --column fast --each --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("agreement       NO"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nslow "), std::string::npos) << r.out;
  // Nothing to compare: one channel is a usage error.
  expect_one_line_error(run("estimate " + f + " --time-column t --column slow --each"), "--each: give two or more", 2);
}

TEST_F(Cli, EachChannelTableSaysWhereEveryChannelStarts) {
  // Two Lorenz x runs side by side, from (1, 1, 1): "raw" keeps its spiral out of the fixed point C-,
  // which lasts its first ~12-15 time units and does not recur (the estimator leaves such a start
  // out), "settled" starts after 50 time units, on the attractor. The table's "from" column is
  // each channel's first analysed time, t0 + skipped samples x dt: inside the spiral for "raw", 0
  // for "settled", and what the JSON's skipped_start says.
  const double dt = 0.01;
  const auto raw = mlce::reference::lorenz_x(10000, dt, {1, 1, 1}, 0.0);
  const auto settled = mlce::reference::lorenz_x(10000, dt);
  const auto f = columns_file("runs.txt", "t raw settled", dt, {raw, settled});
  const std::string base = "estimate " + f + " --time-column t --column raw --column settled --each --quiet";
  const CliRun r = run(base);
  ASSERT_EQ(r.status, 0) << r.err;
  // Columns: channel, lambda, low, "..", high, from, delay, dim, theiler, fit, R^2.
  auto column = [&](const std::string& name, std::size_t k) {
    const auto at = r.out.find("\n" + name + " ");
    if (at == std::string::npos) return std::string();
    std::istringstream row(r.out.substr(at + 1, r.out.find('\n', at + 1) - at - 1));
    std::string field;
    for (std::size_t i = 0; i <= k && row >> field;) ++i;
    return field;
  };
  ASSERT_EQ(column("channel", 6), "from") << r.out;  // the header: "lambda 1/s" and "95 % interval" are 5 words
  // The last column reads each estimate (reading.hpp): Lorenz x on its attractor is chaotic.
  EXPECT_EQ(column("settled", 11), "unstable") << r.out;
  EXPECT_EQ(column("settled", 12), "(chaotic)") << r.out;
  const auto j = nlohmann::json::parse(run(base + " --json").out);
  const double raw_from = std::stod(column("raw", 5)), settled_from = std::stod(column("settled", 5));
  EXPECT_GT(raw_from, 0.0) << r.out;
  EXPECT_LE(raw_from, 15.0) << r.out;
  EXPECT_NEAR(raw_from, j["channels"][0]["skipped_start"].get<double>() * dt, 1e-5 * raw_from) << r.out;
  EXPECT_EQ(settled_from, 0.0) << r.out;
  EXPECT_EQ(j["channels"][1]["skipped_start"], 0);
}

TEST_F(Cli, EachChannelWithOneThatCannotBeEstimatedIsADataError) {
  // The second channel holds one period of a slow sine: too few mean periods to estimate. The
  // table and the JSON still carry the first, and the exit status says the answer is incomplete.
  const double dt = 0.01;
  const auto a = mlce::reference::damped_oscillator(2000, dt, 0.05, 2 * M_PI);
  std::vector<double> slow(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) slow[i] = std::sin(2 * M_PI * 0.05 * dt * static_cast<double>(i));
  const auto f = columns_file("slow.txt", "# time fast slow", dt, {a, slow});
  CliRun r = run("estimate " + f + " --time-column 1 --column 2 --column 3 --each --json --quiet");
  EXPECT_EQ(r.status, 1) << r.err;
  // One line on stderr naming the file and the channel, as for any data error.
  EXPECT_NE(r.err.find("slow.txt: 1 of 2 channels could not be estimated (slow)"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["estimated"], 1);
  EXPECT_EQ(j["compared"], 1);  // the decay measures a divergence; alone, it is compared with nothing
  EXPECT_FALSE(j["agree"].get<bool>());
  EXPECT_TRUE(j["channels"][0].contains("lambda"));
  EXPECT_TRUE(j["channels"][1].contains("error"));
  EXPECT_NE(j["channels"][1]["error"].get<std::string>().find("mean period"), std::string::npos) << j["channels"][1];
  r = run("estimate " + f + " --time-column 1 --column 2 --column 3 --each --quiet");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.out.find("not estimated (why: the warning below)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("agreement       not judged: fewer than two estimates"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("could not be estimated: series too short"), std::string::npos) << r.out;
}

TEST_F(Cli, EachChannelWithAConstantOneEstimatesTheOthers) {
  // A constrained component is written as zeros throughout (an MBDyn joint's reaction about a free
  // axis): with --each that column is its own error row, and the others are estimated as without it,
  // also from the transient --from auto finds on the channels that move. Alone, it stays the file's
  // error (a constant series has no dynamics to analyse).
  const double dt = 0.01, zeta = 0.05, w = 2 * M_PI;
  const auto a = mlce::reference::damped_oscillator(2000, dt, zeta, w);
  const std::vector<double> zero(a.size(), 0.0);
  const auto f = columns_file("zero.txt", "# time decay zero", dt, {a, zero});
  for (const char* from : {"", " --from auto"}) {
    CliRun r = run("estimate " + f + " --time-column 1 --column 2 --column 3 --each --json --quiet" + from);
    EXPECT_EQ(r.status, 1) << from << r.err;
    EXPECT_NE(r.err.find("zero.txt: 1 of 2 channels could not be estimated (zero)"), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["estimated"], 1);
    EXPECT_NEAR(j["channels"][0]["lambda"].get<double>(), -zeta * w, 0.03 * zeta * w) << from;  // lambda = -zeta omega
    EXPECT_NE(j["channels"][1]["error"].get<std::string>().find("zero is constant (all 2000 samples equal 0)"),
              std::string::npos) << j["channels"][1];
  }
  expect_one_line_error(run("estimate " + f + " --time-column 1 --column 2 --column 3"), "zero is constant");
  expect_one_line_error(run("estimate " + f + " --time-column 1 --column 3 --column 3 --each --from auto"),
                        "zero is constant");
}

TEST_F(Cli, MissingFile) {
  expect_one_line_error(run("estimate " + (dir / "nope.txt").string()), "nope.txt: cannot open the file");
}

TEST_F(Cli, EmptyFile) { expect_one_line_error(run("estimate " + write("e.txt", "").string()), "e.txt: no data"); }

TEST_F(Cli, TextInNumericColumn) {
  expect_one_line_error(run("estimate " + write("t.txt", "0 1\n0.1 2\n0.2 x3\n").string() + " --column 2 --dt 0.1"),
                        "t.txt:3: column 2: 'x3' is not a number");
}

TEST_F(Cli, NanAndInf) {
  expect_one_line_error(run("estimate " + write("n.txt", "1\n2\nnan\n").string()), "n.txt:3: column 1: 'nan'");
  expect_one_line_error(run("estimate " + write("i.txt", "1\n-inf\n").string()), "i.txt:2: column 1: '-inf'");
}

TEST_F(Cli, RunThatDivergesAfterTheWindowIsAnalysedUpToTo) {
  // A solver run that blew up after sample 3000: nan from there on. Analysed with --to before the
  // blow-up it gives exactly the exponent of a file that holds only the finite rows.
  constexpr std::size_t kFinite = 3000;
  const auto x = mlce::reference::lorenz_x(4000, 0.01);
  std::ostringstream diverged, finite, one_column;
  diverged.precision(17), finite.precision(17), one_column.precision(17);
  diverged << "# time value junk\n";
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = 0.01 * static_cast<double>(i);
    // a third column the analysis does not use is nan throughout
    if (i < kFinite) diverged << t << " " << x[i] << " nan\n", finite << t << " " << x[i] << "\n", one_column << x[i] << "\n";
    else diverged << t << " nan nan\n", one_column << "-inf\n";
  }
  const std::string d = write("diverged.txt", diverged.str()).string(), f = write("finite.txt", finite.str()).string();
  const std::string o = write("one.txt", one_column.str()).string();
  const CliRun refused = run("estimate " + d + " --time-column 1 --column 2");
  expect_one_line_error(refused, "diverged.txt:3002: column 2: 'nan': expected a finite number (did the run diverge? the 3000 "
                                 "rows before it, to t = 29.99");
  EXPECT_NE(refused.err.find(": --to 29.99"), std::string::npos) << refused.err;
  expect_one_line_error(run("estimate " + o + " --dt 0.01"), "one.txt:3001: column 1: '-inf'");
  expect_one_line_error(run("extract " + d + " --channel col:2 --to 5"), "--to needs a set with a time axis", 2);
  expect_one_line_error(run("estimate " + d + " --time-column 1 --column 2 --to -1"),
                        "diverged.txt: no output step at t <= -1 (the first is at t = 0)");
  expect_one_line_error(run("estimate " + write("nantime.txt", "0 1\n0.1 2\nnan 3\n0.3 4\n").string() +
                            " --time-column 1 --column 2 --to 0.2"),
                        "nantime.txt:3: column 1: 'nan': expected a finite number");

  auto lambda_of = [&](const std::string& args) {
    const CliRun r = run("estimate " + args + " --json --quiet");
    EXPECT_EQ(r.status, 0) << r.err;
    return r.status == 0 ? nlohmann::json::parse(r.out)["lambda"].get<double>() : std::nan("");
  };
  const double reference = lambda_of(f + " --time-column 1 --column 2");
  ASSERT_TRUE(std::isfinite(reference));
  EXPECT_EQ(lambda_of(d + " --time-column 1 --column 2 --to 29.99"), reference);
  EXPECT_EQ(lambda_of(o + " --dt 0.01 --to 29.99"), reference);
  EXPECT_EQ(lambda_of(d + " --time-column 1 --column 2 --from 5 --to 29.99"),
            lambda_of(f + " --time-column 1 --column 2 --from 5"));
  // A non-finite sample inside the window is still refused.
  std::string inside = diverged.str();
  const std::size_t at = inside.find("\n10 ") + 4;  // the row at t = 10, value field
  inside.replace(at, inside.find(' ', at) - at, "inf");
  expect_one_line_error(run("estimate " + write("inside.txt", inside).string() + " --time-column 1 --column 2 --to 29.99"),
                        "inside.txt:1002: column 2: 'inf': expected a finite number");
}

TEST_F(Cli, AnIsolatedSpikeIsRefusedNamingItsLineAndDespikeReplacesIt) {
  std::vector<double> x = mlce::reference::lorenz_x(10000);
  const std::string clean = columns_file("clean.txt", "# time value", 0.01, {x});
  x[5000] = 1000.0;  // one glitched sample: read as it is, lambda was 18.6 1/s, "chaotic"
  const std::string spiked = columns_file("spiked.txt", "# time value", 0.01, {x});
  const std::string refused = "spiked.txt:5002: value: sample 5000 (t = 50 s) is an isolated spike: 1000 between";
  for (const char* command : {"estimate", "ami", "fnn", "kantz", "modes", "stsp", "convergence"})
    expect_one_line_error(run(std::string(command) + " " + spiked + " --time-column 1 --column 2"), refused);
  auto lambda_of = [&](const std::string& args) {
    const CliRun r = run("estimate " + args + " --time-column 1 --column 2 --json --quiet");
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  const double reference = lambda_of(clean)["lambda"].get<double>();
  const auto despiked = lambda_of(spiked + " --despike");
  EXPECT_NEAR(despiked["lambda"].get<double>(), reference, 5e-3 * reference);
  EXPECT_NE(despiked["warnings"].dump().find("value: sample 5000 (t = 50 s) was an isolated spike (1000 between"),
            std::string::npos) << despiked["warnings"];
  // A window that starts after the glitch does not need it replaced.
  EXPECT_GT(lambda_of(spiked + " --from 50.01")["lambda"].get<double>(), 0.0);
}

TEST_F(Cli, ARunStillWritingItsFileIsReadUpToItsLastCompleteLine) {
  const std::vector<double> x = mlce::reference::lorenz_x(5000);
  std::string text = slurp(columns_file("whole.txt", "# time value", 0.01, {x}));
  const CliRun whole = run("estimate " + write("whole.txt", text).string() + " --time-column 1 --column 2 --json --quiet");
  ASSERT_EQ(whole.status, 0) << whole.err;
  text += "50.00 -1.2e";  // the solver is writing row 5000: its value cut inside the exponent
  const CliRun writing = run("estimate " + write("writing.txt", text).string() + " --time-column 1 --column 2 --json --quiet");
  ASSERT_EQ(writing.status, 0) << writing.err;
  const auto j = nlohmann::json::parse(writing.out), w = nlohmann::json::parse(whole.out);
  EXPECT_EQ(j["n_points"], w["n_points"]);
  EXPECT_EQ(j["lambda"], w["lambda"]);
  EXPECT_NE(j["warnings"].dump().find("writing.txt:5002: the last line has no line end and "), std::string::npos) << j["warnings"];
}

TEST_F(Cli, ARestartedRunIsRefusedWithWhereItRestartsAndReadBeforeItWithTo) {
  // Rows 0..2999, then a restart from t = 25 s that writes 25.00 .. 39.99 again.
  const std::vector<double> x = mlce::reference::lorenz_x(4000);
  std::ostringstream s;
  s.precision(17);
  for (int i = 0; i < 3000; ++i) s << 0.01 * i << " " << x[static_cast<std::size_t>(i)] << "\n";
  for (int i = 2500; i < 4000; ++i) s << 0.01 * i << " " << x[static_cast<std::size_t>(i)] << "\n";
  const std::string f = write("restart.txt", s.str()).string();
  expect_one_line_error(run("estimate " + f + " --time-column 1 --column 2"),
                        "restart.txt:3001: time does not increase at sample 3000 (29.99 then 25): expected strictly "
                        "increasing time; a restarted run, or two runs joined? --to 29.99 analyses the samples before");
  const CliRun before = run("estimate " + f + " --time-column 1 --column 2 --to 29.99 --json --quiet");
  ASSERT_EQ(before.status, 0) << before.err;
  EXPECT_EQ(nlohmann::json::parse(before.out)["n_points"], 3000);
}

TEST_F(Cli, NonUniformTime) {
  std::string s;
  for (int i = 0; i < 100; ++i) s += std::to_string(i < 50 ? 0.1 * i : 0.1 * i + 0.05) + " " + std::to_string(std::sin(i)) + "\n";
  const CliRun r = run("estimate " + write("u.txt", s).string() + " --time-column 1 --column 2");
  expect_one_line_error(r, "u.txt:51: non-uniform time step at sample 50");
}

TEST_F(Cli, ConstantSeries) {
  std::string t;
  for (int i = 0; i < 200; ++i) t += "3.5\n";
  expect_one_line_error(run("estimate " + write("c.txt", t).string()), "c.txt: column 1 is constant");
  // Constant on each side of a step: the floor rule cuts the record at the step, and the error says
  // the constant part is the part analysed (it read "all 100 samples" of a 200-sample file).
  std::string step;
  for (int i = 0; i < 200; ++i) step += i < 100 ? "0\n" : "1\n";
  expect_one_line_error(run("estimate " + write("step.txt", step).string()),
                        "step.txt: column 1 is constant (all 100 samples equal 0): no dynamics to analyse (the part "
                        "analysed, samples 0..99, ends where the floor rule cut the record: ");
  // One sample is no history (it was reported as a constant series of 1 sample).
  expect_one_line_error(run("estimate " + write("one.txt", "3.5\n").string()),
                        "one.txt: the series has a single sample: expected a time history");
}

TEST_F(Cli, SeriesTooShortForTheParameters) {
  const auto f = series_file(mlce::reference::henon_x(60), 1.0);
  expect_one_line_error(run("estimate " + f + " --column 2 --dt 1 --dim 3 --delay 10 --horizon 40 --theiler 5"),
                        "series.txt: series too short: 60 samples");
  expect_one_line_error(run("estimate " + f + " --column 2 --dt 1 --delay 20 --dim 3"), "series.txt: series too short");
  // A Theiler window longer than the series leaves FNN no pair: the message says what m = 1 needs.
  expect_one_line_error(run("estimate " + f + " --column 2 --dt 1 --delay 3 --theiler 100"),
                        "series.txt: series too short for FNN: 60 samples, but delay 3 and Theiler window 100 need at "
                        "least 105");
  // A limit cycle over 1.5 of its cycles: no neighbour on another pass (eq. 20).
  const auto v = series_file(mlce::reference::van_der_pol_x(10000, 0.001), 0.001);
  expect_one_line_error(run("estimate " + v + " --column 2 --time-column 1"),
                        "series.txt: series too short: 10000 samples span only 1.5");
}

TEST_F(Cli, AmbiguousColumnsAndBadOptions) {
  const auto f = series_file(mlce::reference::henon_x(100), 1.0);
  expect_one_line_error(run("estimate " + f), "the file has 2 columns");
  expect_one_line_error(run("estimate " + f + " --column 5"), "--column 5 requested, but the file has 2 column(s)");
  expect_one_line_error(run("estimate " + f + " --column 0"), "--column 0 requested, but the file has 2 column(s), numbered from 1");
  expect_one_line_error(run("estimate " + f + " --column 2 --delay x"), "--delay 'x'", 2);
  expect_one_line_error(run("estimate " + f + " --column 2 --fit 9:3"), "expected first < last", 2);
  expect_one_line_error(run("estimate " + f + " --column 2 --align-phase maybe"),
                        "--align-phase 'maybe': expected auto, on or off", 2);
  expect_one_line_error(run("estimate " + f + " --column 2 --dither -1"), "--dither: expected a width >= 0", 2);
  expect_one_line_error(run("estimate " + f + " --column 2 --dither x"), "--dither", 2);
  expect_one_line_error(run("estimate " + f + " --column 2 --dither 1 --seed -3"), "--seed '-3'", 2);
  expect_one_line_error(run("estimate " + f + " --column 2 --dt 1 --to nan"), "--to 'nan': expected a time", 2);
  expect_one_line_error(run("estimate " + f + " --column 2 --dt 1 --from nan"), "--from 'nan': expected a time", 2);
}

TEST_F(Cli, PhaseAlignmentSwitch) {
  // Roessler x: automatic alignment (a saturating curve of a sampled flow), off gives the plain
  // curve's lambda, which `auto` reports as unaligned_lambda.
  const auto f = series_file(mlce::reference::roessler_x(10000, 0.1), 0.1);
  const auto on = nlohmann::json::parse(run("estimate " + f + " --column 2 --time-column 1 --json --quiet").out);
  const auto off =
      nlohmann::json::parse(run("estimate " + f + " --column 2 --time-column 1 --json --quiet --align-phase off").out);
  EXPECT_TRUE(on["phase_aligned"].get<bool>());
  EXPECT_GT(on["mean_phase_shift"].get<double>(), 0.0);
  EXPECT_FALSE(off["phase_aligned"].get<bool>());
  EXPECT_TRUE(off["unaligned_lambda"].is_null());
  EXPECT_DOUBLE_EQ(on["unaligned_lambda"].get<double>(), off["lambda"].get<double>());
  EXPECT_NEAR(on["lambda"].get<double>(), 0.0714, 0.1 * 0.0714);
  // The curve CSV carries the plain curve next to the aligned one, and only then.
  const auto curve = (dir / "aligned.csv").string(), plain_curve = (dir / "plain.csv").string();
  ASSERT_EQ(run("estimate " + f + " --column 2 --time-column 1 --quiet --curve " + curve).status, 0);
  ASSERT_EQ(run("estimate " + f + " --column 2 --time-column 1 --quiet --align-phase off --curve " + plain_curve).status, 0);
  const std::string a = slurp(curve), p = slurp(plain_curve);
  EXPECT_EQ(a.substr(0, a.find('\n')), "step,time,mean_log_distance,terms,in_fit,fit_line,plain_mean_log_distance,local_slope");
  EXPECT_EQ(p.substr(0, p.find('\n')), "step,time,mean_log_distance,terms,in_fit,fit_line,local_slope");
  EXPECT_EQ(on["phase_interpolation"].get<std::string>(), "linear");
  EXPECT_FALSE(off.contains("phase_interpolation"));
  // --phase-interpolation cubic reads the aligned neighbours on cubics, and says so; the plain
  // curve (the same pairs, not moved) is unchanged; a bad value is one error.
  const auto cubic = nlohmann::json::parse(
      run("estimate " + f + " --column 2 --time-column 1 --json --quiet --phase-interpolation cubic").out);
  EXPECT_EQ(cubic["phase_interpolation"].get<std::string>(), "cubic");
  EXPECT_DOUBLE_EQ(cubic["unaligned_lambda"].get<double>(), off["lambda"].get<double>());
  EXPECT_NEAR(cubic["lambda"].get<double>(), 0.0714, 0.1 * 0.0714);
  const auto bad = run("estimate " + f + " --column 2 --time-column 1 --phase-interpolation spline");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--phase-interpolation 'spline': expected linear or cubic"), std::string::npos) << bad.err;
  // A map (Henon, mean period < 8 samples) is never aligned automatically.
  const auto h = series_file(mlce::reference::henon_x(5000), 1.0);
  EXPECT_FALSE(nlohmann::json::parse(run("estimate " + h + " --column 2 --json --quiet").out)["phase_aligned"].get<bool>());
}

TEST_F(Cli, QuantisedSeriesIsFlaggedAndDitherIsReproducible) {
  // Lorenz x rounded to integers (its standard deviation is ~8): the points repeat ~20 times per
  // reference and the estimate is unreliable, which the warnings say; --dither 1 (one quantum)
  // makes the distances continuous, says so, and gives the same lambda for the same seed.
  auto x = mlce::reference::lorenz_x(10000, 0.01);
  // The noise the dithered series carries: rounding error plus the dither's 1/sqrt(12), over the
  // dithered series' standard deviation (its variance: the rounded series' plus 1/12).
  double mean_x = 0, mean_e = 0, var_x = 0, var_e = 0;
  for (double v : x) mean_x += std::round(v) / 1e4, mean_e += (std::round(v) - v) / 1e4;
  for (double v : x)
    var_x += (std::round(v) - mean_x) * (std::round(v) - mean_x) / 1e4,
        var_e += (std::round(v) - v - mean_e) * (std::round(v) - v - mean_e) / 1e4;
  const double noise_truth = std::sqrt((var_e + 1.0 / 12) / (var_x + 1.0 / 12));
  for (double& v : x) v = std::round(v);
  const auto f = series_file(x, 0.01);
  const std::string base = "estimate " + f + " --column 2 --time-column 1 --json --quiet";
  auto has = [](const nlohmann::json& j, const std::string& what) {
    for (const auto& w : j["warnings"])
      if (w.get<std::string>().find(what) != std::string::npos) return true;
    return false;
  };
  const auto plain = nlohmann::json::parse(run(base).out);
  EXPECT_TRUE(has(plain, "lambda is unreliable")) << plain["warnings"];
  const auto d1 = nlohmann::json::parse(run(base + " --dither 1").out);
  const auto d1again = nlohmann::json::parse(run(base + " --dither 1 --seed 1").out);
  const auto d7 = nlohmann::json::parse(run(base + " --dither 1 --seed 7").out);
  EXPECT_TRUE(has(d1, "dithered: uniform noise of width 1")) << d1["warnings"];
  EXPECT_FALSE(has(d1, "lambda is unreliable")) << d1["warnings"];
  EXPECT_EQ(d1["lambda"].get<double>(), d1again["lambda"].get<double>());
  EXPECT_NE(d1["lambda"].get<double>(), d7["lambda"].get<double>());
  // The rounded series' FNN leaves a plane (m = 2: 14.5 % false at m = 1, 0.01 % at 2), where its
  // repeated points' pairs read 1.50; its curve saturates, so a flow's state is widened to m = 3
  // (estimate_mlce), and it stays unreliable. The dithered series: within 20 % of lambda_1 = 0.9056.
  EXPECT_EQ(plain["dim"].get<int>(), 3) << plain["fnn_fraction"];
  EXPECT_EQ(plain["dim_widened_because"].get<std::string>(), "flow_in_a_plane");
  const auto in_the_plane = nlohmann::json::parse(run(base + " --dim 2").out);
  std::printf("rounded, m = 2 given: %.4f; FNN's false fractions %s\n", in_the_plane["lambda"].get<double>(),
              plain["fnn_fraction"].dump().c_str());
  for (const auto& j : {d1, d7}) {
    std::printf("rounded: %.4f, dithered: %.4f, noise_level %.4f (quantum and dither: %.4f)\n",
                plain["lambda"].get<double>(), j["lambda"].get<double>(), j["noise_level"].get<double>(), noise_truth);
    // The dither is noise, and the curve's first step says how much (an upper estimate).
    EXPECT_TRUE(has(j, "measurement noise")) << j["warnings"];
    EXPECT_GE(j["noise_level"].get<double>(), 0.95 * noise_truth);
    EXPECT_LE(j["noise_level"].get<double>(), 1.6 * noise_truth);
    EXPECT_NEAR(j["lambda"].get<double>(), 0.9056, 0.2 * 0.9056);
  }
}

TEST_F(Cli, StartThatDoesNotRecurIsLeftOutUnlessKept) {
  // Lorenz x from (1, 1, 1) with nothing discarded: its spiral out of C- does not recur. By default
  // it is left out, said in a warning and in the text summary, and "from" is where the estimate
  // starts; --keep-start and a --from time keep it.
  const auto f = series_file(mlce::reference::lorenz_x(10000, 0.01, {1.0, 1.0, 1.0}, 0.0), 0.01);
  const std::string base = "estimate " + f + " --column 2 --time-column 1 --quiet";
  const auto left_out = nlohmann::json::parse(run(base + " --json").out);
  const auto skipped = left_out["skipped_start"].get<std::size_t>();
  EXPECT_GT(skipped, 0u);
  EXPECT_NEAR(left_out["from"].get<double>(), 0.01 * static_cast<double>(skipped), 1e-9);
  EXPECT_EQ(left_out["n_points"].get<std::size_t>(), 10000u - skipped);
  EXPECT_NE(left_out["warnings"].dump().find("do not recur"), std::string::npos) << left_out["warnings"];
  EXPECT_NE(run(base).out.find("samples do not recur: left out"), std::string::npos);
  const auto& scores = left_out["start_recurrence"]["scores"];
  ASSERT_GE(scores.size(), 2u);
  EXPECT_LT(scores[0].get<double>(), 0.5);  // the first window does not recur
  EXPECT_EQ(skipped % left_out["start_recurrence"]["window"].get<std::size_t>(), 0u);  // whole windows
  for (const std::string keep : {" --keep-start", " --from 0"}) {
    const auto kept = nlohmann::json::parse(run(base + " --json" + keep).out);
    EXPECT_EQ(kept["skipped_start"].get<std::size_t>(), 0u) << keep;
    EXPECT_EQ(kept["n_points"].get<std::size_t>(), 10000u) << keep;
    EXPECT_EQ(kept["from"].get<double>(), 0.0) << keep;
  }
  // --from auto is a transient rule too: the RMS rule cuts nothing of the spiral, recurrence does.
  const auto automatic = nlohmann::json::parse(run(base + " --json --from auto").out);
  EXPECT_EQ(automatic["skipped_start"].get<std::size_t>(), skipped);
}

TEST_F(Cli, StartUpLeftOutByDistanceSaysSoInTheJson) {
  // Lorenz x from a start near the origin whose scores see one low window only (test
  // Recurrence.LorenzStartUpOfOneLowWindowIsLeftOutByDistance): the JSON carries the distance test's
  // ratios, says it decided, and the warning names the typical distance. (1, 1, 1)'s start-up is cut
  // by the scores, and the distance test does not run.
  const auto f = series_file(
      mlce::reference::lorenz_x(10000, 0.01, {-0.86080969832381982, 1.5167301025649813, 0.76268365812864669}, 0.0), 0.01);
  const auto j = nlohmann::json::parse(run("estimate " + f + " --column 2 --time-column 1 --quiet --json").out);
  const auto& rec = j["start_recurrence"];
  ASSERT_TRUE(rec.contains("distance_ratios")) << rec;
  EXPECT_TRUE(rec["decided_by_distance"].get<bool>());
  const auto ratios = rec["distance_ratios"].get<std::vector<double>>();
  const auto window = rec["window"].get<std::size_t>(), skipped = j["skipped_start"].get<std::size_t>();
  ASSERT_EQ(ratios.size(), skipped / window + 1);
  EXPECT_EQ(skipped % window, 0u);
  EXPECT_LT(ratios.back(), 3.0);
  for (std::size_t w = 0; w + 1 < ratios.size(); ++w) EXPECT_GE(ratios[w], 3.0) << w;
  EXPECT_NE(j["warnings"].dump().find("typical distance"), std::string::npos) << j["warnings"];
  const auto spiral = nlohmann::json::parse(
      run("estimate " + series_file(mlce::reference::lorenz_x(10000, 0.01, {1.0, 1.0, 1.0}, 0.0), 0.01) +
          " --column 2 --time-column 1 --quiet --json")
          .out);
  EXPECT_FALSE(spiral["start_recurrence"].contains("distance_ratios")) << spiral["start_recurrence"];
}

TEST_F(Cli, FailedRunLeavesNoOutputFile) {
  const auto csv = dir / "curve.csv";
  const CliRun r = run("estimate " + write("c.txt", "1\n1\n1\n1\n").string() + " --curve " + csv.string());
  EXPECT_NE(r.status, 0);
  EXPECT_FALSE(fs::exists(csv));
}

TEST_F(Cli, AnyCombinationOfEstimatorOptionsEndsInAResultOrOneClearError) {
  // The contract of every run, over option values an analyst may type, extreme ones included
  // (delay 400, horizon 2, Theiler window 3000, dither 1e9, a window past the run's end): status 0
  // with finite figures, or status 1 (data) / 2 (usage) with exactly one error line; never a crash,
  // a hang, a NaN or an infinity printed. 120 combinations drawn with a fixed seed.
  const std::string data = MLCE_DATA_DIR;
  const std::vector<std::string> inputs = {
      data + "/lorenz_x.txt --time-column 1 --column 2",
      data + "/mbdyn/iso_200rpm_1s/iso_200rpm --channel rel:13:4:z",
      data + "/mbdyn/iso_200rpm_1s/iso_200rpm.nc --channel joint:33:14",
      data + "/mbdyn/c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf --channel node:2:x --channel rel:13:4:z"};
  const std::vector<std::pair<std::string, std::vector<std::string>>> options = {
      {"--delay", {"1", "2", "50", "auto", "400"}},        {"--dim", {"1", "2", "5", "12", "auto"}},
      {"--theiler", {"0", "1", "100", "auto", "3000"}},     {"--horizon", {"2", "3", "10", "auto", "800"}},
      {"--fit", {"auto", "0:1", "2:9", "1:2"}},             {"--from", {"auto", "0", "0.3", "5", "20"}},
      {"--to", {"0.5", "1", "9", "50"}},                    {"--refs", {"1", "10", "all", "500"}},
      {"--align-phase", {"on", "off", "auto"}},             {"--phase-interpolation", {"linear", "cubic"}},
      {"--dither", {"0", "1e-9", "0.5", "1e9"}},            {"--noise-compensation", {"auto", "off"}}};
  const std::vector<std::string> switches = {"--resample", "--keep-start", "--each"};
  std::mt19937 pick(20261127);
  const std::regex non_finite(R"(\b-?(nan|inf)\b)", std::regex::icase);
  int statuses[3] = {0, 0, 0};
  for (int k = 0; k < 120; ++k) {
    std::string args = "estimate " + inputs[pick() % inputs.size()];
    std::vector<std::size_t> order(options.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), pick);
    for (std::size_t i = 0, n = 1 + pick() % 5; i < n; ++i) {
      const auto& [name, values] = options[order[i]];
      args += " " + name + " " + values[pick() % values.size()];
    }
    for (const auto& s : switches)
      if (pick() % 5 == 0) args += " " + s;
    const bool json = pick() % 2 == 0;
    if (json) args += " --json";
    const CliRun r = run(args + " --quiet");
    ASSERT_GE(r.status, 0) << args;
    ASSERT_LE(r.status, 2) << args << "\n" << r.err;
    ++statuses[r.status];
    if (r.status != 0) {
      std::size_t error_lines = 0;
      std::istringstream lines(r.err);
      for (std::string line; std::getline(lines, line);) error_lines += line.find(": error: ") != std::string::npos;
      EXPECT_EQ(error_lines, 1u) << args << "\n" << r.err;
      continue;
    }
    EXPECT_FALSE(std::regex_search(r.out, non_finite)) << args << "\n" << r.out;
    if (json && args.find("--each") == std::string::npos) {
      const auto j = nlohmann::json::parse(r.out);
      EXPECT_TRUE(j["lambda"].is_number()) << args << "\n" << r.out;
    }
  }
  // Both outcomes were drawn (a set of only refusals would test little).
  EXPECT_GT(statuses[0], 20);
  EXPECT_GT(statuses[1] + statuses[2], 20);
}

TEST_F(Cli, ResultsThatCannotReachStandardOutputAreAnErrorNotASuccess) {
  // `mlce ... > out.csv` on a full disk: the buffered writes fail only when flushed at exit, and the
  // command ended with status 0 and a cut file. /dev/full refuses every byte as a full disk does;
  // a closed stdout (>&-) is the other way to lose the results.
  const std::string file = std::string(MLCE_DATA_DIR) + "/lorenz_x.txt";
  for (const std::string& redirect : {std::string(" >/dev/full"), std::string(" >&-")}) {
    if (redirect == " >/dev/full" && !fs::is_character_file("/dev/full")) continue;
    const fs::path err = dir / "stdout_err";
    const int rc = std::system((std::string(MLCE_CLI) + " estimate " + file + " --time-column 1 --column 2 --json --quiet" +
                                redirect + " 2>" + err.string() + " </dev/null").c_str());
    ASSERT_TRUE(WIFEXITED(rc)) << redirect;
    EXPECT_EQ(WEXITSTATUS(rc), 1) << redirect;
    EXPECT_EQ(slurp(err), "mlce estimate: error: standard output: write failed\n") << redirect;
  }
}

TEST_F(Cli, ATimeColumnLeftOutIsSaidSinceTheFiguresAreThenPerSample) {
  // `--column x` alone on a file with a time column: the result is per sample, 100 times the
  // per-second figure at dt = 0.01 s read as such. The header says which column is the time.
  std::string text = "Time [s],temperature,x\n", untimed = "temperature,x\n";
  const auto x = mlce::reference::lorenz_x(3000, 0.01);
  for (std::size_t k = 0; k < x.size(); ++k) {
    text += std::to_string(0.01 * static_cast<double>(k)) + ",1," + std::to_string(x[k]) + "\n";
    untimed += "1," + std::to_string(x[k]) + "\n";
  }
  const std::string file = write("lorenz.csv", text).string();
  const CliRun per_sample = run("estimate " + file + " --column x --json --quiet");
  ASSERT_EQ(per_sample.status, 0) << per_sample.err;
  const auto j = nlohmann::json::parse(per_sample.out);
  EXPECT_EQ(j["lambda"], j["lambda_per_sample"]);
  ASSERT_NE(j["warnings"].dump().find("the results are per sample: column 1 ('Time [s]') looks like the time; "
                                      "--time-column 1 (or --dt DT) gives them per time unit"),
            std::string::npos) << j["warnings"].dump();
  for (const char* given : {" --time-column 1", " --dt 0.01"}) {
    const CliRun timed = run("estimate " + file + " --column x --json --quiet" + given);
    ASSERT_EQ(timed.status, 0) << timed.err;
    EXPECT_EQ(timed.out.find("looks like the time"), std::string::npos) << given;
  }
  // "temperature" is no time: a file without one says nothing.
  const CliRun plain = run("estimate " + write("no_time.csv", untimed).string() + " --column x --json --quiet");
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_EQ(plain.out.find("looks like the time"), std::string::npos) << plain.out;
}

TEST_F(Cli, ASpreadsheetsSemicolonCsvWithDecimalCommasReadsAsItsNumbers) {
  // The bundled series as Excel saves it in a locale whose decimal mark is a comma: the same estimate.
  const std::string file = std::string(MLCE_DATA_DIR) + "/lorenz_x.txt";
  const CliRun named = run("estimate " + file + " --time-column 1 --column 2 --json --quiet");
  ASSERT_EQ(named.status, 0) << named.err;
  std::istringstream in(slurp(file));
  std::string csv = "time;x\r\n", line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), '.', ',');
    std::replace(line.begin(), line.end(), ' ', ';');
    csv += line + "\r\n";
  }
  const CliRun european = run("estimate " + write("series.csv", csv).string() + " --time-column time --column x --json --quiet");
  ASSERT_EQ(european.status, 0) << european.err;
  EXPECT_EQ(nlohmann::json::parse(european.out)["lambda"].get<double>(),
            nlohmann::json::parse(named.out)["lambda"].get<double>());
}

TEST_F(Cli, SeriesFromStandardInputOrAPipe) {
  // `cat series | mlce estimate -`, `<(command)`, a FIFO: read once, front to back, as the file.
  const std::string file = std::string(MLCE_DATA_DIR) + "/lorenz_x.txt";
  const std::string options = " --time-column 1 --column 2 --json --quiet";
  const CliRun named = run("estimate " + file + options);
  ASSERT_EQ(named.status, 0) << named.err;
  const double lambda = nlohmann::json::parse(named.out)["lambda"].get<double>();
  const CliRun piped = run("estimate -" + options, "", file);
  ASSERT_EQ(piped.status, 0) << piped.err;
  EXPECT_EQ(nlohmann::json::parse(piped.out)["lambda"].get<double>(), lambda);
  const fs::path fifo = dir / "series.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A writer that waits for mlce to open the FIFO (a non-blocking open fails until a reader has it
  // open), for 60 s at most: a reader that never comes fails the test instead of hanging it.
  std::signal(SIGPIPE, SIG_IGN);  // a reader that stops early fails the test, not kills it
  std::thread writer([&] {
    int fd = -1;
    for (int k = 0; k < 6000 && fd < 0; ++k) {
      fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd < 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (fd < 0) return;
    ::fcntl(fd, F_SETFL, 0);  // blocking writes from here on
    const std::string text = slurp(file);
    for (std::size_t at = 0; at < text.size();) {
      const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
      if (n <= 0) break;
      at += static_cast<std::size_t>(n);
    }
    ::close(fd);
  });
  const CliRun through_fifo = run("estimate " + fifo.string() + options);
  writer.join();
  ASSERT_EQ(through_fifo.status, 0) << through_fifo.err;
  EXPECT_EQ(nlohmann::json::parse(through_fifo.out)["lambda"].get<double>(), lambda);
  const CliRun listed = run("channels -", "", file);
  ASSERT_EQ(listed.status, 0) << listed.err;
  EXPECT_NE(listed.out.find("10000 rows, 2 columns"), std::string::npos) << listed.out;
  // Errors name the standard input and its line; compressed data on a pipe is said, not misread.
  expect_one_line_error(run("estimate -", "", write("bad.txt", "1\n2\nx\n").string()), "stdin:3: column 1: 'x' is not a number");
  expect_one_line_error(run("estimate -", "", "/dev/null"), "stdin: no data");
  const std::string gz = (dir / "series.gz").string();
  ASSERT_EQ(std::system(("gzip -c -n " + file + " > " + gz).c_str()), 0);
  expect_one_line_error(run("estimate -" + options, "", gz), "stdin: gzip-compressed data from a pipe: decompress it");
  const CliRun named_gz = run("estimate " + gz + options);  // named, it reads
  ASSERT_EQ(named_gz.status, 0) << named_gz.err;
  EXPECT_EQ(nlohmann::json::parse(named_gz.out)["lambda"].get<double>(), lambda);
}

TEST_F(Cli, BundledDemoSeries) {
  const CliRun r = run(std::string("estimate ") + MLCE_DATA_DIR + "/lorenz_x.txt --time-column 1 --column 2 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  // The bundled series is reference::lorenz_x(10000): one draw of an estimator whose series-to-
  // series scatter is several per cent (EstimateSystems.LorenzWithinFivePercentOnMostSeries).
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["lambda"].get<double>(), 0.9056, 0.12 * 0.9056);
  EXPECT_TRUE(j["phase_aligned"].get<bool>());
  EXPECT_GT(j["unaligned_lambda"].get<double>(), 0.0);
}
