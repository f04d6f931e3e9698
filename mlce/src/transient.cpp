#include "mlce/transient.hpp"

#include "mlce/mean_period.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace mlce {

void TransientOptions::validate() const {
  if (!(band >= 0.0)) throw OptionError("transient.band: expected >= 0 (0 = automatic)");
  if (!(band_min > 0.0 && band_min <= band_max)) throw OptionError("transient.band_min/band_max: expected 0 < min <= max");
  if (!(floor_ratio >= 0.0 && floor_ratio < 1.0)) throw OptionError("transient.floor_ratio: expected [0, 1)");
}

std::size_t detect_floor(const Series& s, double floor_ratio) {
  const std::size_t n = s.size(), windows = 100, w = n / windows;
  if (w < 2 || floor_ratio <= 0.0) return 0;
  // In place, no standardised copy: each channel divided by its peak |x| (squares of 1e300 would
  // overflow); the test is a ratio of RMS levels, so the scale does not matter otherwise.
  std::vector<double> rms(windows, 0.0);
  for (const auto& x : s.channels) {
    double peak = 0.0;
    for (double v : x) peak = std::max(peak, std::abs(v));
    if (peak == 0.0) continue;
    double mean = 0.0;
    for (std::size_t i = 75 * w; i < windows * w; ++i) mean += x[i] / peak;
    mean /= static_cast<double>(25 * w);
    for (std::size_t k = 0; k < windows; ++k)
      for (std::size_t i = k * w; i < (k + 1) * w; ++i) rms[k] += (x[i] / peak - mean) * (x[i] / peak - mean);
  }
  for (double& v : rms) v = std::sqrt(v / static_cast<double>(w));
  std::vector<double> tail(rms.begin() + 75, rms.end());
  std::nth_element(tail.begin(), tail.begin() + 12, tail.end());
  const double level = tail[12], peak = *std::max_element(rms.begin(), rms.end());
  if (!(level < floor_ratio * peak)) return 0;
  std::size_t k = windows;
  while (k > 0 && rms[k - 1] <= 10.0 * level) --k;
  return k * w;
}

TransientResult detect_transient(const Series& series, const TransientOptions& options) {
  options.validate();
  validate_series(series);
  const Series s = standardized(series);
  const std::size_t n = s.size();
  TransientResult r;
  if (const std::size_t f = detect_floor(s, options.floor_ratio); f > 0) {
    r.settled = false;
    r.floor_index = f;
    r.end_time = s.time(0);
    r.rule = "decays into the noise/underflow floor from sample " + std::to_string(f) + " (RMS below " +
             std::to_string(options.floor_ratio) + " of its largest): nothing cut at the start";
    return r;
  }
  const std::size_t w = options.window ? options.window : std::max<std::size_t>(2 * options.period, n / 100);
  const std::size_t windows = n / std::max<std::size_t>(w, 1);
  if (windows < 8) {
    r.rule = "series shorter than 8 RMS windows of " + std::to_string(w) + " samples: nothing cut";
    r.end_time = s.time(0);
    return r;
  }
  const std::size_t tail_from = windows - windows / 4;
  // Mean of the last quarter: the centre of the settled motion.
  std::vector<double> mean_tail(s.channel_count(), 0.0);  // once per channel, not once per window
  for (std::size_t c = 0; c < s.channel_count(); ++c) {
    for (std::size_t i = tail_from * w; i < windows * w; ++i) mean_tail[c] += s.channels[c][i];
    mean_tail[c] /= static_cast<double>((windows - tail_from) * w);
  }
  std::vector<double> rms(windows);
  for (std::size_t k = 0; k < windows; ++k) {
    double acc = 0.0;
    for (std::size_t c = 0; c < s.channel_count(); ++c)
      for (std::size_t i = k * w; i < (k + 1) * w; ++i) {
        const double e = s.channels[c][i] - mean_tail[c];
        acc += e * e;
      }
    rms[k] = std::sqrt(acc / static_cast<double>(w));
  }
  std::vector<double> tail(rms.begin() + static_cast<std::ptrdiff_t>(tail_from), rms.end());
  std::nth_element(tail.begin(), tail.begin() + static_cast<std::ptrdiff_t>(tail.size() / 2), tail.end());
  const double ref = tail[tail.size() / 2];
  double band = options.band;
  if (band == 0.0) {
    std::vector<double> dev(tail.size());
    for (std::size_t k = 0; k < tail.size(); ++k) dev[k] = std::abs(tail[k] - ref);
    std::nth_element(dev.begin(), dev.begin() + static_cast<std::ptrdiff_t>(dev.size() / 2), dev.end());
    const double scatter = ref > 0.0 ? dev[dev.size() / 2] / ref : 0.0;
    band = std::clamp(4.0 * scatter, options.band_min, options.band_max);
  }
  auto inside = [&](double v) { return std::abs(v - ref) <= band * ref; };
  std::ostringstream rule;
  if (ref == 0.0 || !inside(rms[tail_from]) || !inside(rms[windows - 1])) {
    r.settled = false;
    rule << "RMS still drifts in the last quarter (decay or growth): no settled part, nothing cut";
    r.rule = rule.str();
    r.end_time = s.time(0);
    return r;
  }
  std::size_t k = windows;
  while (k > 0 && inside(rms[k - 1])) --k;
  r.end_index = k * w;
  r.end_time = s.time(r.end_index);
  rule << "moving RMS in windows of " << w << " samples settles within " << band * 100
       << " % of the last quarter's median from sample " << r.end_index;
  r.rule = rule.str();
  return r;
}

Series skip_transient(const Series& series, TransientResult* result) {
  TransientOptions o;
  o.period = estimate_mean_period(series, {}).mean_period;
  const TransientResult r = detect_transient(series, o);
  if (result) *result = r;
  return time_window(series, r.end_time, series.time(series.size() - 1));
}

}  // namespace mlce
