#pragma once
// A long QR run on the damped oscillator (both exponents -zeta w exactly, trace -2 zeta w), shared by
// the extremes test (2 x 10^5 re-orthonormalisations) and the heavy test (10^7): Q stays orthonormal
// to rounding and the compensated sums give the exact exponents to 1e-8 (no drift from accumulation).
#include <gtest/gtest.h>

#include <numbers>

#include "mlce/spectrum/qr_spectrum.hpp"
#include "oscillator_system.hpp"

namespace mlce::reference {

inline void expect_long_qr_run_exact(double t_end, std::size_t intervals) {
  const double zeta = 0.05, w = 2 * std::numbers::pi;
  const ode::DynamicalSystem s = damped_oscillator_system(zeta, w);
  spectrum::QrOptions o;
  o.t_end = t_end;
  o.step = 0.01;
  o.transient = 0.0;
  o.history_points = 10;
  o.integrator.max_steps = 100'000'000;
  const auto r = spectrum::qr_spectrum(s, Eigen::VectorXd::Ones(2), o);
  EXPECT_EQ(r.intervals, intervals);
  EXPECT_LT(r.orthogonality_error, 1e-12);
  EXPECT_NEAR(r.exponents(0), -zeta * w, 1e-8);
  EXPECT_NEAR(r.raw_exponents.sum(), -2 * zeta * w, 1e-8);
}

}  // namespace mlce::reference
