// The two largest extremes of issue 7, ~1 min each in Release: a series of 10^7 samples and a QR run
// of 10^7 re-orthonormalisations. Labelled "heavy": the sanitizer pass of ./run test leaves them out.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mlce/estimate.hpp"
#include "mlce/spectrum/qr_spectrum.hpp"
#include "long_qr_run.hpp"
#include "reference_systems.hpp"

using namespace mlce;

namespace {
MlceResult estimate(const std::vector<double>& x, double dt) { return estimate_mlce(make_series_with_step({x}, dt), {}); }
}  // namespace

TEST(Heavy, TenMillionSamples) {
  // Henon x, N = 10^7: memory O(N) (no M x m matrix), the estimate as at N = 10^4 (0.4192 per
  // iteration, within 2 %), no overflow in counts or sums.
  const auto x = reference::henon_x(10000000);
  const auto r = estimate(x, 1.0);
  EXPECT_EQ(r.n_points, 10000000u);
  EXPECT_NEAR(r.lambda, 0.41922, 0.02 * 0.41922) << r.fit.rule;
}

TEST(Heavy, TenMillionQrSteps) {
  // 10^7 re-orthonormalisations of a damped oscillator (10^5 time units), as the 2 x 10^5-step run
  // of test_extremes does: no drift from accumulating 10^7 terms.
  reference::expect_long_qr_run_exact(1e5, 10000000u);
}

