#include "mlce/numerics.hpp"

#include <algorithm>
#include <array>

namespace mlce {

namespace {
/// Least squares over i = first..last with abscissae x(i) whose mean is xm (centring keeps the
/// normal equations well conditioned).
template <class X>
LineFit fit_line_about(X x, double xm, const double* y, std::size_t first, std::size_t last) {
  LineFit f;
  f.n = last - first + 1;
  if (f.n < 2) {
    f.intercept = y[first];
    return f;
  }
  CompensatedSum sy;
  for (std::size_t i = first; i <= last; ++i) sy.add(y[i]);
  const double ym = sy.value() / static_cast<double>(f.n);
  CompensatedSum sxx, sxy, syy;
  for (std::size_t i = first; i <= last; ++i) {
    const double dx = x(i) - xm, dy = y[i] - ym;
    sxx.add(dx * dx);
    sxy.add(dx * dy);
    syy.add(dy * dy);
  }
  f.slope = sxy.value() / sxx.value();
  f.intercept = ym - f.slope * xm;
  const double sse = std::max(0.0, syy.value() - f.slope * sxy.value());
  f.r2 = syy.value() > 0.0 ? 1.0 - sse / syy.value() : 1.0;
  if (f.n > 2) f.slope_stderr = std::sqrt(sse / static_cast<double>(f.n - 2) / sxx.value());
  return f;
}
}  // namespace

LineFit fit_line(const double* y, std::size_t first, std::size_t last) {
  return fit_line_about([](std::size_t i) { return static_cast<double>(i); }, 0.5 * static_cast<double>(first + last),
                        y, first, last);
}

LineFit fit_line(const double* x, const double* y, std::size_t n) {
  CompensatedSum sx;
  for (std::size_t i = 0; i < n; ++i) sx.add(x[i]);
  return fit_line_about([x](std::size_t i) { return x[i]; }, sx.value() / static_cast<double>(n), y, 0, n - 1);
}

double student_t95(std::size_t dof) {
  static constexpr std::array<double, 31> table = {
      0.0,    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
      2.201,  2.179,  2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080,
      2.074,  2.069,  2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof == 0) return table[1];
  if (dof < table.size()) return table[dof];
  if (dof <= 60) return 2.042 - (2.042 - 2.000) * static_cast<double>(dof - 30) / 30.0;
  if (dof <= 120) return 2.000 - (2.000 - 1.980) * static_cast<double>(dof - 60) / 60.0;
  return 1.960;
}

double lagged_product_sum(const std::vector<double>& x, std::size_t lag) {
  CompensatedSum s;
  for (std::size_t t = 0; t + lag < x.size(); ++t) s.add(x[t] * x[t + lag]);
  return s.value();
}

double upper_median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

double median(std::vector<double> v) {
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h), v.end());
  if (v.size() % 2 == 1) return v[h];
  const double upper = v[h];  // the lower middle one is the largest of the elements before it
  return 0.5 * (*std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h)) + upper);
}

}  // namespace mlce
