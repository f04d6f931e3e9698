// Ad-hoc models and integrators against independent truth: complex-step derivatives, known
// solutions (convergence order), Boost.Odeint's dopri5, and real MBDyn runs of the same model.
#include <gtest/gtest.h>

#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <complex>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "mlce/models/flapping.hpp"
#include "mlce/models/hammond.hpp"
#include "mlce/models/scene.hpp"
#include "mlce/models/simulate.hpp"
#include "mlce/ode/runge_kutta.hpp"
#include "mlce/ode/step_budget.hpp"
#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/mbdyn_text.hpp"

using namespace mlce;
using Eigen::VectorXd;

namespace {

const std::string kIso = std::string(MLCE_DATA_DIR) + "/mbdyn/iso_200rpm_1s/iso_200rpm";
const std::string kC3 = std::string(MLCE_DATA_DIR) + "/mbdyn/c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf";

/// Complex-step Jacobian (Squire & Trapp): J e_j = Im f(x + i h e_j) / h, exact to rounding.
Eigen::MatrixXd complex_step_jacobian(const models::HammondModel& m, const VectorXd& x, double t) {
  const Eigen::Index n = x.size();
  Eigen::MatrixXd J(n, n);
  const double h = 1e-30;
  for (Eigen::Index j = 0; j < n; ++j) {
    Eigen::VectorXcd xc = x.cast<std::complex<double>>(), f(n);
    xc(j) += std::complex<double>(0.0, h);
    m.rhs(xc, f, t);
    J.col(j) = f.imag() / h;
  }
  return J;
}

models::Scene scene(const std::vector<std::string>& overrides) { return models::load_scene("", overrides); }

}  // namespace

TEST(Hammond, AnalyticJacobianMatchesComplexStep) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const char* damper : {"linear", "nonlinear"}) {
    models::HammondParameters p;
    p.damper.assign(4, damper == std::string("linear") ? models::DamperLaw::linear : models::DamperLaw::nonlinear);
    p.k = {100.0, 0.0, 2500.0, 0.0};
    const models::HammondModel m(p);
    for (int trial = 0; trial < 20; ++trial) {
      VectorXd x(12);
      for (int i = 0; i < 12; ++i) x(i) = U(rng);
      // Rates on both damper branches (|zetadot| below and above 1 deg/s), never at the kink.
      for (int i = 6; i < 10; ++i) x(i) = (trial % 2 ? 0.01 : 0.5) * U(rng);
      const double t = 3.0 * U(rng);
      const auto Ja = m.jacobian(x, t), Jc = complex_step_jacobian(m, x, t);
      const double scale = Jc.cwiseAbs().maxCoeff();
      for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
          ASSERT_NEAR(Ja(i, j), Jc(i, j), 1e-8 * std::max(std::abs(Jc(i, j)), 1e-6 * scale))
              << damper << " trial " << trial << " (" << i << "," << j << ")";
    }
  }
}

TEST(Hammond, NonlinearDamperIsContinuousAtSaturation) {
  const double zL = 0.017453292519943295, chibar = 1.2203e6;
  for (double CL : {0.0, 4067.5}) {
    const double below = models::nonlinear_damper_moment(zL * (1 - 1e-12), CL, chibar, zL);
    const double above = models::nonlinear_damper_moment(zL * (1 + 1e-12), CL, chibar, zL);
    EXPECT_NEAR(below, above, 1e-6 * std::abs(above));
    EXPECT_NEAR(above, -chibar * zL * zL, 1e-9);
    EXPECT_GT(models::nonlinear_damper_moment(-0.5 * zL, CL, chibar, zL), 0.0);  // opposes the rate
  }
}

TEST(Hammond, MassMatrixIsSymmetricAndEnergyIsConservedWithoutDampingAtRest) {
  // No dampers, no rotation: the free system conserves T + V; a sign error in the coupling
  // (as printed in eq. 25b) breaks this.
  models::HammondParameters p;
  p.rpm = 0.0;
  p.c.assign(4, 0.0);
  p.c_x = p.c_y = 0.0;
  p.k = {3e4, 2e4, 3e4, 1e4};
  const models::HammondModel m(p);
  auto energy = [&](const VectorXd& x) {
    double T = 0.5 * (p.m_x + 4 * p.m_b) * x(10) * x(10) + 0.5 * (p.m_y + 4 * p.m_b) * x(11) * x(11);
    double V = 0.5 * p.k_x * x(4) * x(4) + 0.5 * p.k_y * x(5) * x(5);
    for (int i = 0; i < 4; ++i) {
      const double u = p.azimuth0(i) + x(i);
      T += 0.5 * p.I_b * x(6 + i) * x(6 + i) + p.S_b * x(6 + i) * (-x(10) * std::sin(u) + x(11) * std::cos(u));
      V += 0.5 * p.k[static_cast<std::size_t>(i)] * x(i) * x(i);
    }
    return T + V;
  };
  VectorXd x0 = VectorXd::Zero(12);
  x0 << 0.3, -0.2, 0.1, 0.4, 0.05, -0.03, 0.5, 0.0, -0.4, 0.2, 0.1, 0.2;
  ode::IntegratorOptions o;
  o.rtol = 1e-11, o.atol = 1e-13;
  const double e0 = energy(x0);
  ode::integrate_uniform(m, x0, 0.0, 0.1, 101, o, [&](std::size_t, double, const VectorXd& x) {
    EXPECT_NEAR(energy(x), e0, 1e-7 * std::abs(e0));
  });
}

TEST(Integrators, EachSchemeShowsItsOrder) {
  // y' = y cos t, y(0) = 1: y = exp(sin t). Fixed steps h and h/2, error at t = 2 (a step point).
  // Two copies of the equation: gcc 12 warns (-Warray-bounds, a false positive) on Eigen's
  // vectorised copy of a one-element VectorXd.
  auto f = [](const VectorXd& y, VectorXd& dy, double t) { dy = y * std::cos(t); };
  for (auto [scheme, order] : {std::pair{ode::Scheme::bs23, 3}, {ode::Scheme::dp45, 5}, {ode::Scheme::rk4, 4}}) {
    double err[2];
    for (int r = 0; r < 2; ++r) {
      ode::IntegratorOptions o;
      o.scheme = scheme;
      o.fixed_step = true;
      o.h_fixed = 0.1 / (1 << r) / 2;
      VectorXd y(2);
      y << 1.0, 1.0;
      double last = 0;
      ode::integrate_uniform(f, y, 0.0, 0.1, 21, o, [&](std::size_t, double, const VectorXd& x) { last = x(0); });
      err[r] = std::abs(last - std::exp(std::sin(2.0)));
    }
    const double observed = std::log2(err[0] / err[1]);
    EXPECT_NEAR(observed, order, 0.3) << ode::scheme_name(scheme) << " errors " << err[0] << " " << err[1];
  }
}

TEST(StepBudget, StiffnessBoundIsBelowTheStepsTakenAndTooStiffARunIsRefusedBeforeItStarts) {
  // x' = A x with eigenvalues -k and -1 (and a coupling, so the eigenvalues are not A's diagonal
  // read off): rho = k exactly, so the bound over a span S is S k / 4.
  auto linear = [](double k) {
    ode::DynamicalSystem sys;
    sys.dimension = 2;
    Eigen::Matrix2d A;
    A << -k, 3.0, 0.0, -1.0;
    sys.rhs = [A](const VectorXd& x, VectorXd& dx, double) { dx = A * x; };
    sys.jacobian = [A](const VectorXd&, double) { return Eigen::MatrixXd(A); };
    return sys;
  };
  const VectorXd x0 = VectorXd::Ones(2);
  for (auto scheme : {ode::Scheme::bs23, ode::Scheme::dp45}) {
    ode::IntegratorOptions o;
    o.scheme = scheme;
    const auto e = ode::estimate_step_budget(linear(1e3), x0, 0.0, 2.0, 1, o, "linear");
    EXPECT_NEAR(e.fastest_rate, 1e3, 1e-9);
    EXPECT_NEAR(e.minimum_steps, 500.0, 1e-9);
    // The steps the integrator really takes (the stiff mode decays at once; stability limits h).
    VectorXd x = x0;
    double h = 0.0;
    ode::IntegrationStats st;
    ode::integrate_to(linear(1e3).rhs, x, 0.0, 2.0, o, h, st);
    EXPECT_GE(static_cast<double>(st.steps), e.minimum_steps) << ode::scheme_name(scheme);
    // ... and not far below: rk23 is stable to 2.5 on the real axis, rk45 to 3.3, and each runs
    // at the edge with some rejected steps.
    EXPECT_LT(static_cast<double>(st.steps), 4.0 * e.minimum_steps) << ode::scheme_name(scheme) << " " << st.steps;
  }
  // Without an analytic Jacobian: forward differences give the same rate.
  ode::DynamicalSystem no_jacobian = linear(1e3);
  no_jacobian.jacobian = nullptr;
  EXPECT_NEAR(ode::estimate_step_budget(no_jacobian, x0, 0.0, 2.0, 1, {}, "linear").fastest_rate, 1e3, 1e-3);
  // k = 1e12 over 1 s needs 2.5e11 steps: refused, naming what and the numbers.
  try {
    ode::require_step_budget(linear(1e12), x0, 0.0, 1.0, 1, {}, "stiff run");
    ADD_FAILURE() << "no error";
  } catch (const ode::IntegrationError& e) {
    EXPECT_NE(std::string(e.what()).find("stiff run: the fastest mode (|eigenvalue| 1e+12 per unit time) needs at least 2.5e+11 steps"),
              std::string::npos) << e.what();
  }
  // Split into 10^6 calls of 1e-6 each, the same run fits the per-call budget.
  EXPECT_NO_THROW(ode::require_step_budget(linear(1e12), x0, 0.0, 1.0, 1000000, {}, "stiff run"));
  // A fixed step is counted, not estimated; a count beyond the budget is an error, not a cast
  // of 1e21 to size_t.
  ode::IntegratorOptions rk4;
  rk4.scheme = ode::Scheme::rk4;
  rk4.h_fixed = 1e-21;
  EXPECT_THROW(ode::require_step_budget(linear(1.0), x0, 0.0, 1.0, 1, rk4, "rk4"), ode::IntegrationError);
  VectorXd x = x0;
  double h = 0.0;
  ode::IntegrationStats st;
  EXPECT_THROW(ode::integrate_to(linear(1.0).rhs, x, 0.0, 1.0, rk4, h, st), ode::IntegrationError);
  // A right-hand side beyond the range of a double is named, not integrated.
  EXPECT_THROW(ode::require_step_budget(linear(std::numeric_limits<double>::infinity()), x0, 0.0, 1.0, 1, {}, "inf"),
               ode::IntegrationError);
}

TEST(StepBudget, ARunWhoseStiffnessGrowsAlongTheWayIsRefusedWhereItStandsNotAtTheBudget) {
  // x' = -e^{40 t} x: stiffness 1 at the start, so the estimate before the run passes, but the
  // explicit schemes' stability (|h rho| <= 3.3) makes [0, 4] need about e^160 / 132 steps. The run
  // must fail once its steps show it, not after the whole budget of 10^7 steps. By time t it has
  // spent about e^{40 t} / 132 steps and projects e^{40 t} (4 - t) / 3.3: 40 (4 - t) times more, so
  // the projection passes 10 budgets with a few per cent of the budget spent.
  std::size_t evaluations = 0;
  ode::DynamicalSystem sys;
  sys.dimension = 1;
  sys.rhs = [&evaluations](const VectorXd& x, VectorXd& dx, double t) {
    ++evaluations;
    dx = -std::exp(40.0 * t) * x;
  };
  const VectorXd x0 = VectorXd::Ones(1);
  EXPECT_NO_THROW(ode::require_step_budget(sys, x0, 0.0, 0.0 + 1e-3, 1, {}, "growing stiffness"));
  for (const bool uniform : {true, false}) {
    evaluations = 0;
    try {
      if (uniform) {
        ode::integrate_uniform(sys.rhs, x0, 0.0, 0.01, 401, {}, [](std::size_t, double, const VectorXd&) {});
      } else {
        VectorXd x = x0;
        double h = 0.0;
        ode::IntegrationStats st;
        ode::integrate_to(sys.rhs, x, 0.0, 4.0, {}, h, st);
      }
      ADD_FAILURE() << "no error";
    } catch (const ode::IntegrationError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("the steps have shrunk to"), std::string::npos) << m;
      EXPECT_NE(m.find("far beyond the budget of 10000000"), std::string::npos) << m;
    }
    // dp45 makes 6 evaluations per step: under a tenth of the budget was spent.
    EXPECT_LT(evaluations, 6'000'000u) << (uniform ? "integrate_uniform" : "integrate_to");
  }
  // Runs that fit the budget end as they would without the watch: a constant stiffness (the
  // projection is exact), a start-up stiffness 100 times the final one that decays (early windows
  // project ~15 budgets, but the steps grow window on window), and a hump of 5 times that comes and
  // goes (the steps shrink for a while, projecting ~2.5 budgets). rho(t) = 1000 a(t) over 500.
  ode::IntegratorOptions o;
  o.max_steps = 400'000;
  const std::vector<std::pair<std::string, std::function<double(double)>>> stiffness = {
      {"constant", [](double) { return 1.0; }},
      {"decaying start-up", [](double t) { return 1.0 + 99.0 * std::exp(-t); }},
      {"hump", [](double t) { return 1.0 + 4.0 * (t / 5.0) * std::exp(1.0 - t / 5.0); }}};
  for (const auto& [name, stiffness_of] : stiffness) {
    const auto& a = stiffness_of;  // a structured binding is not captured before C++20 in every compiler
    const auto rhs = [&a](const VectorXd& x, VectorXd& dx, double t) { dx = -1e3 * a(t) * x; };
    VectorXd x = x0;
    double h = 0.0;
    ode::IntegrationStats st;
    EXPECT_NO_THROW(ode::integrate_to(rhs, x, 0.0, 500.0, o, h, st)) << name;
    EXPECT_GT(st.steps + st.rejected, 2 * ode::BudgetWatch::kWindow) << name << ": the watch looked at least twice";
    EXPECT_LT(st.steps + st.rejected, o.max_steps) << name;
  }
}

TEST(Integrators, ProgressReportsTheTimeReachedBetweenFarApartOutputSamples) {
  // Two output samples, many steps between them (rho = 1e4 over 10: stability-limited steps):
  // progress comes from the steps, every kProgressSteps of them, at increasing times.
  std::vector<double> reported;
  ode::IntegratorOptions o;
  o.progress = [&reported](double t) { reported.push_back(t); };
  const auto rhs = [](const VectorXd& x, VectorXd& dx, double) { dx = -1e4 * x; };
  const auto st = ode::integrate_uniform(rhs, VectorXd::Ones(1), 0.0, 10.0, 2, o, [](std::size_t, double, const VectorXd&) {});
  ASSERT_EQ(reported.size(), st.steps / ode::IntegratorOptions::kProgressSteps) << st.steps << " steps";
  ASSERT_GE(reported.size(), 5u);
  for (std::size_t k = 0; k < reported.size(); ++k) {
    EXPECT_GT(reported[k], k == 0 ? 0.0 : reported[k - 1]);
    EXPECT_LE(reported[k], 10.0);
  }
}

TEST(Integrators, AdaptiveDp45AgreesWithBoostOdeintDopri5) {
  const auto s = scene({"--rpm", "242.4", "--c", "4067.5,4067.5,0,4067.5", "--t_end", "5"});
  const models::HammondModel m(s.hammond);
  const auto ours = models::simulate(s);
  // Boost.Odeint's dense-output dopri5 on the same system (std::vector state).
  using state = std::vector<double>;
  auto sys = [&](const state& x, state& dx, double t) {
    VectorXd xe = Eigen::Map<const VectorXd>(x.data(), 12), fe(12);
    m(xe, fe, t);
    dx.assign(fe.data(), fe.data() + 12);
  };
  state x(s.x0.data(), s.x0.data() + 12);
  std::vector<state> theirs;
  std::vector<double> times;
  for (std::size_t k = 0; k < ours.time.size(); ++k) times.push_back(ours.time[k]);
  namespace odeint = boost::numeric::odeint;
  odeint::integrate_times(odeint::make_dense_output(1e-12, 1e-12, odeint::runge_kutta_dopri5<state>()), sys, x,
                          times.begin(), times.end(), 1e-4, [&](const state& xs, double) { theirs.push_back(xs); });
  ASSERT_EQ(theirs.size(), ours.states.size());
  for (std::size_t k = 0; k < theirs.size(); k += 50)
    for (int i = 0; i < 12; ++i) EXPECT_NEAR(ours.states[k](i), theirs[k][static_cast<std::size_t>(i)], 1e-6) << k << " " << i;
}

namespace {

/// Lag of blade 3 from an MBDyn output set (the damper joint's own angle would need the .jnt:
/// the bundled 10-s sample has the .mov, so use the relative rotation of the bodies).
std::vector<double> mbdyn_lag3(const std::string& prefix, std::vector<double>& time) {
  auto cs = reader::read_mbdyn_text(prefix, {reader::parse_channel_spec("rel:13:4:z")});
  time = cs.time;
  return cs.values[0];
}

}  // namespace

TEST(Hammond, AgreesWithTheRealMbdynRunOfTheIsotropicRotor) {
  // iso_200rpm: c_y = 51078.7 (Table 1), all dampers, x_h(0) = 0.1 m; first second.
  std::vector<double> t;
  const auto lag = mbdyn_lag3(kIso, t);
  const auto s = scene({"--rpm", "200", "--cy", "51078.7", "--t_end", "1", "--dt_out", "0.005"});
  const auto ours = models::simulate(s);
  ASSERT_EQ(ours.time.size(), lag.size());
  double peak = 0, worst = 0;
  for (std::size_t k = 0; k < lag.size(); ++k) {
    peak = std::max(peak, std::abs(lag[k]));
    worst = std::max(worst, std::abs(ours.states[k](2) - lag[k]));
  }
  EXPECT_GT(peak, 0.01);
  // Measured 1.1e-5 rad at a peak of 0.026 rad. Bound: 1e-3 of the peak, the phase error MBDyn's
  // multistep scheme (rho_inf 0.6, 1 ms) accumulates over 1 s plus 7-digit output; the ad-hoc run
  // (rk45, rtol 1e-8) is ~1e-6 rad accurate (bench_models).
  EXPECT_LT(worst, 1e-3 * peak) << "peak " << peak;
}

TEST(Hammond, FailedDamperAt242rpmGrowsLikeTheRealMbdynRun) {
  // c3zero_242rpm_cyhalf: c_3 = 0, c_y = 25539.35, first 10 s (the limit cycle builds up).
  std::vector<double> t;
  const auto lag = mbdyn_lag3(kC3, t);
  const auto s = scene({"--rpm", "242.4", "--c", "4067.5,4067.5,0,4067.5", "--t_end", "10"});
  const auto ours = models::simulate(s);
  ASSERT_EQ(ours.time.size(), lag.size());
  auto peak = [&](auto get, double a, double b) {
    double m = 0;
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t[k] >= a && t[k] < b) m = std::max(m, std::abs(get(k)));
    return m;
  };
  for (double a : {2.0, 5.0, 8.0}) {
    const double theirs = peak([&](std::size_t k) { return lag[k]; }, a, a + 2);
    const double mine = peak([&](std::size_t k) { return ours.states[k](2); }, a, a + 2);
    EXPECT_NEAR(mine, theirs, 0.02 * theirs) << "window " << a;
  }
  // Pointwise: measured 3.6e-3 rad at a peak of 0.55 rad after 10 s of growth (0.7 %); bound 1.5 %
  // of the peak, the multistep scheme's phase error growing with the amplitude.
  double worst = 0, top = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    worst = std::max(worst, std::abs(ours.states[k](2) - lag[k])), top = std::max(top, std::abs(lag[k]));
  EXPECT_LT(worst, 0.015 * top) << "peak " << top;
}

TEST(Hammond, FailedDamperLimitCycleAt242rpmAndDecayAt124rpm) {
  // Paper 001 Figs. 7-8; the shared MBDyn run: -1.939 .. 1.555 rad over 20-30 s.
  const auto hi = models::simulate(scene({"--rpm", "242.4", "--c", "4067.5,4067.5,0,4067.5", "--t_end", "30"}));
  double lo3 = 0, hi3 = 0;
  for (std::size_t k = 0; k < hi.time.size(); ++k)
    if (hi.time[k] >= 20) lo3 = std::min(lo3, hi.states[k](2)), hi3 = std::max(hi3, hi.states[k](2));
  EXPECT_NEAR(lo3, -1.939, 0.05);
  EXPECT_NEAR(hi3, 1.555, 0.05);
  const auto low = models::simulate(scene({"--rpm", "124.2", "--c", "4067.5,4067.5,0,4067.5", "--t_end", "30"}));
  double early = 0, late = 0;
  for (std::size_t k = 0; k < low.time.size(); ++k)
    (low.time[k] < 5 ? early : low.time[k] > 25 ? late : early) =
        std::max(low.time[k] < 5 ? early : low.time[k] > 25 ? late : early, std::abs(low.states[k](2)));
  EXPECT_LT(late, 0.05 * early);
}

TEST(Flapping, HoverIsADampedOscillatorWithKnownExponent) {
  // mu = 0: beta'' + (gamma/8) beta' + nu^2 beta = 0; with gamma = 8, nu = 1 the roots are
  // -1/2 +- i sqrt(3)/2, so beta = e^{-t/2}(cos(sqrt3/2 t) + (1/sqrt3) sin(sqrt3/2 t)) beta0.
  const auto s = scene({"--model", "flapping", "--mu", "0", "--t_end", "10", "--dt_out", "0.5"});
  const auto tr = models::simulate(s);
  const double w = std::sqrt(3.0) / 2;
  for (std::size_t k = 0; k < tr.time.size(); ++k) {
    const double t = tr.time[k];
    EXPECT_NEAR(tr.states[k](0), 0.1 * std::exp(-t / 2) * (std::cos(w * t) + std::sin(w * t) / std::sqrt(3.0)), 1e-9);
  }
}

namespace {

/// Accepts `room` bytes, then fails every write (a disk that fills up).
class FillingBuffer : public std::streambuf {
 public:
  explicit FillingBuffer(std::size_t room) : room_(room) {}
  std::size_t written = 0;

 protected:
  std::streamsize xsputn(const char*, std::streamsize n) override {
    if (written + static_cast<std::size_t>(n) > room_) return 0;
    written += static_cast<std::size_t>(n);
    return n;
  }
  int_type overflow(int_type c) override { return xsputn(nullptr, 1) == 1 ? c : traits_type::eof(); }

 private:
  std::size_t room_;
};

}  // namespace

TEST(Simulate, ObserversSeeEverySampleAsItComesAndAFailingStreamStopsTheRunAtOnce) {
  const auto s = scene({"--model", "flapping", "--mu", "0.15", "--t_end", "40", "--dt_out", "0.1"});
  const auto tr = models::simulate(s);
  ASSERT_EQ(tr.time.size(), 401u);
  // The rows written as the run goes are the samples of the whole trajectory, to 17 digits.
  std::ostringstream text;
  models::ColumnsWriter columns(text, models::state_names(s));
  std::size_t seen = 0;
  models::simulate(s, [&](std::size_t k, double t, const Eigen::VectorXd& x) {
    EXPECT_EQ(k, seen++);
    columns(k, t, x);
  });
  EXPECT_EQ(seen, tr.time.size());
  std::istringstream rows(text.str());
  std::string header;
  std::getline(rows, header);
  EXPECT_EQ(header, "# time beta betadot");
  for (std::size_t k = 0; k < tr.time.size(); ++k) {
    double t = 0, beta = 0, rate = 0;
    ASSERT_TRUE(rows >> t >> beta >> rate) << k;
    EXPECT_EQ(t, tr.time[k]);
    EXPECT_EQ(beta, tr.states[k](0));
    EXPECT_EQ(rate, tr.states[k](1));
  }
  // A stream that fills up after 2000 bytes stops the run at the first row it cannot take.
  FillingBuffer full(2000);
  std::ostream out(&full);
  models::ColumnsWriter failing(out, models::state_names(s), "run.txt");
  std::size_t offered = 0;
  try {
    models::simulate(s, [&](std::size_t k, double t, const Eigen::VectorXd& x) {
      ++offered;
      failing(k, t, x);
    });
    FAIL() << "a failing stream went unnoticed";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("run.txt: write failed at sample " + std::to_string(offered - 1)), std::string::npos)
        << e.what();
  }
  EXPECT_LT(offered, 50u);
  EXPECT_LE(full.written, 2000u);
}

TEST(Scene, FileKeysCommandLineOverridesAndErrors) {
  const std::string path = ::testing::TempDir() + "/s.scene";
  std::ofstream(path) << "# failed damper\nmodel = hammond\nrpm = 124.2\nc = 4067.5,4067.5,0,4067.5\ndamper = nonlinear\n";
  auto s = models::load_scene(path, {"--rpm", "242.4"});
  EXPECT_DOUBLE_EQ(s.hammond.rpm, 242.4);  // the command line wins
  EXPECT_DOUBLE_EQ(s.hammond.c[2], 0.0);
  EXPECT_EQ(s.hammond.damper[3], models::DamperLaw::nonlinear);
  EXPECT_DOUBLE_EQ(s.hammond.c_y, 25539.35);
  EXPECT_THROW(models::load_scene(path, {"--c", "1,2"}), std::invalid_argument);
  EXPECT_THROW(models::load_scene(path, {"--rpm", "fast"}), std::invalid_argument);
  EXPECT_THROW(models::load_scene(path, {"--integrator", "euler"}), std::invalid_argument);
  try {
    models::load_scene(path, {"--h", "-1e-3"});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), path + ": h = -1e-3: expected a step >= 0 (0: dt_out / 4)");
  }
  // The span errors name the values they refuse, as typed (not std::to_string's 30000000000000.000000).
  const auto message = [&](const std::vector<std::string>& args) {
    try {
      models::load_scene(path, args);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({"--t_end", "0", "--dt_out", "0.005"}),
            path + ": dt_out = 0.005, t_end = 0: expected 0 < dt_out <= t_end");
  EXPECT_EQ(message({"--t_end", "30", "--dt_out", "1e-12"}),
            path + ": t_end / dt_out = 3e+13 output samples: expected at most 5e7 (raise dt_out)");
  EXPECT_THROW(models::load_scene(path, {"--colour", "red"}), std::invalid_argument);
  EXPECT_THROW(models::load_scene("/nonexistent.scene", {}), std::invalid_argument);
  // Each word-valued key names the value it refuses and the words it takes.
  EXPECT_EQ(message({"--damper", "linear,viscous"}), path + ": damper = linear,viscous: expected one value or 4 comma-separated values");
  EXPECT_EQ(message({"--damper", "viscous"}), path + ": damper = viscous: expected linear or nonlinear");
  EXPECT_EQ(message({"--placement", "hub"}), path + ": placement = hub: expected mbdyn or paper");
  EXPECT_EQ(message({"--model", "lorenz"}), path + ": model = lorenz: expected hammond or flapping");
  // A scene saved by a Windows editor: a byte-order mark and CRLF line ends read as the plain file.
  const std::string windows = ::testing::TempDir() + "/w.scene";
  std::ofstream(windows, std::ios::binary) << "\xEF\xBB\xBFmodel = hammond\r\nrpm = 124.2\r\nc = 4067.5,4067.5,0,4067.5\r\n";
  const auto w = models::load_scene(windows, {});
  EXPECT_EQ(w.model, "hammond");
  EXPECT_DOUBLE_EQ(w.hammond.rpm, 124.2);
  EXPECT_DOUBLE_EQ(w.hammond.c[3], 4067.5);
}

TEST(Scene, DescribedSceneReadsAsTypedAndReloadsBitForBit) {
  // describe_scene writes the scene beside a simulation (PREFIX.scene) and heads a sweep's CSV: its
  // numbers must read back exactly, and read as a person typed them (not 242.40000000000001).
  const std::string path = ::testing::TempDir() + "/typed.scene";
  std::ofstream(path) << "model = hammond\nrpm = 242.4\nc = 4067.5,4067.5,0,4067.5\ncy = 25539.35\nx0 = 0.1\n"
                         "t_end = 30\ndt_out = 0.005\nrtol = 1e-8\n";
  const auto s = models::load_scene(path, {"--zetadot_L", "0.017453292519943295"});
  const std::string text = models::describe_scene(s);
  for (const char* line : {"\nrpm = 242.4\n", "\nc = 4067.5,4067.5,0,4067.5\n", "\ncy = 25539.35\n", "\nmx = 8026.6\n",
                           "\nx0 = 0.1\n", "\ndt_out = 0.005\n", "\nrtol = 1e-08\n", "\nzetadot_L = 0.017453292519943295\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << " not in\n" << text;
  const std::string again = ::testing::TempDir() + "/described.scene";
  std::ofstream(again) << text;
  const auto r = models::load_scene(again, {});
  EXPECT_EQ(models::describe_scene(r), text);
  EXPECT_EQ(r.hammond.rpm, s.hammond.rpm);
  EXPECT_EQ(r.hammond.c, s.hammond.c);
  EXPECT_EQ(r.hammond.c_y, s.hammond.c_y);
  EXPECT_EQ(r.hammond.zetadot_L, s.hammond.zetadot_L);
  EXPECT_EQ(r.x0, s.x0);
  EXPECT_EQ(r.dt_out, s.dt_out);
  EXPECT_EQ(r.integrator.rtol, s.integrator.rtol);
}
