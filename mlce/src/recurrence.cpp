#include "mlce/recurrence.hpp"

#include <algorithm>

#include "mlce/numerics.hpp"

namespace mlce {

void RecurrenceOptions::validate() const {
  if (!(transient > 0.0 && transient <= first_below && first_below <= recurrent && recurrent <= 1.0))
    throw OptionError("recurrence: expected 0 < transient <= first_below <= recurrent <= 1");
}

RecurrenceResult recurrent_start(const NeighbourPairs& pairs, std::size_t admissible, const RecurrenceOptions& options) {
  options.validate();
  RecurrenceResult r;
  const std::size_t A = admissible, theiler = pairs.theiler;
  r.window = options.window ? options.window : std::max<std::size_t>({1, 2 * theiler, A / 50});  // never 0
  const auto& refs = pairs.references;
  const auto& nn = pairs.nearest.neighbour;
  std::size_t last_transient_end = 0, transient_windows = 0;
  bool joined = false;  // a window has scored `recurrent`
  std::size_t k = 0;  // references are in increasing sample order
  for (std::size_t a = 0; a + r.window + theiler <= A / 2; a += r.window) {
    const std::size_t end = a + r.window, after = end + theiler;
    std::size_t count = 0, later = 0;
    for (; k < refs.size() && refs[k] < end; ++k) {
      if (nn[k] == NeighbourResult::none) continue;
      ++count;
      later += nn[k] >= after;
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
  return r;
}

}  // namespace mlce
