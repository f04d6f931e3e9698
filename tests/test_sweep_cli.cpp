// mlce sweep: the grid, determinism whatever the job count, resuming after a stop or a kill (bit
// for bit), and the swept exponents against independent references.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_harness.hpp"

namespace fs = std::filesystem;
using mlce::testing::CliRun;
using mlce::testing::expect_one_line_error;
using mlce::testing::slurp;

namespace {

const std::string kScenes = std::string(MLCE_DATA_DIR) + "/../scenes/";
const std::string kC3 = kScenes + "c3zero_242rpm.scene";
const std::string kIso = kScenes + "isotropic_200rpm.scene";

class SweepCli : public mlce::testing::CliFixture {
 protected:
  nlohmann::json sweep_json(const std::string& args) {
    const CliRun r = run("sweep " + args + " --json --quiet");
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return r.status == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
  }
  std::string out(const std::string& name) { return (dir / name).string(); }
};

}  // namespace

TEST_F(SweepCli, FloquetBandOfTheFailedDamperRotor) {
  // Blade 3 inoperative: unstable from about 211 to 305 rpm (the shared MBDyn runs' README),
  // stable outside.
  const auto j = sweep_json(kC3 + " --param rpm=200:320:10 --method floquet --out " + out("f.csv"));
  ASSERT_EQ(j["rows"].size(), 13u);
  for (const auto& row : j["rows"]) {
    const double rpm = row[0], lambda1 = row[1];
    if (rpm >= 220 && rpm <= 300) {
      EXPECT_GT(lambda1, 0.0) << rpm;
    } else {
      EXPECT_LT(lambda1, 0.0) << rpm;
    }
  }
  // A point of the sweep is the same computation as the single command.
  const CliRun single = run("floquet " + kC3 + " --rpm 250 --json");
  ASSERT_EQ(single.status, 0) << single.err;
  EXPECT_NEAR(j["rows"][5][1].get<double>(), nlohmann::json::parse(single.out)["exponents"][0].get<double>(), 1e-9);
}

TEST_F(SweepCli, EigenSweepKeepsTheCollectivePairAtMinusCOver2Ib) {
  const auto j = sweep_json(kIso + " --param rpm=100:300:50 --param cy=25539.35:51078.7:25539.35 --method eigen --out " +
                            out("e.csv") + " --plot " + out("e.png"));
  ASSERT_EQ(j["rows"].size(), 10u);
  const double pair = -4067.5 / (2 * 1084.7);  // collective and reactionless: -c / (2 I_b)
  for (const auto& row : j["rows"]) {
    int hits = 0;
    for (std::size_t c = 2; c < row.size(); ++c)
      if (row[c].is_number() && std::abs(row[c].get<double>() - pair) < 1e-6) ++hits;
    EXPECT_GE(hits, 4) << row.dump();
  }
  EXPECT_TRUE(fs::exists(out("e.png")));  // 2-D: colour map
}

TEST_F(SweepCli, RosensteinFollowsFloquetWhereStableAndIsZeroOnTheLimitCycle) {
  // Paper 001 Figs. 4-5: below the band the MLCE is the Floquet exponent; inside it the motion
  // settles on a limit cycle and the MLCE is ~0 (while the Floquet exponent of x = 0 is positive).
  const auto r = sweep_json(kC3 + " --param rpm=170:250:40 --method rosenstein --out " + out("r.csv") + " --plot " +
                            out("r.png"));
  const auto f = sweep_json(kC3 + " --param rpm=170:250:40 --method floquet --out " + out("f.csv"));
  ASSERT_EQ(r["rows"].size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const double rpm = r["rows"][k][0], mlce = r["rows"][k][1], floquet = f["rows"][k][1];
    std::printf("rpm %.0f: MLCE %.5f (%s), Floquet lambda1 %.5f 1/s\n", rpm, mlce,
                r["rows"][k][4].get<std::string>().c_str(), floquet);
    if (rpm < 200) {
      EXPECT_NEAR(mlce, floquet, 0.1 * std::abs(floquet)) << rpm;
    } else {
      EXPECT_LT(std::abs(mlce), 0.05) << rpm;
    }
    // The stability column (reading.hpp) says which: stable at 170 rpm (Floquet -0.181 1/s);
    // neutral at 210 rpm, at the band's edge (Floquet -0.0038 1/s, 0.3 % per mean period of 0.84 s:
    // inside the neutral band of 1 %), and at 250 rpm on the limit cycle (Floquet +0.32 1/s: the
    // linearisation is unstable, the nonlinear motion bounded).
    EXPECT_EQ(r["rows"][k][7], rpm < 200 ? "stable" : "neutral") << rpm;
  }
  EXPECT_TRUE(fs::exists(out("r.png")));
}

// The modes of each point's simulated run, from its time history alone, against the Floquet exponent of the
// same scene (computed from the equations): within 0.5 % below, inside and above the ground-resonance band. Inside
// it the growth saturates into a limit cycle and is read over its leading part (modes.hpp step 9).
TEST_F(SweepCli, ModesOfTheRunsAreTheFloquetExponent) {
  const auto m = sweep_json(kC3 + " --param rpm=175:275:50 --method modes --preset fast --out " + out("m.csv") + " --plot " +
                            out("m.png"));
  const auto f = sweep_json(kC3 + " --param rpm=175:275:50 --method floquet --out " + out("mf.csv"));
  ASSERT_EQ(m["rows"].size(), 3u);
  const auto& columns = m["columns"];
  ASSERT_EQ(columns[1], "lambda");
  ASSERT_EQ(columns[7], "stability");
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& row = m["rows"][k];
    const double rpm = row[0], modes = row[1], floquet = f["rows"][k][1];
    std::printf("rpm %.0f: modes %.6f [%s, %s] to t = %s (%s), Floquet %.6f 1/s\n", rpm, modes, row[2].dump().c_str(),
                row[3].dump().c_str(), row[6].dump().c_str(), row[8].get<std::string>().c_str(), floquet);
    EXPECT_NEAR(modes / floquet, 1.0, 0.005) << rpm;
    EXPECT_EQ(row[7], floquet < 0 ? "stable" : "unstable") << rpm;
    EXPECT_LT(row[2].get<double>(), modes);
    EXPECT_GT(row[3].get<double>(), modes);
  }
  EXPECT_LT(m["rows"][2][6].get<double>(), 30.0);  // 275 rpm: the growth saturates, read before it
  EXPECT_TRUE(fs::exists(out("m.png")));
}

TEST_F(SweepCli, AWindowOfTheFloorAfterADecayReadsStable) {
  // The isotropic rotor is stable at every speed (its multiblade eigenvalues, `--method eigen`); from
  // x_h = 0.1 m its lags decay to the integrator's floor, ~1e-11, well before 30 s. A sweep analysed
  // from 30 s sees only that floor, whose solver residue "diverges" at +0.7..+1.5 1/s: each point was
  // read "unstable" before the window was judged against the run it was cut from, as `mlce estimate
  // --from` judges it.
  const auto e = sweep_json(kIso + " --param rpm=150:300:50 --method eigen --out " + out("e.csv"));
  const auto r = sweep_json(kIso + " --t_end 60 --from 30 --param rpm=150:300:50 --method rosenstein --out " +
                            out("floor.csv") + " --plot " + out("floor.png"));
  ASSERT_EQ(r["rows"].size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& row = r["rows"][k];
    std::printf("rpm %.0f: eigen lambda1 %.4f 1/s; window 30..: lambda %.4f 1/s, amplitude %.3g: %s\n",
                row[0].get<double>(), e["rows"][k][1].get<double>(), row[1].get<double>(), row[6].get<double>(),
                row[7].get<std::string>().c_str());
    ASSERT_LT(e["rows"][k][1].get<double>(), 0.0);
    EXPECT_LT(row[6].get<double>(), 1e-9);  // the floor
    EXPECT_EQ(row[7], "stable");
    EXPECT_EQ(row[8], "decays to rest");
    EXPECT_EQ(row[9], 1) << "in_decay_floor: lambda is the residue, and the plot does not draw it";
    EXPECT_NE(row.back().get<std::string>().find("floor of a decay that ended before it"), std::string::npos) << row.dump();
  }
  EXPECT_GT(fs::file_size(out("floor.png")), 1000u);  // only the floor's marks: no lambda drawn
  // Two parameters: the colour map, the floor's points at the stable end and circled.
  sweep_json(kIso + " --t_end 60 --from 30 --param rpm=150:200:50 --param cx=40000:60000:20000 --method rosenstein --out " +
             out("floor2.csv") + " --plot " + out("floor2.png"));
  EXPECT_GT(fs::file_size(out("floor2.png")), 1000u);
  // From 10 s the window holds the end of the decay and then the floor: cut at the floor (judged
  // against the run), it reads the least damped eigenvalue, where the floor analysed with the decay
  // read -0.07..+0.02 1/s, neutral.
  const auto d = sweep_json(kIso + " --t_end 30 --from 10 --param rpm=150:300:50 --method rosenstein --out " +
                            out("tail.csv"));
  ASSERT_EQ(d["rows"].size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& row = d["rows"][k];
    const double eigen = e["rows"][k][1];
    std::printf("rpm %.0f: window 10..: lambda %.4f 1/s (%s)\n", row[0].get<double>(), row[1].get<double>(),
                row[7].get<std::string>().c_str());
    EXPECT_NEAR(row[1].get<double>(), eigen, 0.05 * std::abs(eigen)) << row.dump();
    EXPECT_EQ(row[7], "stable");
    EXPECT_EQ(row[9], 0) << "the decay is measured";
  }
}

TEST_F(SweepCli, RosensteinIsZeroOnTheLimitCycleNearTheBandEdge) {
  // Paper 001 Fig. 12 at 300 rpm (the band ends at 307 rpm), lag rate 1 rad/s: the rotor still
  // settles on a limit cycle, whose lambda_1 is 0. Its curve falls (neighbours converging onto the
  // cycle at a contracting exponent) and then stays level; the fall read -0.094 1/s until the fit
  // asked whether the signal itself decays (FitOptions::signal_rate).
  const auto r = sweep_json(kC3 + " --x0 0 --zetadot0 0,0,1,0 --param rpm=300:300:10 --method rosenstein --out " +
                            out("edge.csv"));
  ASSERT_EQ(r["rows"].size(), 1u);
  const double mlce = r["rows"][0][1];
  std::printf("300 rpm, lag rate 1: MLCE %.5f (%s)\n", mlce, r["rows"][0][4].get<std::string>().c_str());
  EXPECT_LT(std::abs(mlce), 0.03);
  EXPECT_EQ(r["rows"][0][4], "bounded divergence");
}

TEST_F(SweepCli, FloquetSensitivityColumnsMatchCentralDifferencesOfTheSweep) {
  // Flapping blade (paper 000 Fig. 2): d lambda / d mu from the sweep's analytic sensitivity
  // against central differences of the swept exponents themselves (step 1e-3).
  const std::string flap = kScenes + "flapping_mu015.scene";
  const auto j = sweep_json(flap + " --param mu=1.199:1.201:0.001 --method floquet --sensitivity mu --out " + out("s.csv"));
  ASSERT_EQ(j["rows"].size(), 3u);
  ASSERT_EQ(j["columns"][3], "dlambda_1/dmu");
  const double fd = (j["rows"][2][1].get<double>() - j["rows"][0][1].get<double>()) / 0.002;
  EXPECT_NEAR(j["rows"][1][3].get<double>(), fd, 0.02 * std::abs(fd));
  expect_one_line_error(run("sweep " + flap + " --param mu=1 --method eigen --sensitivity mu --out " + out("t.csv")),
                        "--sensitivity", 2);
}

TEST_F(SweepCli, InitialStateIsASweepAxis) {
  // init:STATE sets the initial state; Floquet about x = 0 does not depend on it, the simulated
  // amplitude does.
  const auto j = sweep_json(kC3 + " --x0 0 --param init:zetadot3=0:1:1 --method floquet --out " + out("i.csv"));
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["rows"][0][1], j["rows"][1][1]);
  expect_one_line_error(run("sweep " + kC3 + " --param init:zeta9=0:1:1 --out " + out("u.csv")), "'zeta9' is not a state", 2);
}

TEST_F(SweepCli, JobCountDoesNotChangeTheResult) {
  const std::string args = kIso + " --t_end 10 --param rpm=150:250:25 --method rosenstein --quiet";
  ASSERT_EQ(run("sweep " + args + " --jobs 1 --out " + out("one.csv")).status, 0);
  ASSERT_EQ(run("sweep " + args + " --jobs 2 --out " + out("two.csv")).status, 0);
  EXPECT_EQ(slurp(out("one.csv")), slurp(out("two.csv")));
}

TEST_F(SweepCli, StoppedOrKilledSweepResumesToTheSameBytes) {
  const std::string args = kIso + " --t_end 10 --param rpm=120:300:30 --method rosenstein --jobs 2";
  ASSERT_EQ(run("sweep " + args + " --out " + out("whole.csv")).status, 0);
  // Stopped in chunks: exit 3, no CSV yet, the journal holds the finished points.
  const CliRun part = run("sweep " + args + " --out " + out("chunk.csv") + " --max-points 3");
  EXPECT_EQ(part.status, 3) << part.err;
  EXPECT_FALSE(fs::exists(out("chunk.csv")));
  ASSERT_TRUE(fs::exists(out("chunk.csv.partial")));
  std::ofstream(out("chunk.csv.partial"), std::ios::app) << "5,-0.9";  // a line torn by a kill
  const auto resumed = sweep_json(args + " --out " + out("chunk.csv"));
  EXPECT_EQ(resumed["resumed"], 3);
  EXPECT_EQ(resumed["computed"], 4);
  EXPECT_EQ(slurp(out("chunk.csv")), slurp(out("whole.csv")));
  EXPECT_FALSE(fs::exists(out("chunk.csv.partial")));
  // Killed for real: a longer sweep (13 limit-cycle points of 300 s runs, ~5 s with one job) gets SIGKILL after 1 s,
  // certainly before its end (checked: no CSV yet), then is rerun with two jobs.
  const std::string slow = kC3 + " --t_end 100 --param rpm=220:280:5 --method rosenstein";
  ASSERT_EQ(run("sweep " + slow + " --out " + out("slow_whole.csv")).status, 0);
  std::system(("timeout -s KILL 1 " + std::string(MLCE_CLI) + " sweep " + slow + " --jobs 1 --out " + out("killed.csv") +
               " >/dev/null 2>&1")
                  .c_str());
  ASSERT_FALSE(fs::exists(out("killed.csv"))) << "the sweep finished within 1 s: the kill interrupted nothing";
  ASSERT_TRUE(fs::exists(out("killed.csv.partial")));
  const auto after_kill = sweep_json(slow + " --jobs 2 --out " + out("killed.csv"));
  std::printf("killed after 1 s: %d of %d points had been journalled\n", after_kill["resumed"].get<int>(),
              after_kill["points"].get<int>());
  EXPECT_EQ(slurp(out("killed.csv")), slurp(out("slow_whole.csv")));
}

TEST_F(SweepCli, QrLargestExponentAloneIsTheFullSpectrumsFirst) {
  // --count 1: two tangent vectors instead of 12 (the second to see a complex pair), one column.
  const auto one = sweep_json(kC3 + " --param rpm=200:320:60 --method qr --count 1 --out " + out("q1.csv"));
  const auto all = sweep_json(kC3 + " --param rpm=200:320:60 --method qr --out " + out("q.csv"));
  ASSERT_EQ(one["rows"].size(), 3u);
  ASSERT_EQ(all["rows"].size(), 3u);
  EXPECT_EQ(one["columns"], (nlohmann::json{"rpm", "lambda_1", "note"}));
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(one["rows"][k][1].get<double>(), all["rows"][k][1].get<double>(), 1e-6) << one["rows"][k].dump();
}

TEST_F(SweepCli, Errors) {
  const std::string base = "sweep " + kC3 + " --out " + out("x.csv");
  expect_one_line_error(run(base), "--param", 2);
  expect_one_line_error(run(base + " --param rpm"), "expected NAME=first:last:step", 2);
  expect_one_line_error(run(base + " --param rpm=300:200:10"), "first <= last", 2);
  expect_one_line_error(run(base + " --param rpm=200:300:0"), "step must be positive", 2);
  expect_one_line_error(run(base + " --param rpm=a:300:10"), "'a' is not a number", 2);
  expect_one_line_error(run(base + " --param stiffness=1:2:1"), "stiffness", 2);
  expect_one_line_error(run(base + " --param rpm=200 --method lyap"), "--method 'lyap'", 2);
  expect_one_line_error(run(base + " --param rpm=200 --preset turbo"), "--preset 'turbo'", 2);
  expect_one_line_error(run(base + " --param rpm=200 --method rosenstein --channel beta"), "--channel 'beta'", 2);
  expect_one_line_error(run(base + " --param rpm=200 --count 1"), "--count: only with --method qr", 2);
  expect_one_line_error(run(base + " --param rpm=200 --method qr --count 13"), "--count 13: expected 1..12", 2);
  expect_one_line_error(run("sweep " + kC3 + " --param rpm=200"), "--out", 2);
  expect_one_line_error(run(base + " --param rpm=200 --param cx=1 --param cy=1 --plot " + out("p.png")),
                        "one or two swept parameters", 2);
  // One parameter on two axes (the last would win at every point), or a blade's value with all blades'.
  expect_one_line_error(run(base + " --param rpm=200 --param rpm=210"), "--param rpm=210: rpm is swept twice", 2);
  expect_one_line_error(run(base + " --param c=1:2:1 --param c2=3"), "--param c2=3: c2 and c set the same blade's value",
                        2);
  expect_one_line_error(run(base + " --param CL3=1 --param CL=3"), "--param CL=3: CL and CL3 set the same blade's value",
                        2);
  expect_one_line_error(run(base + " --param rpm=200 --rpm 300"), "--param rpm=200: --rpm sets it too", 2);
  EXPECT_FALSE(fs::exists(out("x.csv")));
  // A point that cannot be computed is recorded, not fatal: no values, the reason in its note, a
  // warning on stderr. The rotor with blade 3's damper off is isotropic only at c3 = 4067.5, so
  // eigen (which needs an isotropic rotor) fails at c3 = 0 and computes c3 = 4067.5.
  const CliRun some = run(base + " --param c3=0:4067.5:4067.5 --method eigen --quiet");
  EXPECT_EQ(some.status, 0) << some.err;
  EXPECT_NE(some.err.find("1 of 2 points failed"), std::string::npos) << some.err;
  const std::string mixed = slurp(out("x.csv"));
  EXPECT_NE(mixed.find("\n0,,,,,,,,,,,,,error: the rotor is not isotropic"), std::string::npos) << mixed;
  EXPECT_NE(mixed.find("\n4067.5,-"), std::string::npos) << mixed;
  fs::remove(out("x.csv"));
  // When every point fails (0.05 s at 20 ms: 8 samples), nothing was computed: one error line,
  // exit 1, and no CSV or journal.
  expect_one_line_error(run(base + " --param rpm=200:210:10 --method rosenstein --t_end 0.05 --quiet"),
                        "every one of the 2 points failed (" + out("x.csv") +
                            " not written); the first (rpm = 200): series too short: 8 samples",
                        1);
  EXPECT_FALSE(fs::exists(out("x.csv")));
  EXPECT_FALSE(fs::exists(out("x.csv") + ".partial"));
  // A journal left by a sweep with other settings is not mixed in.
  ASSERT_EQ(run(base + " --param rpm=200:300:50 --max-points 1 --quiet").status, 3);
  expect_one_line_error(run(base + " --param rpm=200:300:25 --quiet"), "other settings", 1);
  EXPECT_FALSE(fs::exists(out("x.csv")));
}
