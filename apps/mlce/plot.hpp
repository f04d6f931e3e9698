#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mlce/each_channel.hpp"
#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"

namespace mlce::cli {
/// Runs gnuplot (Debian gnuplot-nox) on script(csv_tmp) with `csv` as its data and moves the PNG
/// into place only when gnuplot succeeded; throws std::runtime_error naming png_path. The terminal
/// (pngcairo, 900 x `height` pixels), the output file and the CSV separator are set before the
/// script; script() receives the data path ready for a gnuplot single-quoted string.
void render_png(const std::string& png_path, const std::string& csv,
                const std::function<std::string(const std::string& data)>& script, int height = 600);
/// PNG of the divergence curve with the fit region and line.
void plot_curve_png(const MlceResult& r, const std::string& png_path);
/// PNG of every estimated channel's divergence curve with its fit line (mlce estimate --each).
void plot_each_channel_png(const EachChannelResult& r, const std::string& png_path);
/// Colour map of z over a regular (x, y) grid: csv "x,y,z" with a header line.
void plot_map_png(const std::string& csv, const std::string& title, const std::string& xlabel, const std::string& ylabel,
                  const std::string& zlabel, const std::string& png_path);

/// One estimate as the stability plots draw it (mlce estimate RUN RUN ..., mlce sweep --method rosenstein).
struct PlottedReading {
  double x = 0.0, y = 0.0;  ///< the parameter (y: the second one of a map)
  double lambda = 0.0, low = 0.0, high = 0.0;  ///< the estimate and its 95 % interval
  Stability stability = Stability::undetermined;
  /// The window lies in the floor of a decay that ended before it (MlceResult::in_decay_floor):
  /// lambda is the solver's residue, not the motion's, and is not drawn as a value.
  bool in_decay_floor = false;
};

/// PNG of estimates with their 95 % intervals as error bars, coloured by the reading (stable blue,
/// neutral green, unstable red, undetermined hollow grey), and a line at 0. A point in the floor of
/// a decay is a mark below the others (its lambda is a residue). `join`: a thin line through the
/// drawn values in the given order (a sweep; not for runs given in any order); `marks`: dashed
/// vertical lines at x, each labelled.
void plot_readings_png(const std::vector<PlottedReading>& points, const std::string& title, const std::string& xlabel,
                       const std::string& ylabel, const std::string& png_path, bool join,
                       const std::vector<std::pair<double, std::string>>& marks = {});

/// Colour map of lambda over a regular (x, y) grid of readings; a point in the floor of a decay is
/// drawn at the stable end of the scale and circled, an undetermined one crossed.
void plot_reading_map_png(const std::vector<PlottedReading>& points, const std::string& title, const std::string& xlabel,
                          const std::string& ylabel, const std::string& zlabel, const std::string& png_path);

/// PNG of exponents as points of the complex plane: csv "i,lambda,frequency,..." with a header line
/// (the first three columns are read), the growth rate across, the frequency up, and the
/// stability boundary (lambda = 0) drawn: a point right of it is a growing mode.
void plot_exponents_png(const std::string& csv, const std::string& title, const std::string& unit,
                        const std::string& png_path);

/// PNG of eigenvalues in the complex plane from csv "time,real,imag" with a header line: the real
/// part (growth rate) across, the imaginary part up, each point coloured by the time of its analysis
/// (one colour for one analysis), and the stability boundary (real part 0) drawn.
void plot_eigenvalues_by_time_png(const std::string& csv, const std::string& title, const std::string& png_path);

/// PNG of columns 2..N of a CSV (with a header line) against column 1, one line each;
/// `marks`: dashed vertical lines at x, each labelled.
void plot_columns_png(const std::string& csv, const std::string& title, const std::string& xlabel,
                      const std::string& ylabel, const std::string& png_path,
                      const std::vector<std::pair<double, std::string>>& marks = {});
}  // namespace mlce::cli
