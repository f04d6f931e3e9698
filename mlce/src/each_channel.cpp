#include "mlce/each_channel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "mlce/numerics.hpp"

namespace mlce {

void EachChannelOptions::validate() const {
  if (!(relative_tolerance >= 0.0) || !std::isfinite(relative_tolerance))
    throw OptionError("each_channel.relative_tolerance: expected a finite number >= 0");
  if (!(frequency_tolerance >= 0.0) || !std::isfinite(frequency_tolerance))
    throw OptionError("each_channel.frequency_tolerance: expected a finite number >= 0");
}

Agreement judge_agreement(const std::vector<const MlceResult*>& estimates, double relative_tolerance,
                          double frequency_tolerance) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  Agreement a;
  if (estimates.empty()) {  // nothing to judge: no number, no agreement
    a.gap = a.common_low = a.common_high = a.median_lambda = a.tolerance_floor = nan;
    return a;
  }
  std::vector<double> lambdas;
  double largest_frequency = 0.0;
  for (std::size_t k = 0; k < estimates.size(); ++k) {
    const MlceResult& r = *estimates[k];
    lambdas.push_back(r.lambda);
    largest_frequency = std::max(largest_frequency, r.mean_period.mean_frequency);
    if (r.ci95_low > estimates[a.highest_low]->ci95_low) a.highest_low = k;
    if (r.ci95_high < estimates[a.lowest_high]->ci95_high) a.lowest_high = k;
  }
  a.median_lambda = median(lambdas);
  // One interval is no common part of several: with one estimate, gap and common part are NaN.
  a.gap = estimates.size() >= 2 ? estimates[a.highest_low]->ci95_low - estimates[a.lowest_high]->ci95_high : nan;
  a.common_low = a.gap <= 0.0 ? estimates[a.highest_low]->ci95_low : nan;
  a.common_high = a.gap <= 0.0 ? estimates[a.lowest_high]->ci95_high : nan;
  a.tolerance_floor = exponent_resolution(a.median_lambda, largest_frequency, relative_tolerance, frequency_tolerance);
  a.agree = estimates.size() >= 2 && a.gap <= a.tolerance_floor;
  return a;
}

EachChannelResult estimate_each_channel(const Series& series, const EachChannelOptions& options) {
  options.validate();
  const std::size_t count = series.channel_count();
  if (count < 2)
    throw OptionError(fmt::format("estimate_each_channel: the series has {} channel(s); expected 2 or more", count));
  EachChannelResult result;
  std::string first_error;
  for (std::size_t c = 0; c < count; ++c) {
    ChannelEstimate ce;
    ce.name = channel_name(series, c);
    MlceOptions o = options.estimate;
    validate_record_deviation(options.estimate, count);
    if (!o.record_deviation.empty()) o.record_deviation = {options.estimate.record_deviation[c]};  // this channel's
    if (options.estimate.progress) {  // each stage as "<channel> (k of K): <stage>", the fraction of the channels done
      o.progress = [&, c](std::string_view stage, double) {
        options.estimate.progress(fmt::format("{} ({} of {}): {}", ce.name, c + 1, count, stage),
                                  static_cast<double>(c) / static_cast<double>(count));
      };
    }
    try {
      ce.result = estimate_mlce(channel_subset(series, {c}), o);
      ++result.estimated;
    } catch (const InputError& e) {  // this channel cannot be estimated: recorded, the others go on
      ce.error = e.what();
      if (first_error.empty()) first_error = ce.name + ": " + e.what();
    }
    result.channels.push_back(std::move(ce));
  }
  if (result.estimated == 0) throw InputError("no channel could be estimated; " + first_error);

  // The verdict: do the 95 % intervals share a part (up to the resolution of the estimates)? Over
  // the channels whose lambda measures a divergence: an estimate that says it does not
  // (MlceResult::unreliable: a curve that plateaus within one embedding window as noise does, a
  // drift, a wrapped angle, an embedding window of several periods) has no exponent to compare, and
  // a constrained coordinate's rounding noise (34 1/s) would otherwise make every run "disagree".
  std::vector<const MlceResult*> estimates;
  std::vector<const ChannelEstimate*> of;
  for (const auto& ce : result.channels) {
    if (!ce.result) {
      result.warnings.push_back(ce.name + " could not be estimated: " + ce.error);
    } else if (!ce.result->unreliable.empty()) {
      result.warnings.push_back(ce.name + " is left out of the comparison, its lambda does not measure a divergence: " +
                                ce.result->unreliable);
    } else {
      estimates.push_back(&*ce.result), of.push_back(&ce);
    }
  }
  result.compared = estimates.size();
  result.verdict = judge_agreement(estimates, options.relative_tolerance, options.frequency_tolerance);
  const Agreement& v = result.verdict;
  if (result.estimated < 2) {
    result.warnings.push_back("only one channel could be estimated: there is nothing to compare it with");
  } else if (result.compared < 2) {
    result.warnings.push_back(fmt::format("{} of the {} estimated channels measure a divergence: there is nothing to "
                                          "compare", result.compared, result.estimated));
  } else if (!v.agree) {
    const MlceResult& a = *estimates[v.highest_low];
    const MlceResult& b = *estimates[v.lowest_high];
    result.warnings.push_back(fmt::format(
        "the channels disagree: {} reads {:.6g} (95 % interval {:.6g} .. {:.6g}) and {} reads {:.6g} ({:.6g} .. {:.6g}), "
        "{:.3g} apart, beyond the resolution {:.3g}; a channel that stands apart may carry a start-up transient, a noise "
        "floor or too few periods of the motion, or, for a decay, not see the least damped mode",
        of[v.highest_low]->name, a.lambda, a.ci95_low, a.ci95_high, of[v.lowest_high]->name, b.lambda, b.ci95_low,
        b.ci95_high, v.gap, v.tolerance_floor));
  }
  if (options.estimate.progress) options.estimate.progress("done", 1.0);
  return result;
}

}  // namespace mlce
