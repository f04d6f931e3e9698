#include "plot.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "report.hpp"

namespace mlce::cli {

void plot_curve_png(const MlceResult& r, const std::string& png_path) {
  namespace fs = std::filesystem;
  const fs::path tmp_png = png_path + ".tmp-mlce.png";
  const fs::path data = png_path + ".tmp-mlce.csv";
  write_file_atomically(data.string(), curve_csv(r));
  const std::string u = r.time_unit.empty() ? "sample" : r.time_unit;
  const std::string script = fmt::format(
      "set terminal pngcairo size 900,600 noenhanced\nset output '{}'\nset datafile separator ','\n"
      "set key top left\nset grid\nset xlabel 'time ({})'\nset ylabel '<ln d_j(i)>'\n"
      "set title 'Rosenstein divergence: lambda = {:.5g} 1/{} (fit steps {}..{}, R2 {:.4f})'\n"
      "plot '{}' every ::1 using 2:3 with lines lw 2 title 'mean log divergence', "
      "'' every ::1 using 2:($5 > 0 ? $6 : 1/0) with lines lw 3 dt 2 lc rgb 'black' title 'least-squares fit'\n",
      tmp_png.string(), u, r.lambda, u, r.fit.first, r.fit.last, r.r2, data.string());
  FILE* gp = popen("gnuplot 2>&1", "w");
  if (!gp) throw std::runtime_error(png_path + ": cannot start gnuplot (install gnuplot-nox)");
  std::fputs(script.c_str(), gp);
  const int rc = pclose(gp);
  std::error_code ec;
  fs::remove(data, ec);
  if (rc != 0 || !fs::exists(tmp_png)) {
    fs::remove(tmp_png, ec);
    throw std::runtime_error(png_path + ": gnuplot failed to draw the plot (is gnuplot installed?)");
  }
  fs::rename(tmp_png, png_path, ec);
  if (ec) throw std::runtime_error(png_path + ": cannot write the file");
}

}  // namespace mlce::cli
