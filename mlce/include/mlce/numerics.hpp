#pragma once
// Small numerical helpers shared by the estimators.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace mlce {

/// Neumaier's compensated sum: long sums (10^7 log-distances) without drift.
class CompensatedSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    if (std::abs(sum_) >= std::abs(x))
      c_ += (sum_ - t) + x;
    else
      c_ += (x - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + c_; }

 private:
  double sum_ = 0.0;
  double c_ = 0.0;
};

/// Ordinary least squares y = a + b x (compensated sums, x centred on its mean).
struct LineFit {
  double slope = 0.0;
  double intercept = 0.0;
  double r2 = 0.0;
  double slope_stderr = 0.0;  ///< formal standard error (iid residuals)
  std::size_t n = 0;
};
/// Over equally spaced x = first..last (the steps of a curve).
LineFit fit_line(const double* y, std::size_t first, std::size_t last);
/// Over the points (x[i], y[i]), i = 0..n-1 (n >= 1; x not all equal when n >= 2).
LineFit fit_line(const double* x, const double* y, std::size_t n);

/// splitmix64 (Steele, Lea and Flood 2014): a fixed, platform-independent pseudo-random sequence,
/// so that what is drawn from it (the attractor scale's pairs, a dither) is the same on every
/// machine, compiler and thread count, unlike std::uniform_real_distribution.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
/// Uniform in [0, 1) from the top 53 bits of splitmix64.
inline double uniform01(std::uint64_t& state) { return static_cast<double>(splitmix64(state) >> 11) * 0x1.0p-53; }

/// The largest |x[i]| (0 for an empty x). Series are divided by it before squares are taken: squares
/// of 1e200 overflow, squares of 1e-200 underflow.
inline double max_abs(std::span<const double> x) {
  double peak = 0.0;
  for (double v : x) peak = std::max(peak, std::abs(v));
  return peak;
}

/// sum over t of x[t] x[t + lag] (compensated): the unnormalised autocorrelation of a series
/// centred by the caller (lag 0: its sum of squares). 0 when lag >= x.size().
double lagged_product_sum(const std::vector<double>& x, std::size_t lag);

/// The element of rank size/2 of v (the median for odd sizes, the upper of the middle two for even
/// sizes); v non-empty, taken by value (nth_element reorders it).
double upper_median(std::vector<double> v);
/// The median of v (the mean of the middle two for even sizes); v non-empty.
double median(std::vector<double> v);

/// Lagrange weights of the samples at -1, 0, 1, 2 for the point a fraction f past sample 0 (f in
/// [0, 1)): the cubic through four samples, exact for cubics; at f = 0 exactly (0, 1, 0, 0).
inline std::array<double, 4> lagrange_cubic_weights(double f) {
  return {-f * (f - 1.0) * (f - 2.0) / 6.0, (f + 1.0) * (f - 1.0) * (f - 2.0) / 2.0, -(f + 1.0) * f * (f - 2.0) / 2.0,
          (f + 1.0) * f * (f - 1.0) / 6.0};
}

/// Two-sided 95 % quantile of Student's t with `dof` degrees of freedom.
double student_t95(std::size_t dof);

}  // namespace mlce
