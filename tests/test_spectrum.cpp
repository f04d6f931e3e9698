// Jacobian-based exponents against independent truth: analytic eigenvalues (LTI problems,
// Liouville's trace formula), the published Lorenz spectrum, Floquet versus multiblade
// eigenanalysis versus discrete QR (three different computations of the same numbers), and the
// analytic sensitivities against central differences of the exponents themselves.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "mlce/models/dynamics.hpp"
#include "mlce/models/scene.hpp"
#include "mlce/spectrum/floquet.hpp"
#include "mlce/spectrum/qr_spectrum.hpp"
#include "mlce/spectrum/tangent.hpp"

using namespace mlce;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

ode::DynamicalSystem linear_system(const MatrixXd& A) {
  ode::DynamicalSystem s;
  s.dimension = static_cast<int>(A.rows());
  s.rhs = [A](const VectorXd& x, VectorXd& dx, double) { dx = A * x; };
  s.jacobian = [A](const VectorXd&, double) { return A; };
  s.rhs_complex = [A](const Eigen::VectorXcd& x, Eigen::VectorXcd& dx, double) { dx = A.cast<std::complex<double>>() * x; };
  return s;
}

/// Damped oscillator x'' + 2 zeta w x' + w^2 x = 0: both exponents are -zeta w exactly.
MatrixXd oscillator(double zeta, double w) {
  MatrixXd A(2, 2);
  A << 0, 1, -w * w, -2 * zeta * w;
  return A;
}

models::Scene scene(const std::vector<std::string>& overrides) { return models::load_scene("", overrides); }

spectrum::QrOptions qr_options(double t_end, double step, spectrum::MergeRule merge = spectrum::MergeRule::none) {
  spectrum::QrOptions o;
  o.t_end = t_end;
  o.step = step;
  o.transient = 0.1 * t_end;
  o.merge = merge;
  return o;
}

}  // namespace

TEST(QrSpectrum, DampedOscillatorBothExponentsAfter1000TimeUnits) {
  const double zeta = 0.05, w = 2 * std::numbers::pi;
  auto o = qr_options(1000.0, 0.01);
  o.transient = 0.0;
  const auto r = spectrum::qr_spectrum(linear_system(oscillator(zeta, w)), VectorXd::Ones(2), o);
  // Unmerged, each estimate of a complex pair carries an oscillation of about ln(cond of the
  // eigenvectors) / t = ln(w) / 1000 here: the discrete QR method's own limit.
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(r.raw_exponents(i), -zeta * w, 1.1 * std::log(w) / 1000) << i;
  // Liouville: the sum is the mean trace (to the integration tolerance).
  EXPECT_NEAR(r.raw_exponents.sum(), -2 * zeta * w, 1e-8);
  // Merged as unresolved (the CLI default), the pair is -zeta w to the same accuracy.
  o.merge = spectrum::MergeRule::unresolved;
  const auto m = spectrum::qr_spectrum(linear_system(oscillator(zeta, w)), VectorXd::Ones(2), o);
  ASSERT_EQ(m.groups.size(), 1u);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(m.exponents(i), -zeta * w, 1e-8);
}

TEST(QrSpectrum, LinearTimeInvariantEqualsRealPartsOfEigenvalues) {
  MatrixXd A(4, 4);
  A << -0.5, 2.0, 0.3, 0.0, -0.1, -1.0, 0.0, 0.7, 0.2, 0.0, 0.4, 1.0, 0.0, -0.3, 0.0, -2.5;
  const Eigen::EigenSolver<MatrixXd> es(A);
  std::vector<double> re;
  for (int i = 0; i < 4; ++i) re.push_back(es.eigenvalues()(i).real());
  std::sort(re.rbegin(), re.rend());
  const auto r = spectrum::qr_spectrum(linear_system(A), VectorXd::Ones(4), qr_options(400.0, 0.05, spectrum::MergeRule::unresolved));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r.exponents(i), re[static_cast<std::size_t>(i)], 5e-3) << i;
  const auto lin = spectrum::linear_eigen(A);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(lin.exponents(i), re[static_cast<std::size_t>(i)], 1e-12);
}

TEST(QrSpectrum, LorenzPublishedSpectrumAndTrace) {
  ode::DynamicalSystem s;
  s.dimension = 3;
  const double sg = 10, rho = 28, beta = 8.0 / 3.0;
  s.rhs = [=](const VectorXd& x, VectorXd& dx, double) {
    dx.resize(3);
    dx << sg * (x(1) - x(0)), x(0) * (rho - x(2)) - x(1), x(0) * x(1) - beta * x(2);
  };
  s.jacobian = [=](const VectorXd& x, double) {
    MatrixXd J(3, 3);
    J << -sg, sg, 0, rho - x(2), -1, -x(0), x(1), x(0), -beta;
    return J;
  };
  auto o = qr_options(1000.0, 0.05);
  o.transient = 20.0;
  const auto r = spectrum::qr_spectrum(s, Eigen::Vector3d(1, 1, 20), o);
  // Sprott's reference values 0.9056, 0, -14.5723; the sum is -(sigma + 1 + beta) exactly.
  EXPECT_NEAR(r.exponents(0), 0.9056, 0.03);
  EXPECT_NEAR(r.exponents(1), 0.0, 0.01);
  EXPECT_NEAR(r.exponents(2), -14.5723, 0.03);
  EXPECT_NEAR(r.exponents.sum(), -(sg + 1 + beta), 1e-3);
  EXPECT_LT(r.orthogonality_error, 1e-13);
  // The divergence integrated with the trajectory is the constant -(sigma + 1 + beta), and the
  // log-sums of the QR factors reproduce it to the integration tolerance (Liouville).
  EXPECT_NEAR(r.mean_divergence, -(sg + 1 + beta), 1e-9);
  EXPECT_NEAR(r.exponent_sum, -(sg + 1 + beta), 1e-7);
  EXPECT_TRUE(r.warnings.empty());
}

namespace {
/// x' = A(t) x, A = [[-1 + cos t, 1], [0, -2 sin^2 t]], period 2 pi: tr A averages to -1 - 1 = -2
/// over a period, so the two Floquet (and Lyapunov) exponents sum to -2 exactly, while neither is
/// known in closed form.
ode::DynamicalSystem periodic_linear() {
  ode::DynamicalSystem s;
  s.dimension = 2;
  s.period = 2 * std::numbers::pi;
  auto A = [](double t) {
    MatrixXd a(2, 2);
    a << -1 + std::cos(t), 1, 0, -2 * std::sin(t) * std::sin(t);
    return a;
  };
  s.rhs = [A](const VectorXd& x, VectorXd& dx, double t) { dx = A(t) * x; };
  s.jacobian = [A](const VectorXd&, double t) { return A(t); };
  return s;
}
}  // namespace

TEST(Liouville, FloquetAndQrExponentsSumToTheMeanDivergenceOfAPeriodicSystem) {
  const auto fl = spectrum::floquet(periodic_linear(), {});
  EXPECT_NEAR(fl.mean_divergence, -2.0, 1e-9);
  EXPECT_NEAR(fl.exponents.sum(), -2.0, 1e-9);
  EXPECT_TRUE(fl.warnings.empty());
  auto o = qr_options(200 * std::numbers::pi, 0.05);
  const auto qr = spectrum::qr_spectrum(periodic_linear(), VectorXd::Ones(2), o);
  EXPECT_NEAR(qr.mean_divergence, -2.0, 1e-9);  // whole periods averaged
  EXPECT_NEAR(qr.exponent_sum, -2.0, 1e-8);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(qr.raw_exponents(i), fl.exponents(i), 1e-3) << i;
  EXPECT_TRUE(qr.warnings.empty());
}

TEST(Liouville, LooseTangentIntegrationIsFlagged) {
  // Tolerances of 1e-2 and a QR step of 0.1 s on the blade-3-inoperative scene: the tangent
  // integration loses volume, and says so (the default settings do not: ThreeJacobianRoutesAgree).
  const auto sc = scene({"--c", "4067.5,4067.5,0,4067.5"});
  auto loose = qr_options(30.0, 0.1);
  loose.integrator.rtol = loose.integrator.atol = 1e-2;
  const auto r = spectrum::qr_spectrum(models::dynamical_system(sc), sc.x0, loose);
  std::printf("rtol = atol = 1e-2, QR step 0.1 s: exponents sum to %.6f, mean divergence %.6f\n", r.exponent_sum,
              r.mean_divergence);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("Liouville"), std::string::npos);
}

TEST(QrSpectrum, ThreeJacobianRoutesAgree) {
  // Blade 3 inoperative at 242.4 rpm: a nonlinear, time-periodic trajectory growing into the
  // limit cycle. Analytic, complex-step and Jacobian-free tangents give the same exponents.
  const auto sc = scene({"--c", "4067.5,4067.5,0,4067.5"});
  const auto sys = models::dynamical_system(sc);
  std::vector<VectorXd> results;
  std::vector<double> divergence;
  for (auto m : {spectrum::JacobianMethod::analytic, spectrum::JacobianMethod::complex_step, spectrum::JacobianMethod::jacobian_free}) {
    auto o = qr_options(10.0, 0.01);
    o.jacobian = m;
    const auto r = spectrum::qr_spectrum(sys, sc.x0, o);
    results.push_back(r.raw_exponents);
    // Liouville along a trajectory whose divergence varies (the mass matrix depends on the lag
    // angles); the Jacobian-free route gets tr A as tr(Z^-1 A Z) from its own products.
    EXPECT_NEAR(r.exponent_sum, r.mean_divergence, 1e-7 * std::abs(r.mean_divergence)) << spectrum::jacobian_method_name(m);
    EXPECT_TRUE(r.warnings.empty()) << spectrum::jacobian_method_name(m);
    divergence.push_back(r.mean_divergence);
  }
  EXPECT_LT((results[0] - results[1]).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((results[0] - results[2]).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_NEAR(divergence[1], divergence[0], 1e-9 * std::abs(divergence[0]));
  EXPECT_NEAR(divergence[2], divergence[0], 1e-7 * std::abs(divergence[0]));
}

TEST(Tangent, FullJacobianOfEachRouteIsTheAnalyticOneAndAMissingRouteIsRefused) {
  // Hammond, blade 3 inoperative, at a state off the equilibrium (lag angles and rates set): the
  // complex-step and central-difference Jacobians against the model's analytic one.
  const auto sc = scene({"--c", "4067.5,4067.5,0,4067.5"});
  const auto sys = models::dynamical_system(sc);
  VectorXd x = VectorXd::LinSpaced(sys.dimension, -0.3, 0.5);
  const MatrixXd exact = spectrum::jacobian(sys, spectrum::JacobianMethod::analytic, x, 0.37);
  const double scale = exact.cwiseAbs().maxCoeff();
  EXPECT_LT((spectrum::jacobian(sys, spectrum::JacobianMethod::complex_step, x, 0.37) - exact).cwiseAbs().maxCoeff(),
            1e-12 * scale);
  EXPECT_LT((spectrum::jacobian(sys, spectrum::JacobianMethod::jacobian_free, x, 0.37) - exact).cwiseAbs().maxCoeff(),
            1e-7 * scale);
  // A system that has only a right-hand side: the Jacobian-free route serves, the others are refused.
  ode::DynamicalSystem bare;
  bare.dimension = sys.dimension;
  bare.rhs = sys.rhs;
  EXPECT_NO_THROW(spectrum::require(bare, spectrum::JacobianMethod::jacobian_free));
  try {
    spectrum::require(bare, spectrum::JacobianMethod::analytic);
    ADD_FAILURE() << "analytic accepted without a Jacobian";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no analytic Jacobian: use --jacobian complex-step or jacobian-free"),
              std::string::npos) << e.what();
  }
  try {
    spectrum::require(bare, spectrum::JacobianMethod::complex_step);
    ADD_FAILURE() << "complex-step accepted without a complex right-hand side";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no complex right-hand side"), std::string::npos) << e.what();
  }
  for (auto m : {spectrum::JacobianMethod::analytic, spectrum::JacobianMethod::complex_step,
                 spectrum::JacobianMethod::jacobian_free})
    EXPECT_EQ(spectrum::jacobian_method_from_name(spectrum::jacobian_method_name(m)), m);
}

TEST(QrSpectrum, LeadingExponentsAloneAreTheFullSpectrumsWithTheirSensitivities) {
  // Blade 3 inoperative: the k = 1 and 3 largest (k + 1 tangent vectors, thin QR) against all
  // 12, exponents and sensitivities to c3 and rpm. For k < n the sensitivity needs the part of
  // Q_/p outside span(Q).
  const auto sc = scene({"--c", "4067.5,4067.5,0,4067.5"});
  const auto sys = models::dynamical_system(sc);
  const std::vector<ode::ParameterFamily> params{models::parameter_family(sc, "c3"), models::parameter_family(sc, "rpm")};
  auto o = qr_options(20.0, 0.01);
  const auto full = spectrum::qr_spectrum(sys, sc.x0, o, params);
  for (std::size_t k : {1u, 3u}) {
    o.count = k;
    const auto part = spectrum::qr_spectrum(sys, sc.x0, o, params);
    ASSERT_EQ(part.exponents.size(), static_cast<Eigen::Index>(k));
    ASSERT_EQ(part.raw_exponents.size(), static_cast<Eigen::Index>(k + 1));  // one more, to see pairs
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(k); ++i) {
      std::printf("k = %zu, lambda_%ld: %.10f vs %.10f; d/dc3 %.6e vs %.6e; d/drpm %.6e vs %.6e\n", k, i + 1,
                  part.raw_exponents(i), full.raw_exponents(i), part.sensitivities(0, i), full.sensitivities(0, i),
                  part.sensitivities(1, i), full.sensitivities(1, i));
      EXPECT_NEAR(part.raw_exponents(i), full.raw_exponents(i), 1e-6) << k << " " << i;
      for (int p = 0; p < 2; ++p)
        EXPECT_NEAR(part.sensitivities(p, i), full.sensitivities(p, i), 1e-5 * std::abs(full.sensitivities(p, i)) + 1e-12)
            << k << " " << i << " " << p;
    }
    EXPECT_TRUE(std::isnan(part.mean_divergence));  // no Liouville check on part of the spectrum
  }
  // The complex step direction by direction (fewer directions than states) gives the same.
  o.count = 1;
  o.jacobian = spectrum::JacobianMethod::complex_step;
  const auto cs = spectrum::qr_spectrum(sys, sc.x0, o, params);
  EXPECT_NEAR(cs.exponents(0), full.raw_exponents(0), 1e-6);
  for (int p = 0; p < 2; ++p) EXPECT_NEAR(cs.sensitivities(p, 0), full.sensitivities(p, 0), 1e-5 * std::abs(full.sensitivities(p, 0)));
}

TEST(QrSpectrum, LargestExponentAloneIsAveragedWithItsComplexPartner) {
  // Blade 3 inoperative at 200 rpm: the motion decays, lambda_1 = lambda_2 is a complex pair. One
  // tangent vector alone oscillates about it (the unmerged estimate, ln(cond)/t); the extra vector
  // that count = 1 integrates lets the merge rule average the pair as the full spectrum does.
  const auto sc = scene({"--c", "4067.5,4067.5,0,4067.5", "--rpm", "200"});
  const auto sys = models::dynamical_system(sc);
  auto o = qr_options(150.0, 0.01, spectrum::MergeRule::unresolved);
  const auto full = spectrum::qr_spectrum(sys, sc.x0, o);
  o.count = 1;
  const auto one = spectrum::qr_spectrum(sys, sc.x0, o);
  std::printf("200 rpm: lambda_1 alone %.8f (raw %.8f, %.8f), all 12 %.8f\n", one.exponents(0), one.raw_exponents(0),
              one.raw_exponents(1), full.exponents(0));
  ASSERT_EQ(one.exponents.size(), 1);
  ASSERT_EQ(one.groups.size(), 1u);
  EXPECT_EQ(one.groups[0], (std::vector<int>{0, 1}));
  EXPECT_NEAR(one.exponents(0), full.exponents(0), 1e-6);
  EXPECT_GT(std::abs(one.raw_exponents(0) - full.exponents(0)), 1e-3);  // half a pair alone is off
}

// One test per rotor speed: each runs a 400-s QR spectrum of all 12 exponents (5 s here, about
// ten times that under the sanitizers), so they run in parallel, each within ctest's time limit.
class FloquetIsotropicRotor : public ::testing::TestWithParam<double> {};

TEST_P(FloquetIsotropicRotor, AgreesWithMultibladeEigenvaluesAndQr) {
  const double rpm = GetParam();
  const auto sc = scene({"--rpm", std::to_string(rpm), "--cy", "51078.7"});
  const auto fl = spectrum::floquet(models::dynamical_system(sc), {});
  const auto eig = spectrum::linear_eigen(models::time_invariant_form(sc).A);
  ASSERT_EQ(fl.exponents.size(), 12);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(fl.exponents(i), eig.exponents(i), 1e-7) << rpm << " rpm, " << i;
  // Close pairs (about 0.04 1/s apart at 260 rpm) need a few hundred seconds to separate.
  auto o = qr_options(400.0, 0.01, spectrum::MergeRule::unresolved);
  const auto qr = spectrum::qr_spectrum(models::dynamical_system(sc), sc.x0, o);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(qr.exponents(i), eig.exponents(i), 2e-3) << rpm << " rpm, " << i;
  // Collective and reactionless lag modes are decoupled from the hub: -c / (2 I_b), twice each.
  const double target = -4067.5 / (2 * 1084.7);
  int count = 0;
  for (int i = 0; i < 12; ++i) count += std::abs(eig.exponents(i) - target) < 1e-9;
  EXPECT_EQ(count, 4) << rpm;
}
INSTANTIATE_TEST_SUITE_P(Rpm, FloquetIsotropicRotor, ::testing::Values(120.0, 200.0, 260.0, 330.0),
                         [](const ::testing::TestParamInfo<double>& i) { return std::to_string(static_cast<int>(i.param)) + "rpm"; });

TEST(Floquet, TrivialSolutionTestIsRelativeToTheSizeOfTheTerms) {
  // x'' + w^2 x = a cos t, period 2 pi. With w = 1e8 the terms of f are of size 1e16 |x|, so a
  // residue a = 1e-2 at x = 0 is rounding (eps 1e16 ~ 2): x = 0 is taken as the solution. With
  // w = 1, a = 1e-2 is a real forcing: refused, naming both sizes.
  auto forced = [](double w, double a) {
    ode::DynamicalSystem s = linear_system(oscillator(0.0, w));
    const MatrixXd A = oscillator(0.0, w);
    s.rhs = [A, a](const VectorXd& x, VectorXd& dx, double t) {
      dx = A * x;
      dx(1) += a * std::cos(t);
    };
    s.rhs_complex = nullptr;
    s.period = 2 * std::numbers::pi;
    return s;
  };
  try {
    spectrum::floquet(forced(1.0, 1e-2), {});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("x = 0 is not a solution of this model (|f(0, t)| = 0.01, above the 1e-09"),
              std::string::npos) << e.what();
  }
  // w = 1e8 over 2 pi needs at least 1.6e8 steps (|h lambda| <= 4): the step budget says so at
  // once (rather than the trivial-solution test refusing a rounding residue).
  try {
    spectrum::floquet(forced(1e8, 1e-2), {});
    ADD_FAILURE() << "no error";
  } catch (const ode::IntegrationError& e) {
    EXPECT_NE(std::string(e.what()).find("needs at least 1.57e+08 steps"), std::string::npos) << e.what();
  }
}

TEST(QrSpectrum, ContractionBeyondADoubleOverOneStepIsNamedWithTheCure) {
  // Eigenvalues -1 and -1000, QR step 1: r_22 = e^-1000 is below what a double holds. The error
  // names the step and the entry. A step of 0.1 contracts the second column by e^-100 = 4e-44
  // per step, far below atol = 1e-10: it gives -1000 (it gave ln(atol) / step = -234 when the
  // column's error was controlled by atol rather than relative to its size).
  MatrixXd A(2, 2);
  A << -1, 0, 0, -1000;
  auto o = qr_options(20.0, 1.0);
  try {
    spectrum::qr_spectrum(linear_system(A), VectorXd::Ones(2), o);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("over one QR step of 1 (the direction was lost: it contracted beyond 1e-280"),
              std::string::npos) << e.what();
  }
  o.step = 0.1;
  const auto r = spectrum::qr_spectrum(linear_system(A), VectorXd::Ones(2), o);
  EXPECT_NEAR(r.exponents(1), -1000.0, 1e-6 * 1000.0);
  EXPECT_NEAR(r.exponents(0), -1.0, 1e-6);
}

TEST(Floquet, FlappingAtZeroAdvanceRatioIsTheOscillator) {
  // mu = 0: beta'' + (gamma/8) beta' + nu^2 beta = 0, roots -gamma/16 +- i sqrt(nu^2 - (gamma/16)^2).
  const auto sc = scene({"--model", "flapping", "--mu", "0"});
  const auto fl = spectrum::floquet(models::dynamical_system(sc), {});
  EXPECT_NEAR(fl.exponents(0), -0.5, 1e-9);
  EXPECT_NEAR(fl.exponents(1), -0.5, 1e-9);
  // Frequencies are principal values in (-1/2, 1/2] (period 2 pi): sqrt(3/4) appears as 1 - sqrt(3/4).
  EXPECT_NEAR(std::abs(fl.frequencies(0)), 1.0 - std::sqrt(1 - 0.25), 1e-9);
}

TEST(Floquet, BladeThreeInoperativeUnstableBand) {
  auto lambda_max = [](double rpm) {
    const auto sc = scene({"--c", "4067.5,4067.5,0,4067.5", "--rpm", std::to_string(rpm)});
    return spectrum::floquet(models::dynamical_system(sc), {}).exponents(0);
  };
  auto edge = [&](double stable, double unstable) {
    for (int k = 0; k < 30; ++k) {
      const double mid = 0.5 * (stable + unstable);
      (lambda_max(mid) > 0 ? unstable : stable) = mid;
    }
    return 0.5 * (stable + unstable);
  };
  const double lo = edge(180.0, 242.4), hi = edge(360.0, 242.4);
  std::printf("blade 3 inoperative, c_y = 25539.35: Floquet unstable from %.2f to %.2f rpm\n", lo, hi);
  // Paper 001 sec. 5 / the shared MBDyn runs: from about 210-211 rpm to just above 300 rpm.
  EXPECT_NEAR(lo, 211.0, 2.0);
  EXPECT_GT(hi, 300.0);
  EXPECT_LT(hi, 310.0);
}

TEST(Sensitivity, FlappingQrAndFloquetAgreeWithCentralDifferencesOfFloquet) {
  for (double mu : {0.5, 1.2}) {
    const auto sc = scene({"--model", "flapping", "--mu", std::to_string(mu)});
    const auto fam = models::parameter_family(sc, "mu");
    const auto fl = spectrum::floquet(models::dynamical_system(sc), {}, {fam});
    const double d = 1e-4;
    const auto plus = spectrum::floquet(models::dynamical_system(scene({"--model", "flapping", "--mu", std::to_string(mu + d)})), {});
    const auto minus = spectrum::floquet(models::dynamical_system(scene({"--model", "flapping", "--mu", std::to_string(mu - d)})), {});
    auto o = qr_options(2000.0, 0.05, spectrum::MergeRule::unresolved);
    o.integrator.rtol = 1e-10;
    const auto qr = spectrum::qr_spectrum(models::dynamical_system(sc), sc.x0, o, {fam});
    for (int i = 0; i < 2; ++i) {
      const double fd = (plus.exponents(i) - minus.exponents(i)) / (2 * d);
      const double tol = 0.02 * std::abs(fd) + 1e-4;
      EXPECT_NEAR(fl.sensitivities(0, i), fd, tol) << "Floquet, mu " << mu << ", " << i;
      EXPECT_NEAR(qr.exponents(i), fl.exponents(i), 2e-3) << "QR vs Floquet, mu " << mu << ", " << i;
      EXPECT_NEAR(qr.sensitivities(0, i), fd, tol) << "QR, mu " << mu << ", " << i;
    }
  }
}

TEST(Sensitivity, NonlinearDampersQrAgreesWithCentralDifferencesInCL) {
  // Isotropic rotor with the nonlinear dampers of paper 000 eq. 39, C_L = C_d: exponentially
  // stable; d lambda / d C_L from the QR pass against central differences of QR exponents.
  auto sc_at = [](double cl) {
    return scene({"--damper", "nonlinear", "--CL", std::to_string(cl), "--rpm", "242.4", "--x0", "0.01"});
  };
  const double cl = 4067.5, d = 40.0;
  auto o = qr_options(150.0, 0.005, spectrum::MergeRule::unresolved);
  o.count = 2;  // the two leading exponents (3 tangent vectors, not 12): a fourth of the work
  const auto sc = sc_at(cl);
  const auto r = spectrum::qr_spectrum(models::dynamical_system(sc), sc.x0, o, {models::parameter_family(sc, "CL")});
  const auto p = spectrum::qr_spectrum(models::dynamical_system(sc_at(cl + d)), sc.x0, o);
  const auto m = spectrum::qr_spectrum(models::dynamical_system(sc_at(cl - d)), sc.x0, o);
  for (int i = 0; i < 2; ++i) {
    const double fd = (p.exponents(i) - m.exponents(i)) / (2 * d);
    std::printf("exponent %d: %.6f, d/dCL analytic %.4e, central difference %.4e\n", i + 1, r.exponents(i), r.sensitivities(0, i), fd);
    EXPECT_NEAR(r.sensitivities(0, i), fd, 0.1 * std::abs(fd)) << i;
  }
}
