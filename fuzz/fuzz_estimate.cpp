// libFuzzer: the whole automatic estimator (estimate_mlce, then read_stability) on arbitrary short
// series. The parsers' targets check that no file crashes a reader; this one checks what a series
// that passed the readers can do to the estimator: quantised, constant stretches, repeated points,
// amplitudes from subnormal to near DBL_MAX, an offset far above the motion, a window of another
// record, every parameter automatic or set small by hand. The contract: either InputError /
// OptionError (one message, no result), or a result whose lambda, per-sample lambda and 95 %
// interval are numbers (never NaN, never log 0) and whose curve holds no NaN, read without throwing;
// Cao's E, E1 and E2 of the same series (mlce fnn --method cao) numbers too, or a clear error, and so
// Kantz's curves with the estimate's parameters (mlce kantz), and the record's damped modes (mlce modes);
// the isolated spikes the command line refuses or replaces lie where their definition puts them;
// the surrogate test's slopes are numbers (byte 3's bit 2: the test on every estimate).
//
// Input layout: byte 0 picks the options, byte 1 the scale (a power of two, 2^-1074 .. 2^1016),
// byte 2 an offset in units of the scale, byte 3 the channel count, the time step and when the
// surrogate test runs; the rest are the samples, int16 little-endian, channel after channel within
// a row.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/fnn.hpp"
#include "mlce/kantz.hpp"
#include "mlce/modes.hpp"
#include "mlce/reading.hpp"
#include "mlce/series.hpp"

namespace {

[[noreturn]] void broken(const char* what) {
  // A broken contract is a crash for libFuzzer: it keeps the input that did it.
  (void)std::fprintf(stderr, "fuzz_estimate: %s\n", what);
  std::abort();
}

bool number(double x) { return !std::isnan(x); }

/// Cao's E, E1, E2 (mlce fnn --method cao) on the same series: numbers, or one clear error.
void check_cao(const mlce::Series& series, std::size_t delay, std::size_t theiler) {
  mlce::CaoOptions c;
  c.max_dim = 4, c.theiler = theiler, c.max_queries = 500;
  try {
    const auto r = mlce::estimate_dimension_cao(series, delay, c);
    for (const auto* v : {&r.e, &r.e1, &r.e2})
      if (std::any_of(v->begin(), v->end(), [](double x) { return !number(x); })) broken("Cao's E, E1 or E2 is NaN");
  } catch (const mlce::InputError&) {
  } catch (const mlce::OptionError&) {
  }
}

/// Kantz's curves (mlce kantz) with the estimate's parameters: numbers, or one clear error.
void check_kantz(const mlce::Series& series, const mlce::MlceResult& estimate) {
  mlce::KantzOptions k;
  // Two radii over few references: the curves, not their precision, are what is checked, and the
  // fuzzer's time goes to many inputs (from the four seeds in 20 s, a local ASan build: 80 inputs with
  // four radii over 200 references, 121 with these).
  k.radius_count = 2, k.max_references = 100, k.max_neighbours = 8;
  try {
    const auto r = mlce::estimate_kantz(series, estimate, k);
    if (!number(r.lambda) || !number(r.lambda_low) || !number(r.lambda_high)) broken("Kantz's lambda is NaN");
    for (const auto& radius : r.radii) {
      if (!number(radius.ci95_low) || !number(radius.ci95_high)) broken("a Kantz interval is NaN");
      for (const double y : radius.kantz.curve.mean_log_distance)
        if (!number(y)) broken("a Kantz curve holds a NaN");
    }
  } catch (const mlce::InputError&) {
  }
}

/// The modes' identification as the fuzzer runs it (mlce modes, and the estimate's record modes): the
/// fuzzer's time goes to many inputs, not to one large pencil, and to the interval's code path (noise
/// model, replicates), not its precision. With the defaults (160 columns, 100 replicates) one input of 500
/// samples took 6 min in this instrumented build (0.35 s in a release build): libFuzzer's 10 s timeout
/// failed the CI run of b182cf6.
mlce::ModalOptions quick_modes() {
  mlce::ModalOptions m;
  m.max_columns = 40, m.max_rows = 400, m.interval_replicates = 4;
  return m;
}

/// The record's damped modes (mlce modes): numbers, or one clear error.
void check_modes(const mlce::Series& series) {
  try {
    const auto r = mlce::identify_modes(series, quick_modes());
    if ((r.lambda && !number(*r.lambda)) || !number(r.residual)) broken("the modes' lambda or residual is NaN");
    if (!number(r.lambda_spread) || (r.lambda_low && !(number(*r.lambda_low) && number(*r.lambda_high))))
      broken("the modes' interval holds a NaN");
    if (r.lambda_low && !(*r.lambda_low <= *r.lambda && *r.lambda <= *r.lambda_high)) broken("lambda outside its interval");
    for (const auto& m : r.modes)
      if (!number(m.sigma) || !number(m.frequency) || !number(m.share) || !number(m.peak_share)) broken("a mode holds a NaN");
  } catch (const mlce::InputError&) {
  }
}

/// Isolated spikes (what the command line refuses or, with --despike, replaces where it reads a
/// record): inside the record by the margin, at most max_length long, and replaced by finite
/// samples on the line between their neighbours.
void check_spikes(const mlce::Series& series) {
  const mlce::SpikeOptions o;
  const auto spikes = mlce::find_isolated_spikes(series, o);
  for (const auto& s : spikes)
    if (s.first < o.max_length + 1 || s.last + o.max_length + 1 >= series.size() || s.last < s.first ||
        s.last - s.first >= o.max_length || !(s.jump_ratio > o.jump_ratio))
      broken("an isolated spike outside its definition");
  mlce::Series replaced = series;
  if (mlce::replace_isolated_spikes(replaced, o).size() != spikes.size()) broken("a spike found but not replaced");
  for (const auto& s : spikes)
    for (std::size_t i = s.first; i <= s.last; ++i) {
      const double v = replaced.channels[s.channel][i];
      const double lo = std::min(s.before, s.after), hi = std::max(s.before, s.after);
      const double rounding = 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(lo), std::abs(hi)) +
                              std::numeric_limits<double>::denorm_min();
      if (!std::isfinite(v) || v < lo - rounding || v > hi + rounding)
        broken("a replaced spike is not on the line between its neighbours");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4) return 0;
  const std::uint8_t pick = data[0], scale_byte = data[1], offset_byte = data[2], layout = data[3];
  const std::size_t channels = 1 + (layout & 1u);
  const double dt = (layout & 2u) ? 0.01 : 1.0;
  // 2^-1074 (the smallest subnormal) .. 2^1016: samples of |int16| <= 2^15 then stay below DBL_MAX.
  const double scale = std::ldexp(1.0, -1074 + static_cast<int>(scale_byte) * 2090 / 255);
  const double offset = scale * 32768.0 * static_cast<double>(static_cast<int>(offset_byte) - 128) / 8.0;
  const std::size_t rows = std::min<std::size_t>((size - 4) / (2 * channels), 3000);
  std::vector<std::vector<double>> samples(channels, std::vector<double>(rows));
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t c = 0; c < channels; ++c) {
      std::int16_t v = 0;
      std::memcpy(&v, data + 4 + 2 * (i * channels + c), 2);
      samples[c][i] = offset + scale * static_cast<double>(v);
    }

  mlce::MlceOptions o;
  static constexpr std::size_t kSmall[] = {1, 2, 3, 7};
  if (pick & 1u) o.delay = kSmall[(pick >> 1) & 3u];
  if (pick & 8u) o.dim = kSmall[(pick >> 4) & 3u];
  if (pick & 32u) o.theiler = kSmall[(pick >> 1) & 3u] - 1;
  if (pick & 64u) o.horizon = 2 + ((pick >> 2) & 15u);
  if (pick & 128u) o.record_deviation.assign(channels, std::abs(offset) + 1000.0 * scale);  // a window of a larger record
  o.max_references = 500;  // the fuzzer's time goes to many inputs, not to one long curve
  o.record_modes = quick_modes();
  // The surrogate test where the curve reads chaos (the default) or on every estimate: 3 surrogates
  // of 5 passes, few references (its arithmetic, not its power, is what is checked, and the fuzzer's
  // time goes to many inputs).
  o.surrogates_when = (layout & 4u) ? mlce::SurrogateWhen::always : mlce::SurrogateWhen::where_chaos_is_read;
  o.surrogates = mlce::SurrogateOptions{.count = 3, .iterations = 5, .max_samples = 1024, .max_references = 200};
  try {
    const auto series = mlce::make_series_with_step(std::move(samples), dt);
    check_spikes(series);
    check_cao(series, o.delay.value_or(1), o.theiler.value_or(0));
    check_modes(series);
    const auto r = mlce::estimate_mlce(series, o);
    if (!number(r.lambda) || !number(r.lambda_per_sample)) broken("lambda is NaN");
    if (!number(r.ci95_low) || !number(r.ci95_high)) broken("the 95 % interval is NaN");
    for (const double y : r.curve.mean_log_distance)
      if (!number(y)) broken("the divergence curve holds a NaN");
    if (const auto& m = r.record_modes) {  // identified where the curve cannot tell
      if (!number(m->lambda) || !number(m->residual) || m->residual < 0.0) broken("the record's modes hold a NaN");
      if (m->describes_record() && !(m->ci95_low <= m->lambda && m->lambda <= m->ci95_high))
        broken("the record's modes' interval does not hold their lambda");
    }
    if (const auto& t = r.surrogates) {  // slopes are numbers; sigmas may be +-inf (equal surrogates)
      if (!number(t->series_slope) || !number(t->p_value) || !number(t->sigmas)) broken("the surrogate test holds a NaN");
      for (const double slope : t->surrogate_slopes)
        if (!number(slope)) broken("a surrogate's slope is NaN");
      if (t->first_sample + t->samples > t->of_samples || t->surrogate_slopes.size() != 3)
        broken("the surrogate test ran on what it was not given");
    }
    (void)mlce::read_stability(r);
    check_kantz(series, r);
  } catch (const mlce::InputError&) {
  } catch (const mlce::OptionError&) {
  }
  return 0;
}
