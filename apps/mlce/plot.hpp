#pragma once
#include <string>

#include "mlce/estimate.hpp"

namespace mlce::cli {
/// PNG of the divergence curve with the fit region and line, drawn by gnuplot (Debian
/// gnuplot-nox). Written through a temporary file; throws std::runtime_error on failure.
void plot_curve_png(const MlceResult& r, const std::string& png_path);
}  // namespace mlce::cli
