#include "mlce/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mlce {
namespace {

void check(const std::vector<double>& t, const std::vector<double>& v, const char* which) {
  if (t.size() != v.size()) throw std::invalid_argument(std::string(which) + ": time and values differ in length");
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (!std::isfinite(t[k]) || !std::isfinite(v[k]))
      throw std::invalid_argument(std::string(which) + ": non-finite value at sample " + std::to_string(k));
    if (k > 0 && !(t[k] > t[k - 1]))
      throw std::invalid_argument(std::string(which) + ": time does not increase at sample " + std::to_string(k));
  }
}

}  // namespace

HistoryComparison compare_histories(const std::vector<double>& ta, const std::vector<double>& a,
                                    const std::vector<double>& tb, const std::vector<double>& b,
                                    const HistoryComparisonOptions& o) {
  check(ta, a, "first history");
  check(tb, b, "second history");
  if (tb.size() < 2) throw std::invalid_argument("second history: fewer than 2 samples");
  if (std::isnan(o.from) || std::isnan(o.to)) throw std::invalid_argument("window [from, to]: expected times, not nan");
  // The window's ends are matched within 1e-9 of A's step, as time_window does: accumulated times
  // (5.995000000000337) belong to the window a user types (--to 5.995).
  const double tol = ta.size() > 1 ? 1e-9 * (ta.back() - ta.front()) / static_cast<double>(ta.size() - 1) : 0.0;
  const double lo = std::max({o.from - tol, ta.empty() ? 0.0 : ta.front(), tb.front() - tol});
  const double hi = std::min({o.to + tol, ta.empty() ? 0.0 : ta.back(), tb.back() + tol});
  HistoryComparison r;
  r.min_a = r.min_b = std::numeric_limits<double>::infinity();
  r.max_a = r.max_b = -std::numeric_limits<double>::infinity();
  double sum_sq = 0.0;
  std::size_t j = 0;
  for (std::size_t k = 0; k < ta.size(); ++k) {
    const double t = ta[k];
    if (t < lo || t > hi) continue;
    while (j + 2 < tb.size() && tb[j + 1] < t) ++j;
    const double w = std::clamp((t - tb[j]) / (tb[j + 1] - tb[j]), 0.0, 1.0);
    const double bi = (1.0 - w) * b[j] + w * b[j + 1];  // exact at a node (w = 0 or 1): a run against itself differs by 0
    const double d = std::abs(a[k] - bi);
    if (r.points == 0) r.t_first = t;
    r.t_last = t;
    ++r.points;
    sum_sq += d * d;
    if (d > r.max_abs_difference) r.max_abs_difference = d, r.time_of_max = t;
    r.min_a = std::min(r.min_a, a[k]), r.max_a = std::max(r.max_a, a[k]);
    r.min_b = std::min(r.min_b, bi), r.max_b = std::max(r.max_b, bi);
  }
  if (r.points < 2) {
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "the two histories share fewer than 2 samples in the window: A spans t = %.10g..%.10g, B %.10g..%.10g, "
                  "the window is [%.10g, %.10g]",
                  ta.front(), ta.back(), tb.front(), tb.back(), o.from, o.to);
    throw std::invalid_argument(buf);
  }
  r.rms_difference = std::sqrt(sum_sq / static_cast<double>(r.points));
  const double ra = r.max_a - r.min_a, rb = r.max_b - r.min_b;
  r.range_relative_difference = ra > 0 ? std::abs(rb - ra) / ra : (rb > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  const double dta = (ta.back() - ta.front()) / static_cast<double>(ta.size() - 1);
  const double dtb = (tb.back() - tb.front()) / static_cast<double>(tb.size() - 1);
  if (dtb > 1.5 * dta)
    r.warnings.push_back("the second history is sampled more coarsely than the first: interpolation adds error");
  return r;
}

}  // namespace mlce
