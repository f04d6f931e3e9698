// Issue 6: every bundled real MBDyn run against the ad-hoc model of the same scene, through the
// command line as an analyst runs it: trajectories, limit-cycle range or decay rate, the MLCE by
// Rosenstein from both sources, and the MLCE against the Jacobian references (eigen, QR).
//
// Tolerances, from the integrators: MBDyn (multistep, rho_inf 0.6, fixed 1 ms) and the ad-hoc RK45
// (rtol 1e-8) agree to ~1e-5 rad over the first seconds; on the limit cycle the phase error of the
// neutral direction grows linearly (5.7e-2 rad after 30 s at 0.55 rad/s lag rates, i.e. ~0.1 % of a
// period per 10 s), so trajectories are compared where phase has not drifted and the limit cycle by
// its range. Both sources go through the same deterministic estimator, so their MLCEs differ only
// by what the trajectories differ by.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli_harness.hpp"

using mlce::testing::CliRun;

namespace {

const std::string kData = std::string(MLCE_DATA_DIR) + "/mbdyn/";
const std::string kScenes = std::string(MLCE_DATA_DIR) + "/../scenes/";
const std::string kIso = kData + "iso_200rpm_5s/iso_200rpm";
const std::string kLco = kData + "c3zero_242rpm_cyhalf_lco/c3zero_242rpm_cyhalf";

class MbdynVsAdHoc : public mlce::testing::CliFixture {
 protected:
  nlohmann::json json_of(const std::string& args) {
    const CliRun r = run(args + " --json");
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return r.status == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
  }
  std::string simulate(const std::string& scene, double t_end) {
    std::string out = (dir / scene).string();
    const CliRun r = run("simulate " + kScenes + scene + ".scene --t_end " + std::to_string(t_end) + " --out " + out +
                         " --quiet");
    EXPECT_EQ(r.status, 0) << r.err;
    return out;
  }
};

bool contains_zero(const nlohmann::json& e) { return e["ci95"][0].get<double>() <= 0 && e["ci95"][1].get<double>() >= 0; }

}  // namespace

TEST_F(MbdynVsAdHoc, IsotropicRunDecaysAtTheSlowestEigenvalueFromBothSources) {
  const std::string adhoc = simulate("isotropic_200rpm", 5);
  // (a) trajectories over the whole bundled run (5 s, 1000 output steps).
  const auto cmp = json_of("compare " + adhoc + " " + kIso +
                           " --channel rel:11:4:z --channel rel:12:4:z --channel rel:13:4:z --channel rel:14:4:z"
                           " --channel node:2:x --channel node:3:y");
  ASSERT_EQ(cmp["channels"].size(), 6u);
  for (const auto& c : cmp["channels"]) {
    const std::string name = c["channel"];
    std::printf("%-12s max |adhoc - mbdyn| %.3e  range difference %.4f %%\n", name.c_str(),
                c["max_abs_difference"].get<double>(), 100 * c["range_relative_difference"].get<double>());
    EXPECT_LT(c["max_abs_difference"].get<double>(), name[0] == 'r' ? 1e-4 : 1e-4) << name;
  }
  // (b, c, d) the decay rate: Rosenstein on every blade's lag from both sources, against the
  // slowest eigenvalue of the multiblade linearisation (an independent, Jacobian-based number).
  const double slowest = json_of("eigen " + kScenes + "isotropic_200rpm.scene")["exponents"][0].get<double>();
  EXPECT_NEAR(slowest, -1.1828, 1e-3);
  // As an analyst runs it: `mlce compare --mlce`, window from the end of the ad-hoc run's transient.
  const auto exps = json_of("compare " + adhoc + " " + kIso +
                            " --channel rel:11:4:z --channel rel:12:4:z --channel rel:13:4:z --channel rel:14:4:z --mlce");
  ASSERT_EQ(exps["channels"].size(), 4u);
  for (const auto& c : exps["channels"]) {
    const std::string ch = c["channel"];
    const auto& m = c["mlce"];
    const double a = m["a"]["lambda"].get<double>(), b = m["b"]["lambda"].get<double>();
    std::printf("%-12s MLCE ad-hoc %.5f  MBDyn %.5f  eigen %.5f 1/s (window %.3g..%.3g s)\n", ch.c_str(), a, b, slowest,
                m["window"][0].get<double>(), m["window"][1].get<double>());
    EXPECT_LT(a, -0.5);
    EXPECT_LT(b, -0.5);
    EXPECT_LT(std::abs(a - b), 0.1 * std::abs(b)) << ch;        // issue 6: within 10 % of each other
    EXPECT_LT(std::abs(a - slowest), 0.05 * std::abs(slowest)) << ch;  // and of the eigenvalue
    EXPECT_TRUE(m["intervals_overlap"].get<bool>()) << ch;
    EXPECT_TRUE(m["agreement"]["agree"].get<bool>()) << ch;  // overlapping intervals agree at any resolution
    // Both runs read the decay the eigenvalues say (every exponent negative: stable).
    for (const auto& one : {m["a"], m["b"]}) {
      EXPECT_EQ(one["reading"]["stability"], "stable") << ch << ": " << one["reading"].dump();
      EXPECT_EQ(one["reading"]["motion"], "decays to rest") << ch;
    }
  }
}

TEST_F(MbdynVsAdHoc, AWindowAfterTheDecayReadsRestNotChaos) {
  // The isotropic run (every multiblade eigenvalue stable) has decayed to the ad-hoc integrator's
  // floor, ~1e-11 m, by 20 s: `--from 30` leaves that floor alone, whose solver residue read
  // +0.3..+0.9 1/s, "chaotic", before the window was judged against the record it was cut from.
  const std::string adhoc = simulate("isotropic_200rpm", 60);
  const auto late = json_of("estimate " + adhoc + " --channel node:2:x --from 30 --quiet");
  std::printf("node:2:x 30..60 s: lambda %.4f 1/s, window RMS %.3g of the record's deviation: %s\n",
              late["lambda"].get<double>(), late["floor_window_ratio"].get<double>(),
              late["reading"]["summary"].get<std::string>().c_str());
  EXPECT_LT(late["floor_window_ratio"].get<double>(), 1e-6);
  EXPECT_EQ(late["reading"]["stability"], "stable");
  EXPECT_EQ(late["reading"]["motion"], "decays to rest");
  EXPECT_NE(late["warnings"].dump().find("floor of a decay that ended before it"), std::string::npos);
  EXPECT_EQ(late["in_decay_floor"], true);
  // Several runs: the table flags the row, and the plot draws no lambda for it (the residue, +0.69 1/s).
  const std::string table = (dir / "floor_runs.csv").string(), png = (dir / "floor_runs.png").string();
  const CliRun runs = run("estimate " + adhoc + " " + adhoc + " --channel node:2:x --from 30 --quiet --csv " + table +
                          " --plot " + png);
  ASSERT_EQ(runs.status, 0) << runs.err;
  const std::string table_text = mlce::testing::slurp(table);
  EXPECT_NE(table_text.find(",stability,motion,in_decay_floor,"), std::string::npos) << table_text;
  EXPECT_NE(table_text.find(",stable,decays to rest,1,"), std::string::npos) << table_text;
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
  // Every channel of --each, judged against its own record.
  const auto each = json_of("estimate " + adhoc + " --channel node:2:x --channel node:3:y --from 30 --each --quiet");
  ASSERT_EQ(each["channels"].size(), 2u);
  for (const auto& c : each["channels"]) EXPECT_EQ(c["reading"]["motion"], "decays to rest") << c.dump();
  // The whole run is no window: nothing to judge it by, and its decay reads as before.
  const auto whole = json_of("estimate " + adhoc + " --channel node:2:x --quiet");
  EXPECT_TRUE(whole["floor_window_ratio"].is_null());
  EXPECT_EQ(whole["in_decay_floor"], false);
  EXPECT_EQ(whole["reading"]["motion"], "decays to rest");
  // From 10 s the window holds the end of the decay and then the floor: judged against the record, the
  // floor is left out, and every leading part of at least half the window (`mlce convergence`, whose
  // parts are windows of the record too) reads the slowest eigenvalue, where they read +0.01..-0.18
  // 1/s, neutral, with the floor analysed as motion.
  const double slowest = json_of("eigen " + kScenes + "isotropic_200rpm.scene")["exponents"][0].get<double>();
  const auto conv = json_of("convergence " + adhoc + " --channel node:2:x --from 10 --quiet");
  const auto& points = conv["points"];
  ASSERT_EQ(points.size(), 8u);
  for (std::size_t k = 3; k < points.size(); ++k) {
    std::printf("node:2:x 10..%.1f s: lambda %+.4f 1/s (%s)\n", points[k]["t_end"].get<double>(),
                points[k]["lambda"].get<double>(), points[k]["motion"].get<std::string>().c_str());
    EXPECT_NEAR(points[k]["lambda"].get<double>(), slowest, 0.03 * std::abs(slowest)) << k;
    EXPECT_EQ(points[k]["stability"], "stable") << k;
    EXPECT_EQ(points[k]["in_decay_floor"], false) << k;  // the decay is measured
  }
  EXPECT_TRUE(conv["converged"].get<bool>());
  // From 30 s every part is the floor: flagged, and the plot draws none at its residue lambda.
  const std::string parts_png = (dir / "floor_parts.png").string();
  const auto floor = json_of("convergence " + adhoc + " --channel node:2:x --from 30 --quiet --plot " + parts_png);
  for (const auto& p : floor["points"]) {
    EXPECT_EQ(p["in_decay_floor"], true) << p.dump();
    EXPECT_EQ(p["stability"], "stable") << p.dump();
  }
  EXPECT_GT(std::filesystem::file_size(parts_png), 1000u);
}

TEST_F(MbdynVsAdHoc, ShortRunsOfSlowDecaysReadTheFloquetExponent) {
  // Blade 3 inoperative just outside the unstable band (200 and 320 rpm), 20 s in MBDyn's format from
  // x_h = 0.1 m: the decay is slow (about 19 mean periods), and the curve first rises over the
  // start-up, so it starts low in its range like a limit cycle's. Read as bounded divergence from
  // step 0, it gave -0.0709 and -0.0847 against Floquet's -0.0868 and -0.1052; the signal decays as
  // the curve falls, so it is a decay (fit rule, step 1) and reads the least damped Floquet exponent.
  for (const char* rpm : {"200", "320"}) {
    const std::string out = (dir / (std::string("rpm") + rpm)).string();
    const CliRun sim = run("simulate " + kScenes + "c3zero_242rpm.scene --rpm " + rpm + " --t_end 20 --out " + out + " --quiet");
    ASSERT_EQ(sim.status, 0) << sim.err;
    const auto e = json_of("estimate " + out + " --channel rel:13:4:z --quiet");
    const double floquet = json_of("floquet " + kScenes + "c3zero_242rpm.scene --rpm " + rpm)["exponents"][0].get<double>();
    EXPECT_NEAR(e["lambda"].get<double>(), floquet, 0.03 * std::abs(floquet)) << rpm << " rpm: " << e["fit_rule"];
    EXPECT_NE(e["curve_end"], "bounded divergence") << e["fit_rule"];
    EXPECT_EQ(e["reading"]["stability"], "stable");
  }
}

TEST_F(MbdynVsAdHoc, FailedDamperRunLimitCycleRangeAndBoundedDivergence) {
  const std::string adhoc = simulate("c3zero_242rpm", 30);
  // (b) the limit cycle of blade 3 over the bundled part of the MBDyn run (20-30 s): range to 1 %.
  const auto cmp = json_of("compare " + adhoc + " " + kLco + " --channel rel:13:4:z --channel node:2:x --from 20");
  for (const auto& c : cmp["channels"]) {
    const std::string name = c["channel"];
    std::printf("%-12s 20..30 s: range ad-hoc %.5f..%.5f MBDyn %.5f..%.5f, difference %.4f %%, max |A-B| %.3e\n",
                name.c_str(), c["range_a"][0].get<double>(), c["range_a"][1].get<double>(),
                c["range_b"][0].get<double>(), c["range_b"][1].get<double>(),
                100 * c["range_relative_difference"].get<double>(), c["max_abs_difference"].get<double>());
    EXPECT_LT(c["range_relative_difference"].get<double>(), name[0] == 'r' ? 0.01 : 0.02) << name;
  }
  // (c) the MLCE from both sources on the same 10 s of limit cycle (`compare --mlce`): both see
  // bounded divergence (neighbours never separate), both intervals contain 0, and they agree with
  // each other. Without --from the window starts where the ad-hoc run's transient ends (~19.9 s).
  for (const std::string from : {" --from 20", ""}) {
    const auto exps = json_of("compare " + adhoc + " " + kLco + " --channel rel:13:4:z --channel node:2:x --mlce" + from);
    for (const auto& c : exps["channels"]) {
      const std::string ch = c["channel"];
      const auto &m = c["mlce"], &a = m["a"], &b = m["b"];
      std::printf("%-12s %.4g..%.4g s: MLCE ad-hoc %.4f [%.4f, %.4f]  MBDyn %.4f [%.4f, %.4f] 1/s (%s / %s)\n", ch.c_str(),
                  m["window"][0].get<double>(), m["window"][1].get<double>(), a["lambda"].get<double>(),
                  a["ci95"][0].get<double>(), a["ci95"][1].get<double>(), b["lambda"].get<double>(),
                  b["ci95"][0].get<double>(), b["ci95"][1].get<double>(), a["curve_end"].get<std::string>().c_str(),
                  b["curve_end"].get<std::string>().c_str());
      EXPECT_GT(m["window"][0].get<double>(), 19.0) << ch;
      EXPECT_EQ(a["curve_end"], "bounded divergence") << ch;
      EXPECT_EQ(b["curve_end"], "bounded divergence") << ch;
      EXPECT_LT(std::abs(m["difference"].get<double>()), 0.05) << ch;
      EXPECT_TRUE(m["intervals_overlap"].get<bool>()) << ch;
      EXPECT_TRUE(m["agreement"]["agree"].get<bool>()) << ch;
      if (ch == "rel:13:4:z") {
        EXPECT_TRUE(contains_zero(a)) << a.dump();
        EXPECT_TRUE(contains_zero(b)) << b.dump();
      }
      // Both runs read the limit cycle they are (paper 001 Fig. 8: Floquet +0.2985 1/s about x = 0 at
      // 242.4 rpm, so no decay to rest; the motion is bounded).
      for (const auto& one : {a, b}) {
        EXPECT_EQ(one["reading"]["stability"], "neutral") << ch << ": " << one["reading"].dump();
        EXPECT_EQ(one["reading"]["motion"], "limit cycle") << ch;
      }
    }
  }
  // The text table says the same in its last column.
  const CliRun text = run("compare " + adhoc + " " + kLco + " --channel rel:13:4:z --mlce --from 20");
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("reading A / B"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("neutral (limit cycle) / neutral (limit cycle)"), std::string::npos) << text.out;
}

TEST_F(MbdynVsAdHoc, TenSecondsOfSettledLimitCycleResolveZero) {
  // The bundled MBDyn run ends at 30 s, while its limit cycle still settles: blade 3's largest lag
  // per second still moves between 1.5350 and 1.5546 rad over 20..30 s (README), and that residual decaying mode, not the neutral
  // phase, sets the pair distances of a 10 s window (MLCE -0.07..-0.09, interval containing 0).
  // Once settled, 10 s windows of the same scene resolve |lambda| < 0.05 as issue 6 asks.
  const std::string adhoc = simulate("c3zero_242rpm", 70);
  for (const int from : {40, 60}) {
    const auto e = json_of("estimate " + adhoc + " --channel rel:13:4:z --from " + std::to_string(from) + " --to " +
                           std::to_string(from + 10) + " --quiet");
    std::printf("blade 3 lag, %d..%d s: MLCE %.5f [%.5f, %.5f] 1/s (%s)\n", from, from + 10, e["lambda"].get<double>(),
                e["ci95"][0].get<double>(), e["ci95"][1].get<double>(), e["curve_end"].get<std::string>().c_str());
    EXPECT_LT(std::abs(e["lambda"].get<double>()), 0.05) << from;
    EXPECT_TRUE(contains_zero(e)) << e.dump();
  }
}

TEST_F(MbdynVsAdHoc, LongLimitCycleMlceIsZeroLikeTheQrExponent) {
  // 10 limit-cycle periods resolve lambda only to ~0.2 1/s; 180 s of the ad-hoc model (which
  // costs 1 s to simulate) resolve it to 0.05, and the QR method gives the same zero exponent.
  const std::string adhoc = simulate("c3zero_242rpm", 200);
  const auto e = json_of("estimate " + adhoc + " --channel rel:13:4:z --from 20 --quiet");
  const auto qr = json_of("spectrum " + kScenes + "c3zero_242rpm.scene --t-end 100");
  const double mlce = e["lambda"].get<double>(), lambda1 = qr["exponents"][0].get<double>();
  std::printf("blade 3 lag, 20..200 s: MLCE %.5f 1/s [%.5f, %.5f] (%s); QR lambda1 %.5f, lambda2 %.5f 1/s\n", mlce,
              e["ci95"][0].get<double>(), e["ci95"][1].get<double>(), e["curve_end"].get<std::string>().c_str(),
              lambda1, qr["exponents"][1].get<double>());
  EXPECT_LT(std::abs(mlce), 0.05);
  EXPECT_LT(std::abs(lambda1), 0.05);
  EXPECT_LT(std::abs(mlce - lambda1), 0.05);
}
