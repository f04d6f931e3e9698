#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mlce/each_channel.hpp"
#include "mlce/estimate.hpp"

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

/// PNG of estimates with their 95 % intervals as error bars (no line joins them: the runs need not be
/// given in the parameter's order) and a line at 0: csv "x,lambda,low,high"
/// with a header line (mlce estimate RUN1 RUN2 ...: lambda against a parameter or the run's number).
void plot_estimates_png(const std::string& csv, const std::string& title, const std::string& xlabel,
                        const std::string& ylabel, const std::string& png_path);

/// PNG of exponents as points of the complex plane: csv "i,lambda,frequency,..." with a header line
/// (the first three columns are read), the growth rate across, the frequency up, and the
/// stability boundary (lambda = 0) drawn: a point right of it is a growing mode.
void plot_exponents_png(const std::string& csv, const std::string& title, const std::string& unit,
                        const std::string& png_path);

/// PNG of columns 2..N of a CSV (with a header line) against column 1, one line each;
/// `marks`: dashed vertical lines at x, each labelled.
void plot_columns_png(const std::string& csv, const std::string& title, const std::string& xlabel,
                      const std::string& ylabel, const std::string& png_path,
                      const std::vector<std::pair<double, std::string>>& marks = {});
}  // namespace mlce::cli
