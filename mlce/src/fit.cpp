#include "mlce/fit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "mlce/numerics.hpp"

namespace mlce {
namespace {

/// Prefix sums giving the least-squares SSE of any straight piece [a, b] in O(1).
class PieceCost {
 public:
  explicit PieceCost(const std::vector<double>& y) : n_(y.size()) {
    long double mean = 0;
    for (double v : y) mean += v;
    mean /= static_cast<long double>(n_);
    sx_.assign(n_ + 1, 0), sxx_ = sx_, sy_ = sx_, sxy_ = sx_, syy_ = sx_;
    for (std::size_t i = 0; i < n_; ++i) {
      const long double x = i, v = y[i] - mean;
      sx_[i + 1] = sx_[i] + x;
      sxx_[i + 1] = sxx_[i] + x * x;
      sy_[i + 1] = sy_[i] + v;
      sxy_[i + 1] = sxy_[i] + x * v;
      syy_[i + 1] = syy_[i] + v * v;
    }
  }
  double sse(std::size_t a, std::size_t b) const {  // inclusive
    const long double k = b - a + 1;
    const long double sx = sx_[b + 1] - sx_[a], sxx = sxx_[b + 1] - sxx_[a];
    const long double sy = sy_[b + 1] - sy_[a], sxy = sxy_[b + 1] - sxy_[a], syy = syy_[b + 1] - syy_[a];
    const long double cxx = sxx - sx * sx / k, cxy = sxy - sx * sy / k, cyy = syy - sy * sy / k;
    const long double e = cxx > 0 ? cyy - cxy * cxy / cxx : cyy;
    return static_cast<double>(std::max<long double>(0, e));
  }

 private:
  std::size_t n_;
  std::vector<long double> sx_, sxx_, sy_, sxy_, syy_;
};

struct Piece {
  std::size_t a, b;
  double slope;
};

std::vector<Piece> segment_exact(const std::vector<double>& y, std::size_t pieces, std::size_t min_len);

/// Optimal segmentation of y into at most `pieces` straight pieces of at least `min_len` points
/// (least squares, dynamic programming over the breakpoints: O(pieces * n^2)). Curves longer than
/// 2048 steps are segmented on means of blocks of ceil(n / 1024) steps (breakpoints to a block,
/// cost O(pieces * 1024^2)); the pieces' slopes are then fitted on the full curve.
std::vector<Piece> segment(const std::vector<double>& y, std::size_t pieces, std::size_t min_len) {
  const std::size_t n = y.size();
  if (n <= 2048) return segment_exact(y, pieces, min_len);
  const std::size_t block = (n + 1023) / 1024, m = (n + block - 1) / block;
  std::vector<double> coarse(m, 0.0);
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t a = k * block, b = std::min(n, a + block);
    double sum = 0.0;
    for (std::size_t i = a; i < b; ++i) sum += y[i];
    coarse[k] = sum / static_cast<double>(b - a);
  }
  auto out = segment_exact(coarse, pieces, std::max<std::size_t>(3, (min_len + block - 1) / block));
  for (auto& p : out) {
    p.a *= block;
    p.b = std::min(n - 1, (p.b + 1) * block - 1);
    p.slope = fit_line(y.data(), p.a, p.b).slope;
  }
  return out;
}

std::vector<Piece> segment_exact(const std::vector<double>& y, std::size_t pieces, std::size_t min_len) {
  const std::size_t n = y.size();
  const PieceCost cost(y);
  auto slope_of = [&](std::size_t a, std::size_t b) { return fit_line(y.data(), a, b).slope; };
  const std::size_t K = std::max<std::size_t>(1, std::min(pieces, n / min_len));
  constexpr double inf = std::numeric_limits<double>::infinity();
  // best[k][e]: least SSE of the first e points in k+1 pieces; from[k][e]: start of the last piece.
  std::vector<std::vector<double>> best(K, std::vector<double>(n + 1, inf));
  std::vector<std::vector<std::size_t>> from(K, std::vector<std::size_t>(n + 1, 0));
  for (std::size_t e = min_len; e <= n; ++e) best[0][e] = cost.sse(0, e - 1);
  // Every layer but the last is needed at every end point; the last only at e = n (the whole
  // curve), which makes it O(n) instead of O(n^2): a third to a half of the cost.
  for (std::size_t k = 1; k < K; ++k)
    for (std::size_t e = k + 1 == K ? n : (k + 1) * min_len; e <= n; ++e)
      for (std::size_t s = k * min_len; s + min_len <= e; ++s) {
        if (best[k - 1][s] == inf) continue;
        const double c = best[k - 1][s] + cost.sse(s, e - 1);
        if (c < best[k][e]) best[k][e] = c, from[k][e] = s;
      }
  std::size_t k = K - 1;
  while (k > 0 && best[k][n] == inf) --k;
  std::vector<Piece> out;
  for (std::size_t e = n;; --k) {
    const std::size_t s = k == 0 ? 0 : from[k][e];
    out.insert(out.begin(), Piece{s, e - 1, slope_of(s, e - 1)});
    if (k == 0) break;
    e = s;
  }
  return out;
}

bool same_line(const Piece& p, const Piece& q, double tol) {
  const double scale = std::max(std::abs(p.slope), std::abs(q.slope));
  return std::abs(p.slope - q.slope) <= tol * scale;
}

/// Joins neighbouring pieces that are one line (no transient, or no plateau).
std::vector<Piece> merge_collinear(std::vector<Piece> pieces, const std::vector<double>& y, double tol) {
  for (std::size_t k = 0; k + 1 < pieces.size();) {
    if (same_line(pieces[k], pieces[k + 1], tol)) {
      pieces[k].b = pieces[k + 1].b;
      pieces[k].slope = fit_line(y.data(), pieces[k].a, pieces[k].b).slope;
      pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(k) + 1);
      if (k > 0) --k;  // the merged piece has a new slope: compare it with its left neighbour again
    } else {
      ++k;
    }
  }
  return pieces;
}

/// Rule 0b: the curve stays bounded_margin below the attractor scale, starts in the lower half of
/// its range (nearest neighbours start closer than they later are: no decay, which starts at the
/// top) and rises from its start by at most max_rise (more is an exponential divergence that
/// saturates short of the attractor scale, as within the bands of a banded map). It is bounded when it has settled, over its second half its least-squares line changing
/// by less than 0.25 or by less than 0.4 of the curve's range (a straight rise changes by half of it
/// there), or when it falls back over its second half by more than that: a growth saturates at the
/// attractor scale and never falls; a limit cycle that has not fully settled does (its neighbours
/// drift apart by the search's selection bias, then close in again as the residual decaying mode dies
/// out: Hammond at 240 rpm, blade 3 inoperative, rose by 1.3 and fell by 0.7 over 25 s).
enum class Bounded { no, settled, falls_back, returns };
/// A curve that comes back down to its start level swings about a level when the least-squares line
/// over its swings changes by at most this share of its rise (bounded_kind).
constexpr double kReturnDrift = 0.5;

/// The last step at which the curve is at or below `level` (0 when none is).
std::size_t last_at_or_below(const std::vector<double>& y, double level) {
  std::size_t last = y.size() - 1;
  while (last > 0 && y[last] > level) --last;
  return last;
}

/// `back`: for Bounded::returns, the curve's last return to its start level (the fit's last step).
Bounded bounded_kind(const std::vector<double>& y, double attractor, const FitOptions& options, std::size_t& back) {
  const double margin = options.bounded_margin, max_rise = options.bounded_max_rise;
  const std::size_t n = y.size(), half = n / 2;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  if (y[0] > 0.5 * (*lo + *hi) || *hi - y[0] > max_rise) return Bounded::no;
  if (std::isfinite(attractor) && *hi < attractor - margin) {
    const double late = fit_line(y.data(), half, n - 1).slope * static_cast<double>(n - 1 - half);
    const double tolerance = std::max(0.25, 0.4 * (*hi - *lo));
    if (std::abs(late) < tolerance) return Bounded::settled;
    if (late < 0.0) return Bounded::falls_back;
  }
  // A curve that comes back down to its start level after its highest point (FitOptions::bounded_return),
  // however near the attractor scale it rose and whatever its second half does: divergence saturates
  // and stays; pairs of a periodic motion at a phase offset part and close again, every half period.
  // Fitted over its whole swings, from its first step to its last return to that level. Not on a
  // signal that decayed into a floor of its own (signal_floor: build/noisy_decays short's two-mode
  // decays at 3 % noise read 0.15 and 0.31 of the slow mode's rate, neutral, as bounded), nor when the
  // signal's own amplitude decays at least persist_share x as fast as that fit falls (signal_rate):
  // the swings then ride on a decay (Hammond's airframe at 124 rpm, blade 3 inoperative, 2-12 s: the
  // curve swings by 1.4 every 150 steps and falls at the signal's rate beneath). Nor when that fit
  // drifts over the swings by more than kReturnDrift of the rise: a trend beneath swings is a rate
  // (the noise-compensated curves of build/noisy_decays' zeta = 0.05, 3 % noise, whose envelope rate
  // is unknown: a fall of 1.2 rises over 153 steps; the periodic records' 0.17-0.38).
  // The level it comes back down to: its first step's plus bounded_return of its rise.
  back = last_at_or_below(y, y[0] + options.bounded_return * (*hi - y[0]));
  if (!(options.bounded_return > 0.0) || back <= static_cast<std::size_t>(hi - y.begin())) return Bounded::no;
  const double trend = fit_line(y.data(), std::size_t{0}, back).slope;
  const bool decay = options.signal_floor ||
                     (trend < 0.0 && std::isfinite(options.signal_rate) && options.signal_rate <= options.persist_share * trend);
  const bool drifts = std::abs(trend) * static_cast<double>(back) > kReturnDrift * (*hi - y[0]);
  return decay || drifts ? Bounded::no : Bounded::returns;
}

/// The piece of largest |slope| x length (the change it explains).
std::size_t pick_largest_change(const std::vector<Piece>& pieces) {
  std::size_t pick = 0;
  double best_change = -1.0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const double change = std::abs(pieces[k].slope) * static_cast<double>(pieces[k].b - pieces[k].a);
    if (change > best_change) best_change = change, pick = k;
  }
  return pick;
}

void describe(std::ostringstream& rule, const char* stage, const std::vector<Piece>& pieces) {
  rule << stage << " [";
  for (std::size_t k = 0; k < pieces.size(); ++k)
    rule << (k ? ", " : "") << pieces[k].a << ".." << pieces[k].b << " slope " << pieces[k].slope;
  rule << "]";
}

/// The slopes of the region's two halves, [first, mid] and [mid, last] (they share mid): how
/// straight it is (the straightness trim and the bend warning).
struct HalfSlopes {
  std::size_t mid;
  double first, second;
};
HalfSlopes half_slopes(const std::vector<double>& y, std::size_t first, std::size_t last) {
  const std::size_t mid = first + (last - first) / 2;
  return {mid, fit_line(y.data(), first, mid).slope, fit_line(y.data(), mid, last).slope};
}

/// Stage 2 of the rule (fit.hpp): the linear region of y[0..stop], the part before the plateau or
/// floor that stage 1 found (r.end, r.end_index); sets r.first and r.last and accounts in `rule`.
void choose_linear_region(const std::vector<double>& y, std::size_t stop, std::size_t min_len,
                          const FitOptions& options, FitResult& r, std::ostringstream& rule) {
  // Stage 2: before that end, split off a start-up transient and the bend into the end.
  std::vector<double> head(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(stop) + 1);
  auto inner = merge_collinear(segment(head, options.pieces, min_len), head, options.merge_tolerance);
  // A first piece steeper than the next and no longer than it is the start-up transient
  // (neighbour separations still aligning with the unstable direction): it is never the linear
  // region. "No longer", not "shorter": when the start-up lasts one shortest piece and the
  // linear region bends early, the next piece is a shortest piece too (Lorenz x from (0.1, 0, 0)
  // after 10 time units: both 83 steps; the start-up was fitted and read 2.2 lambda_1).
  // Nor when it is shorter than a mean period, however short the next (a region is at least
  // min_periods long): Lorenz (x, y, z) embedded jointly starts up over ~0.5 time units at ~3
  // lambda_1, then bends within 40 steps into a straight stretch of 3 periods; the bend was taken
  // for the one into the plateau, and 5 of 32 such series read the start-up, 2.4-3.0 lambda_1
  // (`build/finite_time_spread channels`, "embedded jointly"; every other section unchanged).
  std::size_t skip = 0;
  if (inner.size() > 1 && std::abs(inner[0].slope) > std::abs(inner[1].slope) &&
      (inner[0].b - inner[0].a <= inner[1].b - inner[1].a || inner[0].b - inner[0].a + 1 < options.period))
    skip = 1;
  // A start-up piece longer than two periods is the start-up and the linear region's beginning
  // merged by a segmentation of a long span (Roessler x whose 3-piece stage finds the plateau 1200
  // steps on, periods 57: a first piece 0..201 at 1.13 lambda_1, skipped, and the fit landed in the
  // flattening at 0.77). It is split in two the same way: when its first part is the steeper, that
  // part alone is the start-up and the second is a candidate (`build/finite_time_spread starts`,
  // Roessler x within 5 % / 10 %: 75 / 111 -> 78 / 114 of 128; Lorenz x, maps and the studies'
  // decays unchanged). Growths only: the rule was measured on them.
  bool split = false;
  const std::size_t start_length = inner.empty() ? 0 : inner[0].b - inner[0].a + 1;
  if (skip && r.end == CurveEnd::saturation && start_length > 2 * std::max<std::size_t>(1, options.period) &&
      start_length >= 2 * min_len) {
    const std::vector<double> start(y.begin() + static_cast<std::ptrdiff_t>(inner[0].a),
                                    y.begin() + static_cast<std::ptrdiff_t>(inner[0].b) + 1);
    auto parts = merge_collinear(segment(start, 2, min_len), start, options.merge_tolerance);
    if (parts.size() == 2 && std::abs(parts[0].slope) > std::abs(parts[1].slope)) {
      for (auto& p : parts) p.a += inner[0].a, p.b += inner[0].a;
      inner.erase(inner.begin());
      inner.insert(inner.begin(), parts.begin(), parts.end());
      split = true;
    }
  }
  std::vector<Piece> candidates(inner.begin() + static_cast<std::ptrdiff_t>(skip), inner.end());
  // A curve that grows into a saturation plateau bends into it only by flattening: a later
  // piece less than bend_ratio x as steep as the steepest before it is the bend, however long
  // (a short series' curve has no straight stretch, and its slow tail can be longer than its
  // linear part: Lorenz x at N = 5000 read 0.40 lambda_1 on such a tail). Not for a decay: its
  // slowest piece is the least negative exponent, the one wanted.
  std::size_t bend_start = stop + 1;  // where the bend into the plateau starts
  if (options.bend_ratio > 0.0 && r.end == CurveEnd::saturation) {
    double steepest = 0.0;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      if (steepest > 0.0 && candidates[k].slope < options.bend_ratio * steepest) {
        bend_start = candidates[k].a;
        candidates.resize(k);  // k >= 1: the piece that set `steepest` stays
        break;
      }
      steepest = std::max(steepest, candidates[k].slope);
    }
  }
  std::size_t pick = skip + pick_largest_change(candidates);
  // An earlier piece of the same sign, at least as steep and at least a period long is the
  // linear region: the bend into the plateau only ever lowers the slope, so the largest-change
  // piece of a curve that bends gradually (Roessler) reaches into the bend.
  const std::size_t largest = pick;
  for (std::size_t k = skip; k < largest; ++k)
    if (inner[k].b - inner[k].a + 1 >= 2 * min_len && inner[k].slope * inner[largest].slope > 0.0 &&
        std::abs(inner[k].slope) >= std::abs(inner[largest].slope)) {
      pick = k;
      break;
    }
  r.first = inner[pick].a;
  r.last = inner[pick].b;
  // A growth that only flattens from the start-up to the pick (every piece between them steeper):
  // the curve is concave, with no straight stretch, and the pieces before the pick are the same
  // growth, not transient. The pick alone is its flattest part; the region spans them all.
  bool joined = false;
  if (r.end == CurveEnd::saturation && pick == largest && pick > skip && inner[pick].slope > 0.0) {
    const auto from = inner.begin() + static_cast<std::ptrdiff_t>(skip), to = inner.begin() + static_cast<std::ptrdiff_t>(pick) + 1;
    const bool only_flattens =
        std::adjacent_find(from, to, [](const Piece& p, const Piece& q) { return p.slope <= q.slope; }) == to;
    if (only_flattens) r.first = inner[skip].a, joined = true;
  }
  // The curve's first step is part of the start-up when it changes the log distance by less
  // than 0.9 x the second step does: the nearest neighbour's separation still has a component
  // along the contracting directions, which shrinks during that step. A piece cannot be one
  // step long (at least 3), so for maps, which align within an iteration, this is decided here
  // (Henon: the first step rises at ~0.7 lambda, the next ones at lambda).
  bool first_step_skipped = false;
  if (r.first == 0 && r.last >= 3) {
    const double sign = inner[pick].slope >= 0.0 ? 1.0 : -1.0;
    if (sign * (y[1] - y[0]) < 0.9 * sign * (y[2] - y[1])) r.first = 1, first_step_skipped = true;
  }
  // Straightness: while the second half of the region is flatter than straightness x the first
  // half, the region reaches into the bend: keep its first three quarters.
  std::size_t trimmed = 0;
  const double straightness = options.period < kMinFlowPeriod ? options.map_straightness : options.straightness;
  while (r.last - r.first + 1 >= 4 * min_len) {
    const HalfSlopes h = half_slopes(y, r.first, r.last);
    if (std::abs(h.second) >= straightness * std::abs(h.first)) break;
    r.last = r.first + 3 * (r.last - r.first) / 4;
    ++trimmed;
  }
  // At least min_periods periods of a curve that saturates, never into the bend, and not on a
  // curve lifted by measurement noise: a shorter region's slope is the phase of the curve's
  // oscillation as much as growth (FitOptions::min_periods).
  std::size_t extended = 0;
  bool cut_back = false;
  if (r.end == CurveEnd::saturation && options.min_periods > 0.0 &&
      !first_step_jumps(y, fit_line(y.data(), r.first, r.last).slope)) {
    const auto span = static_cast<std::size_t>(std::ceil(options.min_periods * static_cast<double>(options.period)));
    std::size_t last = std::min(bend_start - 1, r.first + span);
    // ... and not into a bend the region did not have: cut back while the extended region's second
    // half rises at less than extension_straightness x its first half's slope. Chua's mean period,
    // set by the slow switching between its scrolls, is long against its curve's rise, and 1.5 of
    // them carried the region into the flattening (FitOptions::extension_straightness).
    if (options.extension_straightness > 0.0 && last > r.last) {
      const auto bends = [&](std::size_t end) {
        const HalfSlopes h = half_slopes(y, r.first, end);
        return h.first > 0.0 && h.second < options.extension_straightness * h.first;
      };
      if (!bends(r.last))
        while (last > r.last && bends(last)) {
          --last;
          cut_back = true;
        }
    }
    if (last > r.last) r.last = extended = last;
  }
  rule << "; ";
  describe(rule, "before the end", inner);
  rule << (split ? "; the first piece, longer than two periods, split in two" : "") << (skip ? "; start-up transient skipped" : "") << (first_step_skipped ? "; slow first step skipped" : "")
       << (pick != largest ? "; fitted the earliest piece a period long and as steep as the one of largest |slope| x length"
                           : "; fitted the piece of largest |slope| x length");
  if (joined) rule << ", joined with the steeper pieces after the start-up (concave growth)";
  if (trimmed) rule << "; its end trimmed " << trimmed << "x (second half flatter than " << straightness << " x the first)";
  if (extended)
    rule << "; extended " << (cut_back ? "toward " : "to ") << options.min_periods << " periods"
         << (cut_back ? " (stopped before the region bends)" : "");
  if (trimmed || extended) rule << ": fitted to step " << r.last;
  if (r.end != CurveEnd::none) rule << "; " << to_string(r.end) << " from step " << r.end_index;
}

/// A fall whose second half is less steep than this fraction of its first half's slows along the
/// curve: a warning names the slopes (modes of different damping, or a floor the signal does not show).
/// Rises get no such warning: their start-up and beats hide the steepening (on build/decay_modes'
/// growths the fitted region's halves differ by 1..22 %, the flatter half second).
constexpr double kSlowingDecay = 0.8;
/// A "floor" piece of a signal without a floor of its own that still falls by more than this (natural
/// log) is a slower mode, not a floor: it is fitted with the fall.
constexpr double kSlowModeFall = 1.0;
/// A signal whose amplitude, at its end, grows by at least this (natural log, e^0.5 = 1.65 x) over the
/// curve's horizon (FitOptions::signal_end_rate x steps) grows on its own: it has no attractor of fixed size for
/// its pairs to saturate on. Chaotic series change by far less (second half's rate x horizon at
/// N = 10^4: Lorenz x 0.08, Roessler x -0.0002, Henon x 0.0002; `mlce estimate --json`,
/// end_envelope_rate x dt x horizon); the multi-mode growths of `build/decay_modes` by 1.6 .. 2.9
/// (it prints them). Fewer than 4 windows of 2 mean periods in the second half: NaN, not applied.
constexpr double kGrowingSignal = 0.5;

/// The late region of y[0..stop]: the last `share` of the change from the curve's extreme point
/// (highest for a fall, lowest for a rise) in its first half to `stop`. nullopt when the change is too
/// short for a region of a period (2 minimum pieces).
struct LateRegion {
  std::size_t start, first;  ///< the extreme point, and the region's first step (it ends at stop)
};
std::optional<LateRegion> late_region(const std::vector<double>& y, std::size_t stop, std::size_t min_len, bool falls,
                                      double share) {
  const auto half_end = y.begin() + static_cast<std::ptrdiff_t>(stop / 2) + 1;
  const auto start = static_cast<std::size_t>(
      (falls ? std::max_element(y.begin(), half_end) : std::min_element(y.begin(), half_end)) - y.begin());
  const auto length = static_cast<std::size_t>(share * static_cast<double>(stop - start));
  if (length + 1 < 2 * min_len) return std::nullopt;
  return LateRegion{start, stop - length};
}

/// Stage 2b/2c for a curve with no plateau or floor to bend into (decays whose curve or signal has no
/// floor, FitOptions::late_decay_share; growths of a signal that grows on its own, late_growth_share):
/// the late region (late_region) ending at `stop`. False, with r untouched, when there is none: the
/// growth rule fits it then. `fall` says in the rule what kind of fall it is.
bool choose_late_region(const std::vector<double>& y, std::size_t stop, std::size_t min_len, bool falls, double share,
                        FitResult& r, std::ostringstream& rule,
                        const char* fall = "a fall with no floor to bend into (none on the curve, or none of the signal's own)") {
  const auto region = late_region(y, stop, min_len, falls, share);
  if (!region) return false;
  const std::size_t start = region->start;
  r.first = region->first;
  r.last = stop;
  if (falls)
    rule << "; " << fall << ": fitted the last " << share
         << " of the fall from the curve's highest point (step " << start << ") to step " << stop
         << ", where the faster modes have died out most";
  else
    rule << "; a rise on a signal whose amplitude grows on its own (no attractor to saturate on): fitted the last "
         << share << " of the rise from the curve's lowest point (step " << start << ") to step " << stop
         << ", where the fastest mode dominates most";
  if (falls && stop - start + 1 >= 4 * min_len) {
    const HalfSlopes h = half_slopes(y, start, stop);
    if (h.first < 0.0 && h.second > kSlowingDecay * h.first)
      r.warnings.push_back(fmt::format(
          "the decay slows along the divergence curve: steps {}..{} fall at {:.3g} per step, steps {}..{} at {:.3g}: "
          "modes of different damping, of which the least damped (the largest exponent) dominates only late, or a "
          "floor the signal does not show; the fit takes the later steps {}..{}, and a longer run resolves the slowest "
          "mode better",
          start, h.mid, h.first, h.mid, stop, h.second, r.first, r.last));
  }
  return true;
}

/// Rule 0: the distances change by less than a factor e^0.25 over the whole curve: lambda ~ 0
/// (limit cycle, quasi-periodic motion). Any sub-region would fit wiggles: the whole curve is fitted.
bool fit_flat(const std::vector<double>& y, FitResult& r, std::ostringstream& rule) {
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  if (*hi - *lo >= 0.25) return false;
  r.first = 0;
  r.last = y.size() - 1;
  r.end = CurveEnd::flat;
  r.end_index = y.size() - 1;
  rule << "flat curve (range " << *hi - *lo << " < 0.25): whole curve fitted";
  return true;
}

/// Rule 0b (bounded_kind). Settled: the second half, whose slope tends to 0 as the horizon grows.
/// Falling back: from where the curve first reached its final level, so that the rise and the fall
/// it fits end at the same level (the second half alone would be the residual decay, not the
/// cycle's 0).
bool fit_bounded(const DivergenceCurve& curve, const FitOptions& options, FitResult& r, std::ostringstream& rule) {
  const auto& y = curve.mean_log_distance;
  const std::size_t n = y.size();
  std::size_t back = n - 1;
  const Bounded kind = n >= 6 ? bounded_kind(y, curve.attractor_log_distance, options, back) : Bounded::no;
  if (kind == Bounded::no) return false;
  // A curve that falls back while the signal's own amplitude decays at least persist_share x as fast
  // is a decay to rest, not a limit cycle closing in again: its early rise is the start-up, and a
  // short record of a slow decay starts low in its range (Hammond at 200 rpm, blade 3 inoperative,
  // 20 s: the curve rose by 0.4 in 0.6 s, then fell at -0.087 1/s with the signal's -0.083; fitted
  // from step 0 it read -0.071). The decay stages fit it.
  const double late_slope = fit_line(y.data(), n / 2, n - 1).slope;
  if (kind != Bounded::settled && late_slope < 0.0 && std::isfinite(options.signal_rate) &&
      options.signal_rate <= options.persist_share * late_slope)
    return false;
  const double highest = *std::max_element(y.begin(), y.end());
  std::size_t first = n / 2, last = n - 1;
  if (kind == Bounded::falls_back) {
    first = 0;
    while (first + 3 < n && y[first] < y[n - 1]) ++first;
  } else if (kind == Bounded::returns) {
    // From the first step to the curve's last return to its start level: whole swings, which start
    // and end at the same level.
    first = 0;
    last = back;
  }
  r.first = first;
  r.last = last;
  r.end = CurveEnd::bounded;
  r.end_index = first;
  rule << "bounded divergence: the curve "
       << (kind == Bounded::settled ? "stops rising" : kind == Bounded::returns ? "comes back down to its start level" : "rises and falls back")
       << " at " << highest << ", " << curve.attractor_log_distance - highest << " below the attractor scale ("
       << (kind == Bounded::returns ? "pairs of a periodic motion at a phase offset part and close again"
                                    : "neighbours never separate: limit cycle or torus")
       << "); "
       << (kind == Bounded::settled  ? "second half fitted"
           : kind == Bounded::returns ? "fitted from the first step to its last return to that level"
                                      : "fitted from where it first reached its final level");
  return true;
}

/// Stage 1's finding: the slope per step of the piece of largest change (< 0 a fall, > 0 a rise)
/// and the last step before the plateau or floor (the curve's last step when there is none).
struct CurveCut {
  double change;
  std::size_t stop;
};

/// Stage 1: where does the curve stop changing (plateau for lambda > 0, floor for lambda < 0)?
/// Sets r.end and r.end_index when it does.
CurveCut cut_curve_end(const std::vector<double>& y, std::size_t min_len, const FitOptions& options, FitResult& r,
                       std::ostringstream& rule) {
  const auto pieces = merge_collinear(segment(y, 3, min_len), y, options.merge_tolerance);
  const std::size_t pick = pick_largest_change(pieces);
  CurveCut cut{pieces[pick].slope, y.size() - 1};
  for (std::size_t k = pick + 1; k < pieces.size(); ++k)
    if (std::abs(pieces[k].slope) < options.end_tolerance * std::abs(pieces[pick].slope)) {
      r.end = pieces[pick].slope > 0 ? CurveEnd::saturation : CurveEnd::floor;
      r.end_index = pieces[k].a;
      cut.stop = pieces[k].a - 1;
      break;
    }
  describe(rule, "curve pieces", pieces);
  return cut;
}

/// Stage 1, a floor the signal itself does not share (FitOptions::signal_rate): the neighbours
/// converge onto a motion that persists; the level the curve settles at is fitted.
bool fit_persisting_level(const std::vector<double>& y, const CurveCut& cut, const FitOptions& options, FitResult& r,
                          std::ostringstream& rule) {
  const bool persists = std::isfinite(options.signal_rate) && options.signal_rate > options.persist_share * cut.change;
  if (r.end != CurveEnd::floor || !persists) return false;
  r.first = r.end_index;
  r.last = y.size() - 1;
  r.end = CurveEnd::bounded;
  rule << "; the curve falls at " << cut.change << " per step, the signal's amplitude changes at " << options.signal_rate
       << " (not " << options.persist_share << " x the fall): the neighbours converge "
       << "onto a motion that persists (limit cycle; lambda_1 >= 0); fitted the level it settles at";
  return true;
}

/// Stage 2b: a decay of a signal with no floor of its own has none to bend into: it flattens as its
/// faster modes die out (FitOptions::signal_floor), and a "floor" that still falls is its slowest
/// mode. A signal with a floor of its own explains a floor of the curve, not a curve that shows
/// none. Measurement noise is such a floor too: it lifts the curve's first step (first_step_jumps),
/// and zero distances (quantisation) are one.
bool fit_late_decay(const DivergenceCurve& curve, const CurveCut& cut, std::size_t min_len, const FitOptions& options,
                    FitResult& r, std::ostringstream& rule) {
  const auto& y = curve.mean_log_distance;
  const std::size_t n = y.size();
  if (!(cut.change < 0.0 && options.late_decay_share > 0.0 && (!options.signal_floor || r.end != CurveEnd::floor) &&
        curve.zero_distance_terms == 0 && !first_step_jumps(y, cut.change)))
    return false;
  const bool slower_mode = r.end == CurveEnd::floor && y[r.end_index] - y[n - 1] > kSlowModeFall;
  if (!choose_late_region(y, slower_mode ? n - 1 : cut.stop, min_len, true, options.late_decay_share, r, rule))
    return false;
  if (slower_mode) {
    rule << "; the flatter fall from step " << r.end_index << " is a slower mode, not a floor (it falls by "
         << y[r.end_index] - y[n - 1] << ")";
    r.end = CurveEnd::none;
    r.end_index = 0;
  }
  if (r.end != CurveEnd::none) rule << "; " << to_string(r.end) << " from step " << r.end_index;
  return true;
}

/// Stage 2b', a noise-compensated curve (DivergenceCurve::compensated_noise_share) that falls: a noisy
/// decay whose noise is taken out. It has no floor left to bend into, and its first step's jump is
/// the neighbour search's selection, not noise (step 0 is the plain mean square), so 2b's bars do not
/// apply: it is fitted late like a decay of several modes (the growth rule's region took short early
/// pieces of a curve that still oscillates, or a faster mode's fall: bench/noisy_decays). But the
/// noise's share of the pairs' mean square grows along the curve, and an error e of its measured level
/// moves y_c by -(e/2) share / (1 - share): the fall ends where that moves the slope by at most
/// noise_slope_error of it.
bool fit_compensated_decay(const DivergenceCurve& curve, const CurveCut& cut, std::size_t min_len,
                           const FitOptions& options, FitResult& r, std::ostringstream& rule) {
  const auto& y = curve.mean_log_distance;
  if (curve.compensated_noise_share.size() != y.size() || !(cut.change < 0.0) || options.late_decay_share <= 0.0)
    return false;
  const std::size_t step = std::max<std::size_t>(1, options.period / 4);
  const std::vector<double> shift = noise_level_shift(curve);  // its slope over a region: noise_level_sensitivity
  std::optional<std::size_t> end;  // the latest end within noise_slope_error, else the least error
  double error_at_end = std::numeric_limits<double>::infinity();
  for (std::size_t last = y.size() - 1;; last -= step) {
    const auto region = late_region(y, last, min_len, true, options.late_decay_share);
    if (!region) break;
    const double slope = fit_line(y.data(), region->first, last).slope;
    if (slope < 0.0) {
      const double error = options.noise_variance_error * std::abs(fit_line(shift.data(), region->first, last).slope) / -slope;
      if (error < error_at_end) end = last, error_at_end = error;
      if (error <= options.noise_slope_error) break;
    }
    if (last < step) break;
  }
  if (!end) return false;
  choose_late_region(y, *end, min_len, true, options.late_decay_share, r, rule,
                     "a noise-compensated fall (the noise floor taken out; the first step's jump is the search's selection)");
  rule << "; the fall ends at step " << *end << " of " << y.size() - 1
       << ", where the measured noise level's error moves the slope by " << error_at_end
       << (error_at_end <= options.noise_slope_error ? " of it (at most " : " of it (the least; not within ")
       << options.noise_slope_error << ")";
  r.end = CurveEnd::none;
  r.end_index = 0;
  return true;
}

/// Stage 2c: a rise of a signal whose amplitude grows on its own has no attractor of fixed size to
/// saturate on: its pairs' distances grow with the signal, and a "plateau" that still rises as fast
/// as the signal grows is a beat or a slower mode. Its fastest mode dominates late
/// (FitOptions::late_growth_share).
bool fit_late_growth(const std::vector<double>& y, const CurveCut& cut, std::size_t min_len, const FitOptions& options,
                     FitResult& r, std::ostringstream& rule) {
  const std::size_t n = y.size();
  const double grows = options.signal_end_rate;
  if (!(cut.change > 0.0 && options.late_growth_share > 0.0 && std::isfinite(grows) &&
        grows * static_cast<double>(n - 1) >= kGrowingSignal))
    return false;
  const double level_rate =
      r.end == CurveEnd::saturation && r.end_index + 2 < n ? fit_line(y.data(), r.end_index, n - 1).slope : 0.0;
  if (r.end != CurveEnd::none && level_rate < options.persist_share * grows) return false;
  const std::size_t plateau = r.end_index;
  if (!choose_late_region(y, n - 1, min_len, false, options.late_growth_share, r, rule)) return false;
  if (r.end == CurveEnd::saturation) {
    rule << "; the level from step " << plateau << " rises at " << level_rate << " per step, as the signal grows ("
         << grows << "): not a saturation plateau";
    r.end = CurveEnd::none;
    r.end_index = 0;
  }
  return true;
}

/// The rule of fit.hpp: sets the region [r.first, r.last], r.end and r.end_index.
void choose_region(const DivergenceCurve& curve, const FitOptions& options, FitResult& r, std::ostringstream& rule) {
  const auto& y = curve.mean_log_distance;
  if (fit_flat(y, r, rule) || fit_bounded(curve, options, r, rule)) return;
  const std::size_t period = std::max<std::size_t>(1, options.period);
  const std::size_t min_len = std::max<std::size_t>(3, period / 2 + 1);
  const CurveCut cut = cut_curve_end(y, min_len, options, r, rule);
  if (fit_persisting_level(y, cut, options, r, rule) || fit_compensated_decay(curve, cut, min_len, options, r, rule) ||
      fit_late_decay(curve, cut, min_len, options, r, rule) || fit_late_growth(y, cut, min_len, options, r, rule))
    return;
  choose_linear_region(y, cut.stop, min_len, options, r, rule);
}

/// 95 % interval from batch means: the slope of every batch's curve over the region, t-distributed
/// over the batches; the formal least-squares interval (with a warning) when fewer than two batches
/// cover the region.
void batch_means_interval(const DivergenceCurve& curve, const LineFit& f, FitResult& r) {
  std::vector<double> slopes;
  for (const auto& bm : curve.batch_mean) {
    bool ok = true;
    for (std::size_t i = r.first; i <= r.last && ok; ++i) ok = std::isfinite(bm[i]);
    if (ok) slopes.push_back(fit_line(bm.data(), r.first, r.last).slope);
  }
  if (slopes.size() >= 2) {
    double mean = 0.0;
    for (double s : slopes) mean += s;
    mean /= static_cast<double>(slopes.size());
    double var = 0.0;
    for (double s : slopes) var += (s - mean) * (s - mean);
    var /= static_cast<double>(slopes.size() - 1);
    const double half = student_t95(slopes.size() - 1) * std::sqrt(var / static_cast<double>(slopes.size()));
    r.ci_low = r.slope - half;
    r.ci_high = r.slope + half;
  } else {
    const double half = student_t95(f.n > 2 ? f.n - 2 : 1) * f.slope_stderr;
    r.ci_low = r.slope - half;
    r.ci_high = r.slope + half;
    r.warnings.push_back("too few batches for a batch-means interval: formal least-squares interval reported");
  }
}

/// Warnings about the fitted region: too short, not straight, or (a growth fitted by the rule,
/// FitOptions::bend_warning) bending within itself. Said, not changed.
void warn_about_region(const std::vector<double>& y, const FitOptions& options, FitResult& r) {
  if (r.last - r.first + 1 < 5)
    r.warnings.push_back("fit region has only " + std::to_string(r.last - r.first + 1) + " points");
  if (r.r2 < 0.9 && std::abs(r.slope) * static_cast<double>(r.last - r.first) > 0.5)
    r.warnings.push_back("the fitted region is not straight (R^2 = " + std::to_string(r.r2) + ")");
  if (options.bend_warning > 0.0 && r.automatic && r.end == CurveEnd::saturation && r.slope > 0.0 &&
      r.last - r.first + 1 >= 8) {
    const HalfSlopes h = half_slopes(y, r.first, r.last);
    if (h.first > 0.0 && h.second < options.bend_warning * h.first)
      r.warnings.push_back(fmt::format(
          "the divergence curve bends within the fit region: its first half (steps {}..{}) rises at {:.2f} x the fitted "
          "slope, its second half ({}..{}) at {:.2f} x; there is no straight stretch, and the exponent depends on the "
          "region more than its 95 % interval says (--fit A:B fits another region)",
          r.first, h.mid, h.first / r.slope, h.mid, r.last, h.second / r.slope));
  }
}

}  // namespace

std::vector<double> local_slopes(const std::vector<double>& y, std::size_t period) {
  // Half the period rounded up, written so that no period (up to SIZE_MAX) overflows, nor i + w below.
  const std::size_t w = std::max<std::size_t>(1, period / 2 + period % 2);
  std::vector<double> slope(y.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = w; i < y.size() && y.size() - i > w; ++i)
    slope[i] = (y[i + w] - y[i - w]) / (2.0 * static_cast<double>(w));
  return slope;
}

bool first_step_jumps(const std::vector<double>& y, double slope_per_step) {
  if (y.size() < 2) return false;
  const double jump = y[1] - y[0];
  return jump >= kNoiseJump && jump >= kNoiseJumpRatio * std::abs(slope_per_step);
}

bool first_step_jumps_to_level(const std::vector<double>& y, double slope_per_step) {
  if (y.size() < 4 || !first_step_jumps(y, slope_per_step)) return false;
  const double jump = y[1] - y[0];
  return std::abs(y[2] - y[1]) <= kNoiseLevelShare * jump && std::abs(y[3] - y[2]) <= kNoiseLevelShare * jump;
}

const char* to_string(CurveEnd end) {
  switch (end) {
    case CurveEnd::saturation: return "saturation plateau";
    case CurveEnd::floor: return "noise/underflow floor";
    case CurveEnd::flat: return "flat curve";
    case CurveEnd::bounded: return "bounded divergence";
    default: return "none";
  }
}

void FitOptions::validate() const {
  if (range && !(range->first < range->second))
    throw OptionError("fit range " + std::to_string(range->first) + ":" + std::to_string(range->second) +
                      ": expected first < last");
  if (!(merge_tolerance >= 0.0 && merge_tolerance < 1.0)) throw OptionError("fit.merge_tolerance: expected [0, 1)");
  if (!(end_tolerance > 0.0 && end_tolerance < 1.0)) throw OptionError("fit.end_tolerance: expected (0, 1)");
  if (!(bounded_margin > 0.0)) throw OptionError("fit.bounded_margin: expected > 0");
  if (!(bounded_max_rise > 0.0)) throw OptionError("fit.bounded_max_rise: expected > 0");
  if (!(bounded_return >= 0.0 && bounded_return < 1.0)) throw OptionError("fit.bounded_return: expected [0, 1)");
  if (!(straightness > 0.0 && straightness <= 1.0)) throw OptionError("fit.straightness: expected (0, 1]");
  if (!(map_straightness > 0.0 && map_straightness <= 1.0)) throw OptionError("fit.map_straightness: expected (0, 1]");
  if (!(bend_ratio >= 0.0 && bend_ratio < 1.0)) throw OptionError("fit.bend_ratio: expected [0, 1) (0 = off)");
  if (!(min_periods >= 0.0 && min_periods <= 100.0)) throw OptionError("fit.min_periods: expected [0, 100] (0 = off)");
  if (!(bend_warning >= 0.0 && bend_warning < 1.0)) throw OptionError("fit.bend_warning: expected [0, 1) (0 = never warn)");
  if (!(extension_straightness >= 0.0 && extension_straightness < 1.0))
    throw OptionError("fit.extension_straightness: expected [0, 1) (0 = always extend to min_periods)");
  if (std::isinf(signal_rate)) throw OptionError("fit.signal_rate: expected a finite rate or NaN (unknown)");
  if (std::isinf(signal_end_rate)) throw OptionError("fit.signal_end_rate: expected a finite rate or NaN (unknown)");
  if (!(persist_share > 0.0 && persist_share < 1.0)) throw OptionError("fit.persist_share: expected (0, 1)");
  if (!(late_decay_share >= 0.0 && late_decay_share <= 1.0)) throw OptionError("fit.late_decay_share: expected [0, 1] (0 = off)");
  if (!(late_growth_share >= 0.0 && late_growth_share <= 1.0)) throw OptionError("fit.late_growth_share: expected [0, 1] (0 = off)");
  if (!(noise_variance_error >= 0.0 && std::isfinite(noise_variance_error)))
    throw OptionError("fit.noise_variance_error: expected a finite value >= 0 (0 = exact or unknown)");
  if (!(noise_slope_error > 0.0 && noise_slope_error <= 1.0)) throw OptionError("fit.noise_slope_error: expected (0, 1]");
}

FitResult fit_divergence(const DivergenceCurve& curve, const FitOptions& options) {
  options.validate();
  const auto& y = curve.mean_log_distance;
  const std::size_t n = y.size();
  if (n < 3) throw InputError("divergence curve has " + std::to_string(n) + " points: expected at least 3");
  FitResult r;
  std::ostringstream rule;
  if (options.range) {
    if (options.range->second >= n)
      throw OptionError("fit range " + std::to_string(options.range->first) + ":" + std::to_string(options.range->second) +
                        " exceeds the curve (steps 0.." + std::to_string(n - 1) + ")");
    r.first = options.range->first;
    r.last = options.range->second;
    r.automatic = false;
    rule << "given range";
  } else {
    choose_region(curve, options, r, rule);
  }
  const LineFit f = fit_line(y.data(), r.first, r.last);
  r.slope = f.slope;
  r.intercept = f.intercept;
  r.r2 = f.r2;
  batch_means_interval(curve, f, r);
  warn_about_region(y, options, r);
  r.rule = rule.str();
  return r;
}

}  // namespace mlce
