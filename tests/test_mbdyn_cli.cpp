// MBDyn output sets through the command line: the real samples work, and every malformed set
// gives one line naming the file (and line) and a non-zero exit.
#include <gtest/gtest.h>
#include <unistd.h>
#include <sys/wait.h>
#include <signal.h>
#include <fcntl.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <tuple>
#include <thread>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "cli_harness.hpp"

namespace fs = std::filesystem;
using mlce::testing::CliRun;
using mlce::testing::expect_one_line_error;
using mlce::testing::slurp;

namespace {

const std::string kIso = std::string(MLCE_DATA_DIR) + "/mbdyn/iso_200rpm_1s/iso_200rpm";
const std::string kC3 = std::string(MLCE_DATA_DIR) + "/mbdyn/c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf";

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> v;
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

class MbdynCli : public mlce::testing::CliFixture {
 protected:
  std::string prefix;
  void SetUp() override {
    CliFixture::SetUp();
    for (const char* e : {".log", ".out", ".mov", ".jnt"}) {
      fs::copy_file(kIso + e, dir / (std::string("run") + e));
      fs::permissions(dir / (std::string("run") + e), fs::perms::owner_read | fs::perms::owner_write);
    }
    prefix = (dir / "run").string();
  }
  /// The JSON an `mlce` command prints with --json (the test fails on a non-zero exit).
  nlohmann::json json_of(const std::string& args) {
    const CliRun r = run(args + " --json");
    EXPECT_EQ(r.status, 0) << args << ": " << r.err;
    return r.status == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
  }
  /// The largest exponent of `command` (eigen, floquet) of a bundled scene: the linearisation's.
  double linearisation_exponent(const std::string& command, const std::string& scene) {
    return json_of(command + " " + std::string(MLCE_DATA_DIR) + "/../scenes/" + scene + " --quiet")["exponents"][0].get<double>();
  }
  /// Replaces line `n` (1-based) of run.EXT by `edit(line)`.
  template <class F>
  void edit_line(const std::string& ext, std::size_t n, F edit) {
    auto v = lines_of(prefix + ext);
    v.at(n - 1) = edit(v.at(n - 1));
    std::ofstream o(prefix + ext, std::ios::trunc);
    for (const auto& l : v) o << l << "\n";
  }
};

}  // namespace

TEST_F(MbdynCli, EstimateOnTheFailedDamperRunPrintsAnMlce) {
  const CliRun r = run("estimate " + kC3 + " --channel rel:13:4:z --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(std::isfinite(j["lambda"].get<double>()));
  EXPECT_NEAR(j["dt"].get<double>(), 0.005, 1e-12);
  EXPECT_EQ(j["n_points"].get<std::size_t>(), 2001u);
}

TEST_F(MbdynCli, ReadingOfTheRealRunsFollowsTheirKnownStability) {
  // The shared MBDyn runs (data/mbdyn/README.md): the isotropic rotor at 200 rpm is asymptotically
  // stable (eigen -1.18 1/s); with blade 3's damper inoperative at 242.4 rpm the trivial solution is
  // linearly unstable, so its first 10 s grow (ground resonance) and its later part is a limit
  // cycle (paper 001 Fig. 8). Blade 3's lag (rel:13:4:z) of each, with the summary's first words.
  const std::string mbdyn = std::string(MLCE_DATA_DIR) + "/mbdyn/";
  const struct {
    std::string set, stability, motion;
  } runs[] = {{"iso_200rpm_5s/iso_200rpm", "stable", "decays to rest"},
              {"c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf", "unstable", "growing oscillation"},
              {"c3zero_242rpm_cyhalf_lco/c3zero_242rpm_cyhalf", "neutral", "limit cycle"}};
  for (const auto& k : runs) {
    const CliRun r = run("estimate " + mbdyn + k.set + " --channel rel:13:4:z --json --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out)["reading"];
    EXPECT_EQ(j["stability"], k.stability) << k.set << ": " << j.dump();
    EXPECT_EQ(j["motion"], k.motion) << k.set << ": " << j.dump();
    EXPECT_EQ(j["summary"].get<std::string>().rfind(k.stability + ":", 0), 0u) << j.dump();
    const CliRun text = run("estimate " + mbdyn + k.set + " --channel rel:13:4:z --quiet");
    EXPECT_NE(text.out.find("reading         " + k.stability + ":"), std::string::npos) << text.out;
  }
}

TEST_F(MbdynCli, SeveralRunsAreOneTableWithTheirKnownStabilityAndWhereItChanges) {
  // The three real runs of the test above in one command (as an analyst reads a set of MBDyn runs
  // over a parameter, paper 001 Figs. 11-12): each row is the run's own estimate and reading, the
  // growth within 10 % of its Floquet exponent (+0.2985 1/s, data/mbdyn/README.md), and the table
  // says where the reading changes, with the straight line's zero between a stable and an unstable run.
  const std::string mbdyn = std::string(MLCE_DATA_DIR) + "/mbdyn/";
  const std::string runs = mbdyn + "iso_200rpm_5s/iso_200rpm " + mbdyn + "c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf " +
                           mbdyn + "c3zero_242rpm_cyhalf_lco/c3zero_242rpm_cyhalf";
  const fs::path csv = dir / "runs.csv";
  const CliRun r = run("estimate " + runs + " --channel rel:13:4:z --param case=1:3:1 --json --quiet --csv " + csv.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["runs"].size(), 3u);
  const char* stability[] = {"stable", "unstable", "neutral"};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(j["runs"][k]["reading"]["stability"], stability[k]) << j["runs"][k].dump();
    EXPECT_EQ(j["runs"][k]["parameter"].get<double>(), static_cast<double>(k + 1));
  }
  const double stable = j["runs"][0]["lambda"].get<double>(), growth = j["runs"][1]["lambda"].get<double>();
  EXPECT_NEAR(growth, 0.2985, 0.1 * 0.2985);
  EXPECT_LT(stable, 0.0);
  EXPECT_EQ(j["estimated"].get<std::size_t>(), 3u);
  EXPECT_EQ(j["parameter"], "case");
  ASSERT_EQ(j["stability_changes"].size(), 2u) << j["stability_changes"].dump();
  EXPECT_EQ(j["stability_changes"][0]["from"], "stable");
  EXPECT_EQ(j["stability_changes"][0]["to"], "unstable");
  EXPECT_NEAR(j["stability_changes"][0]["lambda_zero_at"].get<double>(), 1.0 + stable / (stable - growth), 1e-12);
  EXPECT_TRUE(j["stability_changes"][1]["lambda_zero_at"].is_null()) << "unstable to neutral: no rate to draw a line through";
  const auto table = lines_of(csv);
  ASSERT_EQ(table.size(), 4u);
  EXPECT_EQ(table[0].rfind("run,file,case,lambda,ci95_low,ci95_high,unit,", 0), 0u) << table[0];
  EXPECT_NE(table[3].find(",neutral,limit cycle,"), std::string::npos) << table[3];

  const fs::path png = dir / "runs.png";
  const CliRun text = run("estimate " + runs + " --channel rel:13:4:z --param case=1,2,3 --quiet --plot " + png.string());
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_GT(fs::file_size(png), 1000u);
  EXPECT_NE(text.out.find("stability changes between case = 1 (stable) and case = 2 (unstable): lambda = 0 at case = "),
            std::string::npos) << text.out;
  EXPECT_NE(text.out.find("stability changes between case = 2 (unstable) and case = 3 (neutral)\n"), std::string::npos)
      << text.out;
}

TEST_F(MbdynCli, ARunThatCannotBeEstimatedKeepsItsRowAndIsADataError) {
  const std::string missing = (dir / "missing").string();
  const CliRun r = run("estimate " + kC3 + " " + missing + " " + kC3 + " --channel rel:13:4:z --json --quiet");
  EXPECT_EQ(r.status, 1);
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["runs"].size(), 3u);
  EXPECT_EQ(j["estimated"].get<std::size_t>(), 2u);
  EXPECT_NE(j["runs"][1]["error"].get<std::string>().find(missing), std::string::npos) << j["runs"][1].dump();
  EXPECT_EQ(j["runs"][0]["lambda"], j["runs"][2]["lambda"]);
  EXPECT_EQ(j["runs"][0]["reading"]["stability"], "unstable");
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("error: 1 of 3 runs could not be estimated (" + missing + ")"), std::string::npos) << r.err;
  // The table as CSV: a name or a message with a comma or a quote is one quoted field (RFC 4180), so
  // the reader of column files (a separate parser) finds every row as wide as the header.
  const std::string odd = (dir / "miss,ing \"run\"").string();
  const fs::path csv = dir / "runs.csv";
  EXPECT_EQ(run("estimate " + kC3 + " '" + odd + "' --channel rel:13:4:z --quiet --csv " + csv.string()).status, 1);
  const auto rows = lines_of(csv);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2].rfind("2,\"" + (dir / "miss,ing \"\"run\"\"").string() + "\",,", 0), 0u) << rows[2];
  const CliRun listed = run("channels " + csv.string());
  ASSERT_EQ(listed.status, 0) << listed.err;
  EXPECT_NE(listed.out.find("2 rows, 18 columns"), std::string::npos) << listed.out;
  // None estimated: every row says why, no plot is drawn (there is nothing to draw), one error line.
  const CliRun none = run("estimate " + missing + " " + missing + "2 --channel rel:13:4:z --quiet --plot " + (dir / "n.png").string());
  EXPECT_EQ(none.status, 1);
  EXPECT_NE(none.out.find("error: " + missing + "2: "), std::string::npos) << none.out;
  EXPECT_NE(none.err.find("error: none of the 2 runs could be estimated"), std::string::npos) << none.err;
  EXPECT_EQ(std::count(none.err.begin(), none.err.end(), '\n'), 1) << none.err;
  EXPECT_FALSE(fs::exists(dir / "n.png"));
  // Options that fit no set of runs are usage errors, before anything is read.
  expect_one_line_error(run("estimate " + kC3 + " " + kC3 + " " + kC3 + " --channel rel:13:4:z --param rpm=1,2"),
                        "--param rpm=1,2: 2 values for 3 runs", 2);
  expect_one_line_error(run("estimate " + kC3 + " " + kC3 + " --channel rel:13:4:z --channel node:2:x --each"), "--each", 2);
  expect_one_line_error(run("estimate " + kC3 + " --channel rel:13:4:z --csv " + (dir / "t.csv").string()),
                        "--csv: the table of several runs", 2);
  EXPECT_FALSE(fs::exists(dir / "t.csv"));
  expect_one_line_error(run("estimate " + kC3 + " " + kC3 + " --channel rel:13:4:z --delay 0"), "delay = 0: expected >= 1", 2);
  expect_one_line_error(run("estimate " + kC3 + " " + kC3 + " --channel rel:13:4"), "channel 'rel:13:4': expected", 2);
  // What fits one file and not another is that run's: a column file among MBDyn sets.
  const CliRun mixed = run("estimate " + std::string(MLCE_DATA_DIR) + "/lorenz_x.txt " + kC3 + " --channel rel:13:4:z --quiet");
  EXPECT_EQ(mixed.status, 1);
  EXPECT_NE(mixed.out.find("lorenz_x.txt is a column file: channel 'rel:13:4:z' does not apply"), std::string::npos) << mixed.out;
  EXPECT_NE(mixed.out.find("unstable growing oscillation"), std::string::npos) << mixed.out;
}

TEST_F(MbdynCli, BladeHingeOfTheGrowingRunIsUnstableNotChaotic) {
  // node:12:x of the growing run (Floquet +0.2985 1/s): blade 2's hinge, e = 0.3048 m off the axis,
  // carries the rotation, a steady carrier over the hub's growth. Unstable; no chaos claimed.
  const CliRun r = run("estimate " + kC3 + " --channel node:12:x --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out)["reading"];
  EXPECT_EQ(j["stability"], "unstable") << j.dump();
  EXPECT_EQ(j["motion"], "diverging") << j.dump();
}

TEST_F(MbdynCli, BladeCoordinatesWhoseCurveNeverSeparatesReadTheGrowthBeneathTheirCarrier) {
  // node:12:y and node:13:vx of the growing run carry the rotation (4.04 Hz = 242.4 rpm) over the hub's
  // growth: their curves never separate for good, and they read "neutral, limit cycle" until the
  // record's modes were asked. The growth beneath is the linearisation's (Floquet, from the equations).
  const double floquet = linearisation_exponent("floquet", "c3zero_242rpm.scene");
  for (const char* channel : {"node:12:y", "node:13:vx"}) {
    const CliRun r = run("estimate " + kC3 + " --channel " + channel + " --json --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    std::printf("%s: lambda %+.4f 1/s, carrier %s, Floquet %+.4f\n", channel, j["lambda"].get<double>(),
                j["carrier"].dump().c_str(), floquet);
    EXPECT_EQ(j["reading"]["stability"], "unstable") << j["reading"].dump();
    EXPECT_EQ(j["reading"]["motion"], "growth beneath a steady carrier") << j["reading"].dump();
    ASSERT_TRUE(j["carrier"].is_object()) << channel;
    EXPECT_NEAR(j["carrier"]["frequency"].get<double>(), 242.4 / 60.0, 1e-3) << channel;  // the rotation
    EXPECT_NEAR(j["carrier"]["growth_rate"].get<double>(), floquet, 0.05 * floquet) << channel;
  }
  // The limit-cycle run's same channels: a carrier, nothing growing beneath it.
  const std::string lco = std::string(MLCE_DATA_DIR) + "/mbdyn/c3zero_242rpm_cyhalf_lco/c3zero_242rpm_cyhalf";
  for (const char* channel : {"node:12:y", "node:13:vx", "rel:13:4:z"}) {
    const CliRun r = run("estimate " + lco + " --channel " + channel + " --json --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::parse(r.out)["carrier"].is_null()) << channel;
  }
}

TEST_F(MbdynCli, ARotatingBladeCoordinateOverAShortStableRunIsTheRotationNotADivergence) {
  // The 1 s isotropic run (3.3 rotor turns): blade coordinates carry the 200 rpm rotation over a hub
  // whose motion decays (the rotor's multiblade eigenvalues, a second method, are all stable). Over so
  // few periods their curves swing with the pairs' phase and read "unstable, diverging" (+1.6 .. +9
  // 1/s) until the record's modes were asked where the curve cannot tell: the rotation, undamped,
  // nearly all of the record: neutral, and named.
  const double eigen = linearisation_exponent("eigen", "isotropic_200rpm.scene");
  ASSERT_LT(eigen, 0.0);
  for (const char* channel : {"node:12:y", "node:11:vy", "node:14:y"}) {
    const CliRun r = run("estimate " + kIso + " --channel " + channel + " --json --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    std::printf("%s: lambda %+.4f 1/s, record modes %s\n", channel, j["lambda"].get<double>(),
                j["record_modes"].dump().c_str());
    EXPECT_EQ(j["reading"]["stability"], "neutral") << j["reading"].dump();
    ASSERT_TRUE(j["record_modes"].is_object()) << channel;
    EXPECT_TRUE(j["record_modes"]["describes_record"].get<bool>()) << channel;
    EXPECT_NEAR(j["record_modes"]["frequency"].get<double>(), 200.0 / 60.0, 2e-3) << channel;  // the rotation
    EXPECT_GE(j["record_modes"]["share"].get<double>(), 0.9) << channel;
    EXPECT_NE(j["reading"]["summary"].get<std::string>().find("carries the rotation"), std::string::npos);
  }
}

TEST_F(MbdynCli, ALagOverLessThanOnePeriodOfItsModeIsNotReadUnstable) {
  // Blade 1's lag over the 1 s isotropic run: 1.24 mean periods of a motion that persists, too few
  // for neighbours from another pass; the refusal points to the modes. Over 0.92 periods of its
  // least damped mode they read +0.254 1/s, but with a 95 % interval of [-0.088, +0.597]: the rotor is
  // stable (its slowest multiblade eigenvalue, a second method, -1.18), and "unstable, growing mode",
  // the reading before, was wrong; the sign is not resolved, and the reading says so.
  const double eigen = linearisation_exponent("eigen", "isotropic_200rpm.scene");
  ASSERT_LT(eigen, 0.0);
  const CliRun refused = run("estimate " + kIso + " --channel rel:11:4:z --quiet");
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("series too short"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("mlce modes"), std::string::npos) << refused.err;
  const auto j = json_of("modes " + kIso + " --channel rel:11:4:z --quiet");
  ASSERT_TRUE(j.is_object());
  std::printf("rel:11:4:z over 1 s: modes lambda %+.4f [%+.4f, %+.4f] (eigen %+.4f): %s\n", j["lambda"].get<double>(),
              j["ci95"][0].get<double>(), j["ci95"][1].get<double>(), eigen, j["reading"].get<std::string>().c_str());
  EXPECT_NE(j["stability"], "unstable");
  EXPECT_EQ(j["stability"], "undetermined");
  EXPECT_LT(j["ci95"][0].get<double>(), 0.0);
}

TEST_F(MbdynCli, ChannelOfRoundingNoiseReadsNoStability) {
  // node:2:y of the limit-cycle run: node 2 is the airframe's x-part, free in absolute x only
  // (../shared/data/mbdyn/README.md), so its y holds MBDyn's rounding, ~1e-22 m, white (lag-1
  // autocorrelation 0.01), up to 30x louder in places.
  // It is no decay into a noise floor and no instability: the reading is undetermined.
  const std::string set = std::string(MLCE_DATA_DIR) + "/mbdyn/c3zero_242rpm_cyhalf_lco/c3zero_242rpm_cyhalf";
  const CliRun r = run("estimate " + set + " --channel node:2:y --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["reading"]["stability"], "undetermined") << j["reading"].dump();
  EXPECT_EQ(j["n_points"].get<std::size_t>(), 2001u) << "analysed whole: no floor cut";
  for (const auto& w : j["warnings"]) EXPECT_EQ(w.get<std::string>().find("measurement noise"), std::string::npos) << w;
}

TEST_F(MbdynCli, ALagThatDecaysToItsWrittenResolutionReadsTheDecay) {
  // rel:11:4:z of the real isotropic run (0-20 s, data/mbdyn/README.md): blade 1's lag from two
  // nodes' orientations, which MBDyn writes in degrees with 7 digits, decays to a few quanta
  // (1e-5 deg, 1.7e-7 rad) about 0 by ~10 s. The rotor's slowest multiblade eigenvalue (a second
  // method, mlce eigen) is the truth for the decay. Before the resolution floor the whole record read
  // -0.89 1/s (its steps of a quantum analysed with the decay), and the windows of the quanta alone
  // "unstable, chaotic" (from 10 s, +171 1/s) and "unstable, growing oscillation" (from 15 s).
  const std::string file = std::string(MLCE_DATA_DIR) + "/mbdyn/iso_200rpm_rel11_20s.csv";
  const CliRun eigen = run("eigen " + std::string(MLCE_DATA_DIR) + "/../scenes/isotropic_200rpm.scene --json");
  ASSERT_EQ(eigen.status, 0) << eigen.err;
  const double slowest = nlohmann::json::parse(eigen.out)["exponents"][0].get<double>();
  ASSERT_LT(slowest, 0.0);
  const CliRun whole = run("estimate " + file + " --time-column 1 --column 2 --json --quiet");
  ASSERT_EQ(whole.status, 0) << whole.err;
  const auto w = nlohmann::json::parse(whole.out);
  std::printf("whole record: lambda %+.4f 1/s over %zu of 4001 samples (slowest eigenvalue %+.4f)\n",
              w["lambda"].get<double>(), w["n_points"].get<std::size_t>(), slowest);
  EXPECT_NEAR(w["lambda"].get<double>(), slowest, 0.02 * std::abs(slowest));
  EXPECT_EQ(w["reading"]["stability"], "stable");
  EXPECT_NE(w["warnings"].dump().find("decays to the resolution it was written with"), std::string::npos) << w["warnings"];
  for (const char* from : {"10", "15"}) {
    const CliRun r = run("estimate " + file + " --time-column 1 --column 2 --from " + from + " --json --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    std::printf("from %s s: lambda %+.4g 1/s, %s\n", from, j["lambda"].get<double>(),
                j["reading"]["summary"].get<std::string>().c_str());
    EXPECT_EQ(j["reading"]["stability"], "stable") << from;
    EXPECT_EQ(j["in_decay_floor"], true) << from;
    EXPECT_NE(j["warnings"].dump().find("resolution it was written with"), std::string::npos) << j["warnings"];
  }
}

TEST_F(MbdynCli, ConvergenceSaysWhetherTheReadingHoldsOverTheRun) {
  // mlce convergence reads every part (reading.hpp) and says whether the reading holds from half the
  // run on. Blade 3's lag of the growing run (0-10 s, ground resonance: the trivial solution is
  // linearly unstable, Floquet +0.2985 1/s at 242.4 rpm) reads a growing oscillation on every such part.
  const std::string mbdyn = std::string(MLCE_DATA_DIR) + "/mbdyn/";
  CliRun r = run("convergence " + mbdyn + "c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf --channel rel:13:4:z --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["points"].size(), 8u);
  for (std::size_t k = 3; k < 8; ++k) {
    EXPECT_EQ(j["points"][k]["stability"], "unstable") << j["points"][k];
    EXPECT_EQ(j["points"][k]["motion"], "growing oscillation") << j["points"][k];
  }
  EXPECT_TRUE(j["reading_settled"].get<bool>());
  // The 5 s isotropic run (stable, eigen -1.18 1/s) spans 4.5 mean periods: where a part of at
  // least half of it reads otherwise than the whole, the verdict says so, naming that part.
  r = run("convergence " + mbdyn + "iso_200rpm_5s/iso_200rpm --channel rel:13:4:z --json --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["points"].back()["stability"], "stable");
  bool differs = false;
  for (std::size_t k = 3; k < 8; ++k) differs |= j["points"][k]["stability"] != "stable";
  EXPECT_EQ(j["reading_settled"].get<bool>(), !differs);
  bool said = false;
  for (const auto& w : j["warnings"]) said |= w.get<std::string>().find("the reading changes with the run length") != std::string::npos;
  EXPECT_EQ(said, differs) << j["warnings"].dump();
}

TEST_F(MbdynCli, BladeAzimuthThatWrapsIsFlaggedAndItsLagIsNot) {
  // node:13:r3 is blade 3's absolute Euler angle about z: at 242 rpm it wraps at +-180 deg every
  // 0.25 s (41 times in 10 s, counted from the .mov). Its lag relative to the hub (rel:13:4:z) is
  // unwrapped by the reader and is not flagged.
  const CliRun azimuth = run("estimate " + kC3 + " --channel node:13:r3 --json");
  ASSERT_EQ(azimuth.status, 0) << azimuth.err;
  const auto a = nlohmann::json::parse(azimuth.out);
  bool said = false;
  for (const auto& w : a["warnings"]) said |= w.get<std::string>().find("and 41 time(s) in all, by a whole turn: an angle that wraps at +-180 deg") != std::string::npos;
  EXPECT_TRUE(said) << a["warnings"].dump();
  // ... so its exponent is not read as a stability (reading.hpp), and the JSON says why.
  EXPECT_EQ(a["unreliable"], "an angle that wraps by whole turns");
  EXPECT_EQ(a["reading"]["stability"], "undetermined");
  const CliRun lag = run("estimate " + kC3 + " --channel rel:13:4:z --json");
  ASSERT_EQ(lag.status, 0) << lag.err;
  EXPECT_EQ(lag.out.find("whole turn"), std::string::npos);
  EXPECT_TRUE(nlohmann::json::parse(lag.out)["unreliable"].is_null());
}

TEST_F(MbdynCli, ExtractWritesTimeAndChannelsAsCsv) {
  const CliRun r = run("extract " + kIso + ".nc --channel joint:33:14 --channel rel:13:4:z");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream s(r.out);
  std::string header, first;
  std::getline(s, header);
  std::getline(s, first);
  EXPECT_EQ(header, "time,joint:33:14,rel:13:4:z");
  EXPECT_EQ(first, "0,0,0");
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 202);
  const fs::path csv = dir / "lag.csv";
  ASSERT_EQ(run("extract " + prefix + " --channel joint:33:14 --csv " + csv.string()).status, 0);
  EXPECT_EQ(slurp(csv).substr(0, 26), "time,joint:33:14\n0,0\n0.005");
  // The CSV is streamed through a temporary beside it: written whole, it equals stdout's rows, and
  // no temporary is left behind; a path that cannot be written is one error and leaves nothing.
  const CliRun to_stdout = run("extract " + prefix + " --channel joint:33:14");
  EXPECT_EQ(slurp(csv), to_stdout.out);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp-mlce"), std::string::npos) << e.path();
  const fs::path blocked = csv / "lag.csv";  // its parent is a file
  expect_one_line_error(run("extract " + prefix + " --channel joint:33:14 --csv " + blocked.string()),
                        blocked.string() + ": cannot write the file", 1);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp-mlce"), std::string::npos) << e.path();
}

TEST_F(MbdynCli, ExtractDrawsTheChannelsAndALongRecordAsItsEnvelope) {
  const fs::path png = dir / "lag.png";
  const CliRun r = run("extract " + prefix + " --channel rel:13:4:z --channel node:2:x --plot " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 202);  // the CSV still goes to stdout
  EXPECT_EQ(slurp(png).substr(1, 3), "PNG");
  // 300 000 rows: drawn as the min/max envelope of buckets, not every row.
  const fs::path long_run = dir / "long.txt", long_png = dir / "long.png";
  {
    std::ofstream f(long_run);
    for (int k = 0; k < 300000; ++k) f << k * 1e-3 << ' ' << std::sin(2e-3 * k) << '\n';
  }
  const CliRun l = run("extract " + long_run.string() + " --channel col:2 --csv " + (dir / "long.csv").string() +
                       " --plot " + long_png.string());
  ASSERT_EQ(l.status, 0) << l.err;
  EXPECT_EQ(slurp(long_png).substr(1, 3), "PNG");
}

TEST_F(MbdynCli, ChannelsListsNodesJointsAndTimeSpan) {
  const CliRun r = run("channels " + prefix + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["blocks"], 201);
  EXPECT_EQ(j["nodes"].size(), 7u);
  EXPECT_EQ(j["nodes"][0]["orientation"], "euler123");
  EXPECT_EQ(j["entities"].size(), 9u);  // joints 2 3 4 5 6 31..34
  EXPECT_NEAR(j["time"][1].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(j["eigenanalyses"], 0);
  // An eigenvalue table in the .out (after its last Step line, as MBDyn's solver.cc prints one) is counted.
  std::ofstream(prefix + ".out", std::ios::app) << "Info: 0, success\nMode n.       Real          Imag             Damp %     Freq Hz\n"
                                                   "       1:          -2 -      44.6766 j      4.47214     -7.11049\n"
                                                   "       2:          -2 +      44.6766 j      4.47214      7.11049\n";
  EXPECT_EQ(nlohmann::json::parse(run("channels " + prefix + " --json").out)["eigenanalyses"], 1);
  // The set's eigenanalysis files (PREFIX_<k>.m) are counted (in place of the .out's tables, as
  // `mlce eigenanalysis SET` reads them) and the command that reads them named.
  for (const char* k : {"_0.m", "_1.m"}) std::ofstream(prefix + k) << "dCoef = 0.5;\nalpha = [0.5 0 1;\n];\n";
  EXPECT_EQ(nlohmann::json::parse(run("channels " + prefix + " --json").out)["eigenanalyses"], 2);
  EXPECT_NE(run("channels " + prefix).out.find("MBDyn eigenanalyses: 2 (mlce eigenanalysis " + prefix + ")"), std::string::npos);
}

TEST_F(MbdynCli, RowOutOfOrder) {
  auto v = lines_of(prefix + ".mov");
  std::swap(v[7], v[8]);
  std::ofstream o(prefix + ".mov", std::ios::trunc);
  for (const auto& l : v) o << l << "\n";
  o.close();
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.mov:8: expected the row of label 2");
}

TEST_F(MbdynCli, WrongColumnCount) {
  edit_line(".mov", 15, [](const std::string& l) { return l.substr(0, l.rfind(' ')); });
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.mov:15: label 2: 12 columns, expected 13");
}

TEST_F(MbdynCli, TextInANumericField) {
  // Line 50 is row 5 of block 6: joint 6 (axial rotation), 20 columns.
  edit_line(".jnt", 50, [](const std::string& l) { return l.substr(0, l.rfind(' ')) + " abc"; });
  expect_one_line_error(run("extract " + prefix + " --channel joint:6:20"), "run.jnt:50: column 20: 'abc' is not a number");
}

TEST_F(MbdynCli, NonFiniteValue) {
  edit_line(".mov", 8, [](const std::string& l) { return "       2 nan" + l.substr(l.find(' ', 9)); });
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.mov:8: column 2: 'nan': expected a finite number");
}

TEST_F(MbdynCli, UnknownLabels) {
  expect_one_line_error(run("extract " + prefix + " --channel node:99:x"), "run.log: channel 'node:99:x': no structural node 99");
  expect_one_line_error(run("extract " + prefix + " --channel joint:99:2"), "run.jnt: no rows of label 99");
  expect_one_line_error(run("extract " + kIso + ".nc --channel joint:99:2"),
                        "no joint 99; with output: 2 3 4 5 6 31 32 33 34");
}

// The real NetCDF file lists joints 1 and 21..24 and node 1 among its labels but writes no variable
// of theirs (output off in the run): a channel of one says so and names those that write output,
// and `mlce channels` marks them.
TEST_F(MbdynCli, NetcdfLabelsWithTheirOutputOff) {
  expect_one_line_error(run("extract " + kIso + ".nc --channel joint:21:2"),
                        "joint 21 writes no output in this file (listed in 'elem.joint', no 'elem.joint.21.f'); "
                        "with output: 2 3 4 5 6 31 32 33 34");
  for (const char* spec : {"node:1:x", "node:1:r1", "rel:1:13:z"})
    expect_one_line_error(run("extract " + kIso + ".nc --channel " + spec),
                          "structural node 1 writes no output in this file (listed in 'node.struct', no "
                          "'node.struct.1.X'); with output: 2 3 4 11 12 13 14");
  const auto listing = run("channels " + kIso + ".nc --json");
  ASSERT_EQ(listing.status, 0) << listing.err;
  const auto j = nlohmann::json::parse(listing.out);
  std::vector<long> off;
  for (const auto& e : j["entities"])
    if (e["type"] == "output off") off.push_back(e["label"].get<long>());
  EXPECT_EQ(off, (std::vector<long>{1, 21, 22, 23, 24}));
}

TEST_F(MbdynCli, ColumnBeyondTheRow) {
  expect_one_line_error(run("extract " + prefix + " --channel joint:33:20"), "label 33 has 15 columns, column 20 requested");
  expect_one_line_error(run("extract " + prefix + " --channel node:2:r4"), "writes 3 orientation numbers");
}

TEST_F(MbdynCli, BlockCountsDisagree) {
  auto v = lines_of(prefix + ".out");
  v.resize(v.size() - 5);
  std::ofstream o(prefix + ".out", std::ios::trunc);
  for (const auto& l : v) o << l << "\n";
  o.close();
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "inconsistent output set");
}

TEST_F(MbdynCli, EntityFileCutShortSaysWhatEveryFileHoldsAndThatPartIsRead) {
  const CliRun intact = run("extract " + prefix + " --channel node:2:x --channel joint:33:14");
  ASSERT_EQ(intact.status, 0) << intact.err;
  // The .mov of an interrupted copy: 100 of its 201 blocks (7 nodes each) and half a row.
  auto v = lines_of(prefix + ".mov");
  ASSERT_EQ(v.size(), 201u * 7);
  std::ofstream o(prefix + ".mov", std::ios::trunc);
  for (std::size_t k = 0; k < std::size_t{100} * 7; ++k) o << v[k] << "\n";
  o << v[700].substr(0, v[700].size() / 2);
  o.close();
  std::istringstream rows(intact.out);  // a header, then one row per block: row 100 is block 99's
  std::string row;
  for (int k = 0; k <= 100; ++k) std::getline(rows, row);
  const std::string t99 = row.substr(0, row.find(','));
  const CliRun refused = run("extract " + prefix + " --channel node:2:x --channel joint:33:14");
  expect_one_line_error(refused, "run.mov: 100 blocks (expected equal counts, or one fewer for an interrupted run); "
                                 "every file holds the first 100, to t = ");
  const double t_said = std::stod(refused.err.substr(refused.err.rfind("t = ") + 4));
  EXPECT_NEAR(t_said, std::stod(t99), 1e-9);
  EXPECT_NEAR(std::stod(refused.err.substr(refused.err.rfind("(--to ") + 6)), t_said, 0.0);  // the remedy, as typed
  const CliRun part = run("extract " + prefix + " --channel node:2:x --channel joint:33:14 --to " + t99);
  ASSERT_EQ(part.status, 0) << part.err;
  EXPECT_EQ(part.out, intact.out.substr(0, part.out.size()));
  EXPECT_EQ(std::count(part.out.begin(), part.out.end(), '\n'), 101);
}

TEST_F(MbdynCli, MissingFilesOfTheSet) {
  fs::remove(prefix + ".jnt");
  expect_one_line_error(run("extract " + prefix + " --channel joint:33:14"), "run.jnt: cannot open the file");
  fs::remove(prefix + ".log");
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.log: missing; MBDyn writes it beside");
}

TEST_F(MbdynCli, MalformedLogAndOut) {
  edit_line(".log", 3, [](const std::string&) { return std::string("structural node: 2 0.1 zero 0 euler123 0 0 0"); });
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.log:3: node 2: position is not a number");
  fs::copy_file(kIso + ".log", prefix + ".log", fs::copy_options::overwrite_existing);
  edit_line(".out", 10, [](const std::string&) { return std::string("Step 6 0.006 0.001"); });
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.out:10: expected 'Step");
  // A problem block with 'output: none' leaves the .out without Step lines: no time axis.
  std::ofstream(prefix + ".out", std::ios::trunc) << "# Step Time TStep NIter ResErr SolErr SolConv Out\n";
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"),
                        "run.out: no Step line, so the time of the 201 output blocks is unknown");
}

TEST_F(MbdynCli, EmptyEntityFile) {
  std::ofstream(prefix + ".mov", std::ios::trunc).close();
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.mov: no rows");
}

TEST_F(MbdynCli, TextFilesLeftEmptyByANetcdfOnlyRunPointToTheNc) {
  // 'output results: netcdf, no text': MBDyn still creates the entity files, empty.
  fs::copy_file(kIso + ".nc", prefix + ".nc");
  std::ofstream(prefix + ".mov", std::ios::trunc).close();
  const std::string nc = "; the run's NetCDF output is beside it: read " + prefix + ".nc";
  expect_one_line_error(run("estimate " + prefix + " --channel rel:13:4:z"),
                        "run.mov: no rows (empty file, as 'output results: netcdf, no text' leaves it)" + nc);
  expect_one_line_error(run("channels " + prefix), "run.mov: no rows (empty file");
  fs::remove(prefix + ".mov");
  expect_one_line_error(run("extract " + prefix + " --channel node:2:x"), "run.mov: cannot open the file (missing or unreadable)" + nc);
  const CliRun r = run("extract " + prefix + ".nc --channel rel:13:4:z");  // as the message says
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(MbdynCli, SetCompressedByGzipReadsAsItsTextAndABrokenCopyIsOneError) {
  // The set as an analyst archives it: every file through the gzip program, names PREFIX.ext.gz.
  const std::string channels = " --channel rel:13:4:z --channel joint:33:14 --channel node:2:x --csv ";
  const fs::path plain = dir / "plain.csv";
  ASSERT_EQ(run("extract " + prefix + channels + plain.string()).status, 0);
  ASSERT_GT(slurp(plain).size(), 201u * 40u);  // the 201 blocks' rows
  ASSERT_EQ(std::system(("gzip -n -q " + prefix + ".log " + prefix + ".out " + prefix + ".mov " + prefix + ".jnt").c_str()), 0);
  ASSERT_FALSE(fs::exists(prefix + ".mov"));
  for (const std::string& name : {prefix, prefix + ".mov.gz"}) {
    const fs::path gz = dir / "gz.csv";
    const CliRun r = run("extract " + name + channels + gz.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(slurp(gz), slurp(plain)) << name;
  }
  const CliRun listed = run("channels " + prefix);
  ASSERT_EQ(listed.status, 0) << listed.err;
  EXPECT_NE(listed.out.find("201 output blocks"), std::string::npos) << listed.out;
  // A copy cut short: one line naming the file, no partial CSV.
  const std::string gz = slurp(prefix + ".jnt.gz");
  std::ofstream(prefix + ".jnt.gz", std::ios::binary | std::ios::trunc) << gz.substr(0, gz.size() - 100);
  const std::string csv = (dir / "lag.csv").string();
  expect_one_line_error(run("extract " + prefix + " --channel joint:33:14 --csv " + csv),
                        "run.jnt.gz: the gzip data end early (the file was cut short in copying?)");
  EXPECT_FALSE(fs::exists(csv));
}

TEST_F(MbdynCli, UsageErrors) {
  expect_one_line_error(run("estimate " + prefix), "--channel", 2);
  expect_one_line_error(run("extract " + prefix + " --channel node:2:q"), "channel 'node:2:q': expected", 2);
  expect_one_line_error(run("estimate " + prefix + " --channel node:2:x --column 3"), "--channel", 2);
}

TEST_F(MbdynCli, CorruptNetcdf4FileThatMakesHdf5LoopIsOneErrorWithinTheTimeLimit) {
  // data/corrupt/netcdf4_hdf5_loops.nc (found by fuzz_netcdf) keeps libhdf5 busy for minutes; the
  // read runs first in a child process that is killed at the limit (MbdynNetcdf.CorruptNetcdf4Files...).
  const std::string nc = std::string(MLCE_DATA_DIR) + "/corrupt/netcdf4_hdf5_loops.nc";
  const fs::path csv = dir / "loops.csv";
  for (const std::string& args : {"channels " + nc, "extract " + nc + " --channel node:2:x --csv " + csv.string(),
                                  "estimate " + nc + " --channel node:2:x"})
    expect_one_line_error(run(args, "MLCE_NETCDF4_TIME_LIMIT=1"),
                          nc + ": reading it as a netCDF-4 (HDF5) file did not end within 1 s");
  EXPECT_FALSE(fs::exists(csv));
  expect_one_line_error(run("channels " + nc, "MLCE_NETCDF4_TIME_LIMIT=-2"),
                        "MLCE_NETCDF4_TIME_LIMIT: expected seconds > 0, got '-2'");
}

TEST_F(MbdynCli, NoPartialCsvOnError) {
  const fs::path csv = dir / "x.csv";
  expect_one_line_error(run("extract " + prefix + " --channel node:99:x --csv " + csv.string()), "no structural node 99");
  EXPECT_FALSE(fs::exists(csv));
}

TEST_F(MbdynCli, OutputsToDevicesAndThroughLinksLeaveTheNamesAsTheyWere) {
  // A rename of a finished temporary onto /dev/stdout or /dev/null made them regular files (the
  // tests run as root); a link to a file was replaced by a file.
  const auto kind = [](const char* p) { return fs::symlink_status(p).type(); };
  const auto stdout_kind = kind("/dev/stdout"), null_kind = kind("/dev/null");
  ASSERT_NE(stdout_kind, fs::file_type::regular);
  ASSERT_EQ(null_kind, fs::file_type::character);
  const std::string extract = "extract " + prefix + " --channel node:2:x";
  const fs::path plain = dir / "plain.csv";
  ASSERT_EQ(run(extract + " --csv " + plain.string()).status, 0);
  const CliRun to_stdout = run(extract + " --csv /dev/stdout");
  ASSERT_EQ(to_stdout.status, 0) << to_stdout.err;
  EXPECT_EQ(to_stdout.out, slurp(plain));  // the CSV itself, on the captured stdout
  EXPECT_EQ(kind("/dev/stdout"), stdout_kind);
  for (const char* option : {" --csv /dev/null", " --plot /dev/null"}) {
    const CliRun r = run(extract + option);
    EXPECT_EQ(r.status, 0) << option << ": " << r.err;
    EXPECT_EQ(kind("/dev/null"), fs::file_type::character) << option;
  }
  // A symbolic link keeps pointing where it did; the file it names gets the content.
  fs::create_directories(dir / "store");
  fs::create_symlink(dir / "store" / "lag.csv", dir / "lag.csv");
  ASSERT_EQ(run(extract + " --csv " + (dir / "lag.csv").string()).status, 0);
  EXPECT_TRUE(fs::is_symlink(dir / "lag.csv"));
  EXPECT_EQ(slurp(dir / "store" / "lag.csv"), slurp(plain));
  fs::create_symlink(dir / "store" / "lag.png", dir / "lag.png");
  ASSERT_EQ(run(extract + " --plot " + (dir / "lag.png").string()).status, 0);
  EXPECT_TRUE(fs::is_symlink(dir / "lag.png"));
  EXPECT_EQ(slurp(dir / "store" / "lag.png").substr(1, 3), "PNG");
  for (const auto& e : fs::directory_iterator(dir / "store"))  // no scratch file left beside them
    EXPECT_TRUE(e.path().filename() == "lag.csv" || e.path().filename() == "lag.png") << e.path();
  // A device that refuses the bytes (a full disk: /dev/full) is one error, not a silent success.
  if (fs::is_character_file("/dev/full")) expect_one_line_error(run(extract + " --csv /dev/full"), "/dev/full: write failed");
}

// ---- mlce simulate: ad-hoc runs written as an MBDyn text set, read back by the same reader -----

TEST_F(MbdynCli, SimulateToMbdynThenEstimateTheLagOfBlade3) {
  const std::string scenes = std::string(MLCE_DATA_DIR) + "/../scenes/";
  const std::string out = (dir / "adhoc").string();
  const CliRun sim = run("simulate " + scenes + "c3zero_242rpm.scene --t_end 20 --out " + out + " --quiet");
  ASSERT_EQ(sim.status, 0) << sim.err;
  for (const char* e : {".log", ".out", ".mov", ".scene"}) EXPECT_TRUE(fs::exists(out + e)) << e;
  const CliRun est = run("estimate " + out + " --channel rel:13:4:z --json --quiet");
  ASSERT_EQ(est.status, 0) << est.err;
  EXPECT_TRUE(std::isfinite(nlohmann::json::parse(est.out)["lambda"].get<double>()));
  // The lag from the bodies equals the model's own coordinate (columns format, column 4 = zeta3).
  ASSERT_EQ(run("simulate " + scenes + "c3zero_242rpm.scene --t_end 20 --format columns --out " + out + " --quiet").status, 0);
  const CliRun a = run("extract " + out + " --channel rel:13:4:z");
  const CliRun b = run("extract " + out + ".txt --channel col:4");
  std::istringstream sa(a.out), sb(b.out);
  std::string la, lb;
  std::getline(sa, la), std::getline(sb, lb);
  double worst = 0;
  while (std::getline(sa, la) && std::getline(sb, lb))
    worst = std::max(worst, std::abs(std::stod(la.substr(la.find(',') + 1)) - std::stod(lb.substr(lb.find(',') + 1))));
  EXPECT_LT(worst, 1e-9);
}

TEST_F(MbdynCli, EveryBundledSceneRuns) {
  for (const auto& entry : fs::directory_iterator(std::string(MLCE_DATA_DIR) + "/../scenes")) {
    const CliRun r = run("simulate " + entry.path().string() + " --t_end 2 --format columns --out " +
                         (dir / entry.path().stem()).string() + " --quiet");
    EXPECT_EQ(r.status, 0) << entry.path() << ": " << r.err;
  }
}

TEST_F(MbdynCli, InterruptedSimulationLeavesNoScratchFiles) {
  // Ctrl-C (SIGINT) or kill (SIGTERM) in the middle of a long run: the process ends by the signal,
  // as the shell expects, and the temporaries it was writing are gone with it.
  const std::string scene = std::string(MLCE_DATA_DIR) + "/../scenes/c3zero_242rpm.scene";
  for (const auto& [format, sig, scratch] : {std::tuple{"mbdyn", SIGINT, "long.mov.tmp"},
                                             std::tuple{"columns", SIGTERM, "long.txt.tmp-mlce"}}) {
    const fs::path out = dir / format;
    fs::create_directories(out);
    const std::string long_run = (out / "long").string();
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, STDOUT_FILENO), ::dup2(null, STDERR_FILENO);
      ::execl(MLCE_CLI, MLCE_CLI, "simulate", scene.c_str(), "--t_end", "100000", "--out", long_run.c_str(), "--format",
              format, "--quiet", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    bool writing = false;  // wait for the run to be writing its scratch file (30 s at most)
    for (int k = 0; k < 3000 && !writing; ++k) {
      writing = fs::exists(out / scratch);
      if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ::kill(pid, sig);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(writing) << format;
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << format << ": status " << status;
    EXPECT_TRUE(fs::is_empty(out)) << format << ": " << fs::directory_iterator(out)->path();
  }
}

TEST_F(MbdynCli, SimulateErrors) {
  expect_one_line_error(run("simulate --rpm fast --out " + (dir / "x").string()), "rpm = 'fast': expected a finite number");
  expect_one_line_error(run("simulate --model flapping --format mbdyn --out " + (dir / "x").string()),
                        "--format mbdyn needs a hammond scene");
  EXPECT_FALSE(fs::exists(dir / "x.log"));
  expect_one_line_error(run("simulate /nonexistent.scene --out " + (dir / "x").string()), "cannot open the scene file");
  // rpm in the wrong units: refused before it runs (it ran 19 s to the step budget at 1e300).
  expect_one_line_error(run("simulate --rpm 2.424e10 --out " + (dir / "x").string()), "needs at least");
  EXPECT_FALSE(fs::exists(dir / "x.log"));
  // Stopped where it stands (a negative lag spring: the lags pass 1000 rad by t = 0.5) after
  // thousands of samples were written as they came: neither format leaves a file behind.
  const std::string scene = std::string(MLCE_DATA_DIR) + "/../scenes/nonlinear_CL0.scene --k -1e6 --quiet --out ";
  expect_one_line_error(run("simulate " + scene + (dir / "stop").string()), "the steps have shrunk");
  expect_one_line_error(run("simulate " + scene + (dir / "stop").string() + " --format columns"), "the steps have shrunk");
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_NE(entry.path().filename().string().rfind("stop", 0), 0u) << entry.path() << " was left behind";
}

TEST_F(MbdynCli, AMovWithoutItsOutSaysWhatIsMissing) {
  // Only the .mov was copied: it reads as 13 plain columns, and a node channel says why not.
  const fs::path lone = dir / "lone";
  fs::create_directory(lone);
  fs::copy_file(prefix + ".mov", lone / "run.mov");
  const std::string mov = (lone / "run.mov").string();
  const std::string missing = (lone / "run.out").string() + " (whose Step lines give the time of every output block) is not beside it";
  expect_one_line_error(run("estimate " + mov + " --channel rel:13:4:z"), missing, 2);  // an option error
  expect_one_line_error(run("extract " + mov + " --channel node:2:x"), missing);
  const CliRun inventory = run("channels " + mov);
  EXPECT_EQ(inventory.status, 0) << inventory.err;
  EXPECT_NE(inventory.err.find(missing), std::string::npos) << inventory.err;
  // Its columns stay readable; beside its .out and .log the same file is an MBDyn set again.
  EXPECT_EQ(run("extract " + mov + " --channel col:2").status, 0);
  fs::copy_file(prefix + ".out", lone / "run.out");
  expect_one_line_error(run("extract " + mov + " --channel node:2:x"),
                        "run.log: missing; MBDyn writes it beside " + (lone / "run").string() + ".out");
  fs::copy_file(prefix + ".log", lone / "run.log");
  const CliRun set = run("extract " + mov + " --channel node:2:x");
  EXPECT_EQ(set.status, 0) << set.err;
  EXPECT_EQ(set.out, run("extract " + prefix + " --channel node:2:x").out);
}

TEST_F(MbdynCli, TruncatedSetReadsCompleteBlocksWithWarnings) {
  // Cut the .mov mid-line in its last block: exit 0, 200 of 201 blocks, warnings on stderr.
  const std::string mov = slurp(prefix + ".mov");
  std::ofstream(prefix + ".mov", std::ios::trunc) << mov.substr(0, mov.size() - 150);
  const CliRun r = run("extract " + prefix + " --channel node:2:x");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 201);  // header + 200 blocks
  EXPECT_NE(r.err.find("no end of line"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("last block is incomplete"), std::string::npos) << r.err;
}

TEST_F(MbdynCli, LateTimesPrintedWithSixDigitsGiveTheSameExponent) {
  // The 10 s failed-damper run as if it had started at t = 1000 s and MBDyn had printed its .out
  // by default (%g, 6 significant digits): blocks 5 ms apart print 1000, 1000, 1000.01, 1000.01, ...
  // The times are rebuilt from the Step indices and time steps; the exponent is the run's own.
  for (const char* e : {".log", ".mov"}) fs::copy_file(kC3 + e, dir / (std::string("late") + e));
  std::ofstream out(dir / "late.out");
  for (const auto& line : lines_of(kC3 + ".out")) {
    std::istringstream f(line);
    std::string word, step;
    double time = 0, tstep = 0;
    if (!(f >> word >> step >> time >> tstep) || word != "Step") {
      out << line << "\n";
      continue;
    }
    std::string rest;
    std::getline(f, rest);
    char head[96];
    std::snprintf(head, sizeof head, "Step %s %g %g", step.c_str(), 1000.0 + time, tstep);
    out << head << rest << "\n";
  }
  out.close();
  ASSERT_NE(slurp(dir / "late.out").find("Step 10 1000.01 0.001"), std::string::npos);
  const std::string late = (dir / "late").string();
  const CliRun shifted = run("estimate " + late + " --channel rel:13:4:z --json");
  ASSERT_EQ(shifted.status, 0) << shifted.err;
  const CliRun original = run("estimate " + kC3 + " --channel rel:13:4:z --json --quiet");
  ASSERT_EQ(original.status, 0) << original.err;
  const auto a = nlohmann::json::parse(shifted.out), b = nlohmann::json::parse(original.out);
  ASSERT_FALSE(a["warnings"].empty());
  EXPECT_NE(a["warnings"][0].get<std::string>().find("late.out: times printed with 6 significant digits, too few"), std::string::npos);
  EXPECT_NEAR(a["dt"].get<double>(), 0.005, 1e-12);
  EXPECT_NEAR(a["lambda"].get<double>(), b["lambda"].get<double>(), 1e-9 * std::abs(b["lambda"].get<double>()));
  const CliRun t = run("extract " + late + " --channel node:2:x");
  ASSERT_EQ(t.status, 0) << t.err;
  EXPECT_NE(t.err.find("times printed with 6 significant digits"), std::string::npos) << t.err;
  EXPECT_NE(t.out.find("\n1000.005,"), std::string::npos) << t.out.substr(0, 80);
}

TEST_F(MbdynCli, RunThatDivergesAfterTheWindowIsAnalysedUpToTo) {
  // The 10 s failed-damper run as if it had blown up at t = 6 s: every .mov field nan from output
  // block 1200 on. With --to before it, the exponent is exactly that of the intact run on the same
  // window; without, one line names the row and the last finite time.
  fs::copy_file(kC3 + ".log", dir / "blown.log");
  fs::copy_file(kC3 + ".out", dir / "blown.out");
  std::ofstream mov(dir / "blown.mov");
  std::size_t n = 0;
  for (const auto& line : lines_of(kC3 + ".mov")) {
    if (n++ < std::size_t{1200} * 7) {
      mov << line << "\n";
      continue;
    }
    std::istringstream f(line);
    std::string label, field, row;
    f >> label;
    row = label;
    while (f >> field) row += " nan";
    mov << row << "\n";
  }
  mov.close();
  const std::string blown = (dir / "blown").string();
  const CliRun refused = run("estimate " + blown + " --channel rel:13:4:z");
  // Line 8403: node 4, the first row of block 1200 the channel reads.
  expect_one_line_error(refused, "blown.mov:8403: column 5: 'nan': expected a finite number (did the run diverge? This "
                                 "block is at t = 6; the 1200 before it, to t = 5.995, are finite)");
  const CliRun cut = run("estimate " + blown + " --channel rel:13:4:z --to 5.995 --json --quiet");
  ASSERT_EQ(cut.status, 0) << cut.err;
  const CliRun intact = run("estimate " + kC3 + " --channel rel:13:4:z --to 5.995 --json --quiet");
  ASSERT_EQ(intact.status, 0) << intact.err;
  const auto a = nlohmann::json::parse(cut.out), b = nlohmann::json::parse(intact.out);
  EXPECT_EQ(a["n_points"], b["n_points"]);
  EXPECT_EQ(a["lambda"].get<double>(), b["lambda"].get<double>());
  expect_one_line_error(run("estimate " + blown + " --channel rel:13:4:z --to -1"), "blown.out: no output step at t <= -1");
  // extract --to writes the finite part: the 1200 blocks to t = 5.995, as the intact run prints them.
  const CliRun part = run("extract " + blown + " --channel rel:13:4:z --to 5.995");
  ASSERT_EQ(part.status, 0) << part.err;
  const CliRun whole = run("extract " + kC3 + " --channel rel:13:4:z");
  ASSERT_EQ(whole.status, 0) << whole.err;
  EXPECT_EQ(std::count(part.out.begin(), part.out.end(), '\n'), 1201);  // header + 1200 blocks
  EXPECT_EQ(whole.out.substr(0, part.out.size()), part.out);
  EXPECT_NE(part.out.find("\n5.995"), std::string::npos);  // printed as 5.995000000000337
  expect_one_line_error(run("extract " + blown + " --channel rel:13:4:z"), "blown.mov:8403: column 5: 'nan'");
  // compare --to: the diverged run against the intact one, identical up to the blow-up.
  const CliRun same = run("compare " + blown + " " + kC3 + " --channel rel:13:4:z --to 5.995 --json");
  ASSERT_EQ(same.status, 0) << same.err;
  const auto c = nlohmann::json::parse(same.out)["channels"][0];
  EXPECT_EQ(c["points"].get<int>(), 1200);  // block 1199, at t = 5.995000000000337, is in the window
  EXPECT_EQ(c["max_abs_difference"].get<double>(), 0.0);
  // A nan window end would silently take the whole run: refused as an option error.
  expect_one_line_error(run("compare " + blown + " " + kC3 + " --channel rel:13:4:z --to nan"),
                        "--to 'nan': expected a time", 2);
  expect_one_line_error(run("extract " + blown + " --channel rel:13:4:z --to nan"), "--to: expected a time", 2);
}

TEST_F(MbdynCli, NetcdfWithoutLogMeasuresFromTheFirstRecordAndSaysSo) {
  fs::copy_file(kIso + ".nc", dir / "alone.nc");
  const CliRun r = run("extract " + (dir / "alone.nc").string() + " --channel rel:13:4:z --channel joint:33:14");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("angle measured from the first record"), std::string::npos) << r.err;
  std::istringstream s(r.out);
  std::string line;
  std::getline(s, line);
  double worst = 0;
  while (std::getline(s, line)) {  // the run starts at zero lag: same angle as the damper's
    const auto a = line.find(','), b = line.find(',', a + 1);
    worst = std::max(worst, std::abs(std::stod(line.substr(a + 1, b - a - 1)) - std::stod(line.substr(b + 1))));
  }
  EXPECT_LT(worst, 1e-9);
}

TEST_F(MbdynCli, EveryCommandHasHelp) {
  for (const char* c : {"estimate", "ami", "fnn", "modes", "simulate", "channels", "extract"}) {
    const CliRun r = run(std::string(c) + " --help");
    EXPECT_EQ(r.status, 0) << c;
    EXPECT_EQ(r.out.rfind(std::string("mlce ") + c, 0), 0u) << r.out;
  }
}

TEST_F(MbdynCli, SimulateRefusesAnOutputTooLargeToHold) {
  expect_one_line_error(run("simulate --t_end 1e6 --dt_out 1e-6 --out " + (dir / "x").string()),
                        "output samples: expected at most 5e7");
}

// mlce compare: the ad-hoc model (mlce simulate, rk45 rtol 1e-8) against the real MBDyn runs
// (multistep rho 0.6, fixed 1 ms). Tolerances: over 10 s of the growing blade-3 oscillation the
// two integrators' phase errors accumulate to a few 1e-3 rad at 0.55 rad amplitude; the ranges
// (the limit-cycle measure) agree to 0.1 %.
TEST_F(MbdynCli, CompareLeavesAChannelOfRoundingNoiseOutOfTheWindowAndTheVerdict) {
  // node:2:y (the airframe's x-part, free in x only) holds MBDyn's rounding, whose RMS wanders: its
  // "transient" ended at 6.4 s and moved every channel's window there (node:2:x then read 3.09 1/s
  // on 3.6 s of growth), and its "exponent" (34 1/s, the embedding window's) was judged against the
  // other run's. It waits for nothing now and is judged against nothing.
  const CliRun both = run("compare " + kC3 + " " + kC3 + " --channel node:2:y --channel node:2:x --mlce --json");
  ASSERT_EQ(both.status, 0) << both.err;
  const CliRun alone = run("compare " + kC3 + " " + kC3 + " --channel node:2:x --mlce --json");
  ASSERT_EQ(alone.status, 0) << alone.err;
  const auto jb = nlohmann::json::parse(both.out), ja = nlohmann::json::parse(alone.out);
  const auto& noise = jb["channels"][0]["mlce"];
  const auto& hub = jb["channels"][1]["mlce"];
  EXPECT_EQ(hub["window"], ja["channels"][0]["mlce"]["window"]);
  EXPECT_EQ(hub["a"]["lambda"], ja["channels"][0]["mlce"]["a"]["lambda"]);
  EXPECT_NE(hub["window_rule"].get<std::string>().find("not waited for: node:2:y"), std::string::npos) << hub["window_rule"];
  EXPECT_TRUE(noise["agreement"].is_null()) << noise["agreement"];
  EXPECT_EQ(noise["a"]["reading"]["stability"], "undetermined");
  EXPECT_TRUE(hub["agreement"]["agree"].get<bool>());
  bool said = false;
  for (const auto& w : jb["warnings"])
    said = said || w.get<std::string>().find("node:2:y: the two exponents are not compared") != std::string::npos;
  EXPECT_TRUE(said) << jb["warnings"].dump();
}

TEST_F(MbdynCli, CompareAdHocWithMbdynBladeLagsAndHub) {
  const std::string adhoc = (dir / "adhoc").string();
  ASSERT_EQ(run("simulate " + std::string(MLCE_DATA_DIR) + "/../scenes/c3zero_242rpm.scene --t_end 10 --out " + adhoc).status, 0);
  const std::string png = (dir / "cmp.png").string();
  const CliRun r = run("compare " + adhoc + " " + kC3 +
                       " --channel rel:11:4:z --channel rel:12:4:z --channel rel:13:4:z --channel rel:14:4:z"
                       " --channel node:2:x --channel node:3:y --json --plot " + png);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["channels"].size(), 6u);
  for (const auto& c : j["channels"]) {
    const std::string name = c["channel"];
    const bool blade = name.rfind("rel:", 0) == 0;
    EXPECT_EQ(c["points"].get<int>(), 2001) << name;  // every block: the runs end within rounding of t = 10
    EXPECT_LT(c["max_abs_difference"].get<double>(), blade ? 1e-2 : 5e-4) << name;
    EXPECT_LT(c["range_relative_difference"].get<double>(), 2e-3) << name;
  }
  EXPECT_TRUE(fs::exists(png));
  expect_one_line_error(run("compare " + adhoc + " --channel rel:13:4:z"), "give two runs", 2);
  // A channel one of the runs cannot provide (ad-hoc sets have no .jnt): named, exit 1.
  expect_one_line_error(run("compare " + kIso + " " + adhoc + " --channel joint:33:14"), "adhoc.jnt: cannot open the file", 1);
  // An MLCE window too short for an estimate (9.85..10 s): refused, naming the channel and the run
  // (the estimator's message alone did not say which of the two runs it came from).
  expect_one_line_error(run("compare " + kC3 + " " + kC3 + " --channel rel:13:4:z --mlce --from 9.85"),
                        "rel:13:4:z: MLCE: " + kC3 + ": series too short", 1);
}

// mlce modes on the real MBDyn runs against the Jacobian-based references of the same model (mlce eigen
// for the isotropic rotor, mlce floquet for blade 3 inoperative): the least damped mode read from the
// time history is the linearisation's largest real part.
TEST_F(MbdynCli, ModesOfTheRealRunsAreTheLinearisationsLeastDampedMode) {
  const double iso = linearisation_exponent("eigen", "isotropic_200rpm.scene");
  const double c3 = linearisation_exponent("floquet", "c3zero_242rpm.scene");
  struct Case {
    std::string args;
    double truth, tolerance;
  };
  const std::string iso5 = std::string(MLCE_DATA_DIR) + "/mbdyn/iso_200rpm_5s/iso_200rpm";
  const std::string lag20 = std::string(MLCE_DATA_DIR) + "/mbdyn/iso_200rpm_rel11_20s.csv --time-column 1 --column 2";
  for (const Case& c : {Case{iso5 + " --channel node:2:x", iso, 1e-4}, Case{lag20, iso, 0.01},
                        Case{kC3 + " --channel rel:11:4:z", c3, 0.01}, Case{kC3 + " --channel rel:13:4:z", c3, 0.01},
                        Case{kC3 + " --channel node:2:x", c3, 0.01}}) {
    const nlohmann::json j = json_of("modes " + c.args);
    std::printf("%s: lambda %.7g, interval %s, the linearisation's %.7g; %s\n", c.args.c_str(), j["lambda"].get<double>(),
                j["ci95"].dump().c_str(), c.truth, j["reading"].get<std::string>().c_str());
    EXPECT_NEAR(j["lambda"].get<double>() / c.truth, 1.0, c.tolerance) << c.args;
    ASSERT_TRUE(j["ci95"].is_array()) << c.args;
    EXPECT_LT(j["ci95"][0].get<double>(), j["lambda"].get<double>()) << c.args;
    EXPECT_GT(j["ci95"][1].get<double>(), j["lambda"].get<double>()) << c.args;
    // The isotropic hub is a sum of the linearisation's modes to the solver's error: lambda within 1e-5 of the
    // eigenvalue (-1.182834 against -1.182838), and its noise interval (step 8 of modes.hpp) as narrow (3e-6
    // wide). The interval need not hold the eigenvalue: MBDyn's integrator and the ad-hoc linearisation differ
    // by some 1e-6 (a misfit, not noise: the halves read -1.18298 and -1.182837), and the rotating lags' and
    // the growing run's halves differ by more than their noise moves them too.
    if (c.tolerance < 1e-3) {
      EXPECT_NEAR(j["lambda"].get<double>() / c.truth, 1.0, 1e-5) << c.args;
      EXPECT_LT(j["ci95"][1].get<double>() - j["ci95"][0].get<double>(), 1e-5 * std::abs(c.truth)) << c.args;
    }
    EXPECT_TRUE(j["linear"].get<bool>()) << c.args;
    EXPECT_EQ(j["reading"].get<std::string>().rfind(c.truth < 0 ? "stable" : "unstable", 0), 0U) << j["reading"];
  }
}

// Hammond with nonlinear lag dampers, released from x_h = 0.1 m: a large, fast, nonlinear start, then the
// decay of the linearisation's least damped mode over seven decades. The hub's modes give that mode's
// rate (mlce eigen of the scene), where the run's strongest modes decay 7-10 times faster.
TEST_F(MbdynCli, ModesOfANonlinearDamperRunEndWithTheLinearisationsRate) {
  const std::string out = (dir / "nonlinear").string();
  ASSERT_EQ(run("simulate " + std::string(MLCE_DATA_DIR) + "/../scenes/nonlinear_CLnominal.scene --out " + out + " --quiet").status, 0);
  const double truth = linearisation_exponent("eigen", "nonlinear_CLnominal.scene");
  for (const char* channel : {"node:2:x", "rel:11:4:z"}) {
    const nlohmann::json j = json_of("modes " + out + " --channel " + channel);
    std::printf("%s: lambda %.7g (halves %s and %s), the linearisation's %.7g\n", channel, j["lambda"].get<double>(),
                j["first_half_lambda"].dump().c_str(), j["second_half_lambda"].dump().c_str(), truth);
    EXPECT_NEAR(j["lambda"].get<double>() / truth, 1.0, 0.01) << channel;
    EXPECT_NEAR(j["second_half_lambda"].get<double>() / truth, 1.0, 0.002) << channel;
    EXPECT_EQ(j["reading"].get<std::string>().rfind("stable, decaying modes", 0), 0U) << j["reading"];
  }
}

TEST_F(MbdynCli, ModesTextCsvPlotAndErrors) {
  const fs::path csv = dir / "modes.csv", png = dir / "modes.png";
  const CliRun r = run("modes " + prefix + " --channel node:2:x --csv " + csv.string() + " --plot " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("<- lambda"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reading         stable, decaying modes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("interval        ["), std::string::npos) << r.out;
  EXPECT_EQ(lines_of(csv).at(0), "sigma,frequency,damping_ratio,share,peak_share,offset");
  EXPECT_GT(fs::file_size(png), 1000U);
  // The hub's y holds rounding noise of 1e-24 m in this run: no mode stands above it, and nothing is read.
  const CliRun noise = run("modes " + prefix + " --channel node:2:y --json");
  ASSERT_EQ(noise.status, 0) << noise.err;
  EXPECT_EQ(nlohmann::json::parse(noise.out)["reading"].get<std::string>().rfind("undetermined", 0), 0U) << noise.out;
  // A constant record: one error naming it, and no file left behind.
  const fs::path none = dir / "none.csv";
  std::string constant;
  for (int i = 0; i < 100; ++i) constant += "1.5\n";
  write("constant.txt", constant);
  expect_one_line_error(run("modes " + (dir / "constant.txt").string() + " --dt 0.1 --csv " + none.string()), "is constant");
  EXPECT_FALSE(fs::exists(none));
  expect_one_line_error(run("modes " + prefix + " --channel node:2:x --order 0"), "--order '0': expected auto or 1 .. 40", 2);
  expect_one_line_error(run("modes " + prefix + " --channel node:2:x --order many"), "--order 'many'", 2);
  expect_one_line_error(run("modes " + prefix + " --channel node:2:x --replicates 1"),
                        "--replicates 1: expected 0 (no interval) or 2 .. 100000", 2);
  expect_one_line_error(run("modes " + prefix + " --channel node:2:x --replicates -1"),
                        "--replicates -1: expected 0 (no interval) or 2 .. 100000", 2);
  const CliRun plain = run("modes " + prefix + " --channel node:2:x --replicates 0 --json");
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_TRUE(nlohmann::json::parse(plain.out)["ci95"].is_null()) << plain.out;
  expect_one_line_error(run("modes " + prefix + " --channel node:2:x --to 0.02"), "a modal fit needs at least 12");
}

// The ad-hoc isotropic rotor over 20 s decays to 1e-10 of its start, where the integrator's error is all
// that is left: analysed up to that floor, each coordinate reads the linearisation's least damped mode
// (an early build of mlce modes that fitted the floor too read the airframe's y at +0.915 1/s).
TEST_F(MbdynCli, ModesOfADecayIntoItsSolverFloorAreReadUpToIt) {
  const std::string out = (dir / "iso").string();
  ASSERT_EQ(run("simulate " + std::string(MLCE_DATA_DIR) + "/../scenes/isotropic_200rpm.scene --format columns --out " + out +
                " --quiet").status, 0);
  const double truth = linearisation_exponent("eigen", "isotropic_200rpm.scene");
  for (const char* column : {"2", "6", "7"}) {  // zeta1, x_h, y_h
    const nlohmann::json j = json_of("modes " + out + ".txt --time-column 1 --column " + column);
    std::printf("column %s: lambda %.7g, floor from sample %zu; the linearisation's %.7g\n", column, j["lambda"].get<double>(),
                j["floor_start"].get<std::size_t>(), truth);
    EXPECT_NEAR(j["lambda"].get<double>() / truth, 1.0, 1e-4) << column;
    EXPECT_GT(j["floor_start"].get<std::size_t>(), 2000U) << column;
    EXPECT_NE(j["warnings"].dump().find("decays into a rounding/tolerance floor"), std::string::npos) << j["warnings"];
  }
}

// A range in a channel spec is the channels named one by one: the four blades' lags of the 5 s isotropic
// run as rel:11..14:4:z, estimated each, give what rel:11:4:z .. rel:14:4:z give; a reversed range is a
// usage error naming it, before any file is read.
TEST_F(MbdynCli, AChannelRangeIsTheChannelsNamedOneByOne) {
  const std::string set = std::string(MLCE_DATA_DIR) + "/mbdyn/iso_200rpm_5s/iso_200rpm";
  const auto ranged = json_of("estimate " + set + " --channel rel:11..14:4:z --each --quiet");
  const auto named = json_of("estimate " + set +
                             " --channel rel:11:4:z --channel rel:12:4:z --channel rel:13:4:z --channel rel:14:4:z --each --quiet");
  ASSERT_EQ(ranged["channels"].size(), 4U);
  EXPECT_EQ(ranged["channels"], named["channels"]);
  EXPECT_EQ(ranged["channels"][2]["channel"], "rel:13:4:z");
  const auto extracted = run("extract " + set + " --channel node:11..12:y --to 0.01");
  ASSERT_EQ(extracted.status, 0) << extracted.err;
  EXPECT_EQ(extracted.out.substr(0, extracted.out.find('\n')), "time,node:11:y,node:12:y");
  expect_one_line_error(run("estimate " + set + " --channel rel:14..11:4:z"), "range 14..11: expected FIRST <= LAST", 2);
}
