#include "mlce/recurrence.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "mlce/neighbours.hpp"
#include "mlce/numerics.hpp"

namespace mlce {

void RecurrenceOptions::validate() const {
  if (!(transient > 0.0 && transient <= first_below && first_below <= recurrent && recurrent <= 1.0))
    throw OptionError("recurrence: expected 0 < transient <= first_below <= recurrent <= 1");
  if (!(far > 1.0)) throw OptionError("recurrence.far: expected > 1 (a ratio to the typical distance)");
  if (typical_points == 0) throw OptionError("recurrence.typical_points: expected >= 1");
  if (!std::isfinite(repeat_distance))
    throw OptionError("recurrence.repeat_distance: expected a finite distance (negative = off)");
}

namespace {

/// The distance test of RecurrenceOptions::far on windows [w W, (w + 1) W), w < windows. The
/// typical distance is measured from points at least a Theiler window before the second half, as
/// every judged window lies (a point just before it would find its own continuation).
void judge_by_distance(const DelayEmbedding& embedding, std::size_t admissible, std::size_t theiler, std::size_t windows,
                       const RecurrenceOptions& options, RecurrenceResult& r) {
  const std::size_t A = std::min(admissible, embedding.size()), half = A / 2;
  if (half <= theiler || windows == 0) return;
  const RangeIndex second_half(embedding, half, A - half);  // one tree for every window asked
  const double typical = median(second_half.distances(strided_indices(half - theiler, options.typical_points)));
  if (!(typical > 0.0)) return;  // repeated points: no scale to compare with
  std::size_t far_windows = 0;
  bool joins = false;  // a window comes near the second half: the motion has joined what recurs
  for (std::size_t w = 0; w < windows && (w + 1) * r.window <= half; ++w) {
    std::vector<std::uint32_t> points(r.window);
    for (std::size_t i = 0; i < r.window; ++i) points[i] = static_cast<std::uint32_t>(w * r.window + i);
    const double ratio = median(second_half.distances(points)) / typical;
    r.distance_ratio.push_back(ratio);
    if (ratio < options.far) {
      joins = true;
      break;
    }
    ++far_windows;
  }
  // Every window judged far: no window joins what recurs, nothing to tell a start-up by, and nothing
  // is cut (as with the scores). Only possible when the windows cover less than half of the first
  // half: the typical distance is the first half's median. A drift moves that median with it, and
  // its windows' ratios stay ~1.
  if (joins && far_windows > 0) r.start = far_windows * r.window, r.by_distance = true;
}

}  // namespace

RecurrenceResult recurrent_start(const NeighbourPairs& pairs, std::size_t admissible, const RecurrenceOptions& options,
                                 const DelayEmbedding* embedding) {
  options.validate();
  RecurrenceResult r;
  const std::size_t A = admissible, theiler = pairs.theiler;
  r.window = options.window ? options.window : std::max<std::size_t>({1, 2 * theiler, A / 50});  // never 0
  const auto& refs = pairs.references;
  const auto& nn = pairs.nearest.neighbour;
  const auto& distance = pairs.nearest.distance;
  const auto& repeated = pairs.nearest.repeated;  // may be empty: not known
  if (nn.size() != refs.size() || distance.size() != refs.size() || (!repeated.empty() && repeated.size() != refs.size()))
    throw std::invalid_argument(fmt::format("recurrent_start: {} references, {} neighbours, {} distances and {} repeat "
                                            "flags; expected one neighbour and one distance per reference, and one "
                                            "flag each or none",
                                            refs.size(), nn.size(), distance.size(), repeated.size()));
  std::size_t last_transient_end = 0, transient_windows = 0;
  bool joined = false;  // a window has scored `recurrent`
  std::size_t k = 0;  // references are in increasing sample order
  for (std::size_t a = 0; a + r.window + theiler <= A / 2; a += r.window) {
    const std::size_t end = a + r.window, after = end + theiler;
    std::size_t count = 0, later = 0;
    for (; k < refs.size() && refs[k] < end; ++k) {
      if (nn[k] == NeighbourResult::none) continue;
      ++count;
      const double nearest = !repeated.empty() && repeated[k] != 0 ? 0.0 : distance[k];  // an exact repeat: 0
      later += nn[k] >= after || nearest <= options.repeat_distance;
    }
    if (count == 0 || count < options.min_references) break;
    const double expected = static_cast<double>(A - after) / static_cast<double>(A);
    const double ratio = static_cast<double>(later) / static_cast<double>(count) / expected;
    r.ratio.push_back(ratio);
    if (r.ratio.size() == 1 && ratio >= options.first_below) joined = true;  // starts on the attractor
    if (!joined && ratio >= options.recurrent)
      joined = true, r.start = transient_windows >= options.min_windows ? last_transient_end : 0;
    if (!joined && ratio < options.transient) last_transient_end = end, ++transient_windows;
  }
  if (embedding != nullptr && r.start == 0 && !r.ratio.empty() && r.ratio.front() < options.first_below)
    judge_by_distance(*embedding, A, theiler, r.ratio.size(), options, r);
  return r;
}

NeighbourDrift neighbour_drift(const Series& series, const NeighbourPairs& pairs) {
  NeighbourDrift d;
  const auto& refs = pairs.references;
  const auto& nn = pairs.nearest.neighbour;
  if (nn.size() != refs.size() || pairs.nearest.distance.size() != refs.size())
    throw std::invalid_argument("neighbour_drift: expected one neighbour and one distance per reference");
  const std::vector<double> divisor = unit_deviation_divisors(series);
  const std::size_t C = series.channel_count(), m = pairs.dim, J = pairs.delay, n = series.size();
  std::vector<CompensatedSum> moment(C);  // sum_q s_qc Delta_q, per channel
  CompensatedSum lag_squares, distance_squares;
  for (std::size_t q = 0; q < refs.size(); ++q) {
    const std::size_t j = refs[q], k = nn[q];
    if (nn[q] == NeighbourResult::none || j + (m - 1) * J >= n || k + (m - 1) * J >= n) continue;
    const double lag = static_cast<double>(k) - static_cast<double>(j);
    for (std::size_t c = 0; c < C; ++c) {
      const auto& x = series.channels[c];
      double s = 0.0;
      // Each sample over its divisor first, as the search's coordinates: no difference of two huge
      // values of opposite sign overflows.
      for (std::size_t i = 0; i < m; ++i) s += x[k + i * J] / divisor[c] - x[j + i * J] / divisor[c];
      moment[c].add(s / static_cast<double>(m) * lag);
    }
    lag_squares.add(lag * lag);
    distance_squares.add(pairs.nearest.distance[q] * pairs.nearest.distance[q]);
    ++d.pairs;
  }
  if (d.pairs == 0 || !(lag_squares.value() > 0.0) || !(distance_squares.value() > 0.0)) return d;
  double largest = -1.0;
  for (std::size_t c = 0; c < C; ++c) {
    const double a = moment[c].value() / lag_squares.value();  // unit deviations per sample
    const double part = static_cast<double>(m) * a * a * lag_squares.value() / distance_squares.value();
    d.share += part;
    if (part > largest) {
      largest = part;
      d.channel = c;
      d.rate_per_sample = a * divisor[c];
      d.over_run_in_deviations = a * static_cast<double>(n);  // the coordinates are in deviations
    }
  }
  d.share = std::min(d.share, 1.0);  // the regression's part of the distances cannot exceed them
  return d;
}

}  // namespace mlce
