#pragma once
// Small numerical helpers shared by the estimators.
#include <cmath>
#include <cstddef>

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

/// Ordinary least squares y = a + b x over equally spaced x = first..last.
struct LineFit {
  double slope = 0.0;
  double intercept = 0.0;
  double r2 = 0.0;
  double slope_stderr = 0.0;  ///< formal standard error (iid residuals)
  std::size_t n = 0;
};
LineFit fit_line(const double* y, std::size_t first, std::size_t last);

/// Two-sided 95 % quantile of Student's t with `dof` degrees of freedom.
double student_t95(std::size_t dof);

}  // namespace mlce
