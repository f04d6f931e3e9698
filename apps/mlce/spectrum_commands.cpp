#include "spectrum_commands.hpp"

#include <fmt/format.h>

#include <boost/program_options.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "cli_common.hpp"
#include "mlce/models/dynamics.hpp"
#include "mlce/models/scene.hpp"
#include "mlce/spectrum/floquet.hpp"
#include "mlce/spectrum/qr_spectrum.hpp"
#include "mlce/spectrum/solver_pencil.hpp"
#include "mlce/reader/mbdyn_eigenanalysis.hpp"
#include "mlce/reader/mbdyn_netcdf.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "plot.hpp"
#include "report.hpp"

namespace po = boost::program_options;

namespace mlce::cli {
namespace {

/// The exponents' sum beside the mean divergence of the vector field: Liouville's formula makes
/// them equal, so their difference is the computation's own error (liouville.hpp).
std::string liouville_line(double sum, double mean_divergence, const std::string& unit) {
  return fmt::format("# sum of the exponents {:.10g} 1/{}; mean divergence of the vector field (tr A) {:.10g}; "
                     "difference {:.2g} (Liouville's formula makes them equal)\n",
                     sum, unit, mean_divergence, sum - mean_divergence);
}

/// Options every Jacobian-based command shares.
struct Common {
  std::string sensitivity, jacobian = "analytic", csv_path;
  bool json = false, quiet = false;
};

void add_common(po::options_description& d, Common& c) {
  d.add_options()
      ("sensitivity", po::value(&c.sensitivity), "comma-separated parameters to differentiate by (e.g. CL,rpm; c3; mu)")
      ("jacobian", po::value(&c.jacobian), "analytic | complex-step | jacobian-free")
      ("json", po::bool_switch(&c.json), "print one JSON object")
      ("csv", po::value(&c.csv_path), "write the exponents (and sensitivities) as CSV, one row each")
      ("quiet", po::bool_switch(&c.quiet), "no progress messages");
}

/// The exponents as CSV for scripts: i, lambda, [frequency, multiplier_abs], then d lambda / d p per
/// parameter; units as in the text table (1/time unit, rad/time unit).
std::string exponents_csv(const Eigen::VectorXd& ex, const Eigen::VectorXd* freq, const Eigen::VectorXcd* multipliers,
                          const std::vector<std::string>& names, const Eigen::MatrixXd& sens) {
  std::string out = "i,lambda";
  if (freq) out += ",frequency";
  if (multipliers) out += ",multiplier_abs";
  for (const auto& n : names) out += ",dlambda/d" + n;
  out += "\n";
  for (Eigen::Index i = 0; i < ex.size(); ++i) {
    out += fmt::format("{},{:.17g}", i + 1, ex(i));
    if (freq) out += fmt::format(",{:.17g}", (*freq)(i));
    if (multipliers) out += fmt::format(",{:.17g}", std::abs((*multipliers)(i)));
    for (std::size_t k = 0; k < names.size(); ++k) out += fmt::format(",{:.17g}", sens(static_cast<Eigen::Index>(k), i));
    out += "\n";
  }
  return out;
}

std::string time_unit(const models::Scene& s) { return s.model == "flapping" ? "rad of azimuth" : "s"; }

std::vector<ode::ParameterFamily> families(const models::Scene& scene, const std::string& list) {
  std::vector<ode::ParameterFamily> out;
  std::vector<std::string> seen;  // a parameter twice would print (and key in JSON) one column twice
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    if (name.empty()) continue;
    if (std::find(seen.begin(), seen.end(), name) != seen.end())
      throw po::error("--sensitivity " + list + ": '" + name + "' is given twice");
    seen.push_back(name);
    try {
      out.push_back(models::parameter_family(scene, name));
    } catch (const std::invalid_argument& e) {
      throw po::error(std::string("--sensitivity: ") + e.what());
    }
  }
  return out;
}

spectrum::JacobianMethod method(const std::string& name) {
  try {
    return spectrum::jacobian_method_from_name(name);
  } catch (const std::invalid_argument& e) {
    throw po::error(std::string("--jacobian: ") + e.what());
  }
}

nlohmann::json sensitivities_json(const std::vector<std::string>& names, const Eigen::MatrixXd& s) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::vector<double> row(static_cast<std::size_t>(s.cols()));
    for (Eigen::Index i = 0; i < s.cols(); ++i) row[static_cast<std::size_t>(i)] = s(static_cast<Eigen::Index>(k), i);
    j[names[k]] = row;
  }
  return j;
}

std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

/// Human table: index, exponent, [frequency], sensitivities.
std::string table(const Eigen::VectorXd& ex, const Eigen::VectorXd* freq, const std::vector<std::string>& names,
                  const Eigen::MatrixXd& sens, const std::string& unit) {
  std::string out = fmt::format("{:>4}  {:>14}", "i", "lambda (1/" + unit + ")");
  if (freq) out += fmt::format("  {:>16}", "freq (rad/" + unit + ")");
  for (const auto& n : names) out += fmt::format("  {:>16}", "dlambda/d" + n);
  out += "\n";
  for (Eigen::Index i = 0; i < ex.size(); ++i) {
    out += fmt::format("{:>4}  {:>14.7g}", i + 1, ex(i));
    if (freq) out += fmt::format("  {:>16.7g}", (*freq)(i));
    for (std::size_t k = 0; k < names.size(); ++k) out += fmt::format("  {:>16.7g}", sens(static_cast<Eigen::Index>(k), i));
    out += "\n";
  }
  return out;
}

double positive_option(const po::variables_map& vm, const char* name, double def) {
  if (!vm.count(name)) return def;
  const double v = vm[name].as<double>();
  if (!(v >= 0.0) || !std::isfinite(v)) throw po::error(fmt::format("--{}: expected a non-negative number", name));
  return v;
}

}  // namespace

int cmd_spectrum(const std::vector<std::string>& args) {
  Common c;
  std::string merge = "auto", history_path, plot_path;
  po::options_description d("mlce spectrum SCENE [--key value ...] [options]");
  add_common(d, c);
  d.add_options()
      ("t-end", po::value<double>(), "end of the run (default: 10 x the scene's t_end: the estimates converge like 1/t)")
      ("qr-step", po::value<double>(), "re-orthonormalisation interval (default: the scene's dt_out)")
      ("transient", po::value<double>(), "time before the sums start (default: 10 % of the run)")
      ("merge", po::value(&merge), "auto (average neighbouring exponents that have not separated over the run: complex pairs), off, or a tolerance in 1/time")
      ("count", po::value<int>(), "only the K largest exponents (K tangent vectors: the cost scales with K; 1 = the MLCE); default all")
      ("history", po::value(&history_path), "write the running estimates (and sensitivities) as CSV")
      ("plot", po::value(&plot_path), "PNG of the running estimates");
  const auto parsed = parse_scene_command(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->vm;
  const models::Scene& scene = parsed->scene;
  spectrum::QrOptions o;
  o.jacobian = method(c.jacobian);
  o.t_end = vm.count("t-end") ? vm["t-end"].as<double>() : 10.0 * scene.t_end;
  if (!(o.t_end > 0) || !std::isfinite(o.t_end)) throw po::error("--t-end: expected a positive time");
  o.step = vm.count("qr-step") ? vm["qr-step"].as<double>() : scene.dt_out;
  if (!(o.step > 0) || !std::isfinite(o.step) || o.step > o.t_end) throw po::error("--qr-step: expected 0 < step <= t-end");
  o.transient = positive_option(vm, "transient", 0.1 * o.t_end);
  if (o.transient >= o.t_end) throw po::error("--transient: expected less than the run length");
  o.integrator = scene.integrator;
  const ode::DynamicalSystem sys = models::dynamical_system(scene);
  if (vm.count("count")) {
    const int k = vm["count"].as<int>();
    if (k < 1 || k > sys.dimension)
      throw po::error(fmt::format("--count {}: expected 1..{} (the model's states)", k, sys.dimension));
    o.count = static_cast<std::size_t>(k);
  }
  if (merge == "auto") o.merge = spectrum::MergeRule::unresolved;
  else if (merge == "off") o.merge = spectrum::MergeRule::none;
  else {
    o.merge = spectrum::MergeRule::tolerance;
    const auto tol = parse_finite(merge);
    if (!tol || !(*tol > 0)) throw po::error("--merge '" + merge + "': expected auto, off or a positive tolerance");
    o.merge_tolerance = *tol;
  }
  const auto params = families(scene, c.sensitivity);
  ProgressLine progress("QR spectrum", c.quiet);
  o.progress = std::ref(progress);
  const spectrum::QrResult r = spectrum::qr_spectrum(sys, scene.x0, o, params);
  const std::string unit = time_unit(scene);

  if (!history_path.empty() || !plot_path.empty()) {
    // Running estimates (time, lambda_i) for the plot; the CSV adds d lambda_i / d p per parameter.
    const Eigen::Index n = r.history.cols();
    std::string head = "time", sens_head;
    for (Eigen::Index i = 0; i < n; ++i) head += fmt::format(",lambda{}", i + 1);
    for (const auto& p : r.parameters)
      for (Eigen::Index i = 0; i < n; ++i) sens_head += fmt::format(",dlambda{}/d{}", i + 1, p);
    std::string csv = head + sens_head + "\n", plot_csv = head + "\n";
    for (std::size_t k = 0; k < r.history_time.size(); ++k) {
      const auto row = static_cast<Eigen::Index>(k);
      std::string line = fmt::format("{:.10g}", r.history_time[k]);
      for (Eigen::Index i = 0; i < n; ++i) line += fmt::format(",{:.10g}", r.history(row, i));
      plot_csv += line + "\n";
      for (Eigen::Index i = 0; i < r.history_sensitivities.cols(); ++i) line += fmt::format(",{:.10g}", r.history_sensitivities(row, i));
      csv += line + "\n";
    }
    if (!history_path.empty()) write_file_atomically(history_path, csv);
    if (!plot_path.empty())
      plot_columns_png(plot_csv, "discrete QR: running estimates of the Lyapunov exponents", "time (" + unit + ")",
                       "lambda (1/" + unit + ")", plot_path);
  }
  if (!c.csv_path.empty())
    write_file_atomically(c.csv_path, exponents_csv(r.exponents, nullptr, nullptr, r.parameters, r.sensitivities));
  if (c.json) {
    nlohmann::json j;
    j["method"] = "qr";
    j["scene"] = scene.source;
    j["exponents"] = to_vector(r.exponents);
    j["raw_exponents"] = to_vector(r.raw_exponents);
    j["groups"] = r.groups;
    if (!r.parameters.empty()) j["sensitivities"] = sensitivities_json(r.parameters, r.sensitivities);
    j["time_unit"] = unit;
    j["t_end"] = o.t_end;
    j["qr_step"] = o.step;
    j["transient"] = o.transient;
    j["averaging_start"] = r.averaging_start;
    j["averaging_time"] = r.averaging_time;
    j["intervals"] = r.intervals;
    j["jacobian"] = spectrum::jacobian_method_name(o.jacobian);
    j["merge"] = merge;
    j["orthogonality_error"] = r.orthogonality_error;
    j["count"] = r.exponents.size();
    j["exponent_sum"] = r.exponent_sum;
    if (std::isfinite(r.mean_divergence)) j["mean_divergence"] = r.mean_divergence;
    else j["mean_divergence"] = nullptr;  // count < n: no Liouville check
    j["steps"] = r.stats.steps;
    j["evaluations"] = r.stats.evaluations;
    j["warnings"] = r.warnings;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << fmt::format("# discrete QR: {} exponents of {} ({}), t = 0..{} {}, QR step {}, averaged over the last {} {}, {} Jacobian\n",
                             r.exponents.size() < sys.dimension ? fmt::format("the {} largest", r.exponents.size())
                                                                : std::to_string(r.exponents.size()),
                             scene.source, scene.model, o.t_end, unit, o.step, r.averaging_time, unit,
                             spectrum::jacobian_method_name(o.jacobian));
    for (const auto& g : r.groups) {
      std::string idx;
      for (int i : g) {
        if (!idx.empty()) idx += ',';
        idx += std::to_string(i + 1);
      }
      std::cout << fmt::format("# averaged (multiplicity {}): exponents {}\n", g.size(), idx);
    }
    std::cout << table(r.exponents, nullptr, r.parameters, r.sensitivities, unit);
    if (std::isfinite(r.mean_divergence)) std::cout << liouville_line(r.exponent_sum, r.mean_divergence, unit);
  }
  print_warnings(r.warnings);
  return 0;
}

namespace {

int print_linear(const spectrum::LinearSpectrum& s, const models::Scene& scene, const char* method, const Common& c,
                 const std::vector<std::string>& coordinates, const std::string& plot_path) {
  const std::string unit = time_unit(scene);
  const std::string csv =
      exponents_csv(s.exponents, &s.frequencies, s.period > 0 ? &s.values : nullptr, s.parameters, s.sensitivities);
  if (!c.csv_path.empty()) write_file_atomically(c.csv_path, csv);
  if (!plot_path.empty())
    plot_exponents_png(csv,
                       fmt::format("{} of {}{}", s.period > 0 ? "Floquet exponents" : "eigenvalues", scene.source,
                                   s.period > 0 ? fmt::format(" (frequencies modulo {:.6g} rad/{})", 2 * M_PI / s.period, unit)
                                                : std::string()),
                       unit, plot_path);
  if (c.json) {
    nlohmann::json j;
    j["method"] = method;
    j["scene"] = scene.source;
    j["exponents"] = to_vector(s.exponents);
    j["frequencies"] = to_vector(s.frequencies);
    if (s.period > 0) {
      j["period"] = s.period;
      std::vector<double> mag;
      for (Eigen::Index i = 0; i < s.values.size(); ++i) mag.push_back(std::abs(s.values(i)));
      j["multipliers_abs"] = mag;
      j["resolution_floor"] = s.resolution_floor;
    }
    if (!coordinates.empty()) j["coordinates"] = coordinates;
    if (!s.parameters.empty()) j["sensitivities"] = sensitivities_json(s.parameters, s.sensitivities);
    j["time_unit"] = unit;
    j["eigenvector_condition"] = s.eigenvector_condition;
    j["exponent_sum"] = s.exponents.sum();
    j["mean_divergence"] = s.mean_divergence;
    j["warnings"] = s.warnings;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << fmt::format("# {} of {} ({}){}\n", method, scene.source, scene.model,
                             s.period > 0 ? fmt::format(", period {:.10g} {} (frequencies modulo {:.6g} rad/{})", s.period, unit,
                                                        2 * M_PI / s.period, unit)
                                          : std::string());
    std::cout << table(s.exponents, &s.frequencies, s.parameters, s.sensitivities, unit);
    std::cout << liouville_line(s.exponents.sum(), s.mean_divergence, unit);
  }
  print_warnings(s.warnings);
  return 0;
}

}  // namespace

int cmd_floquet(const std::vector<std::string>& args) {
  Common c;
  std::string orbit, plot_path;
  po::options_description d("mlce floquet SCENE [--key value ...] [options]");
  add_common(d, c);
  d.add_options()
      ("plot", po::value(&plot_path), "PNG of the exponents in the complex plane (growth rate, frequency)")
      ("period", po::value<double>(), "period T (default: the model's, 2 pi / Omega for Hammond)")
      ("orbit", po::value(&orbit), "comma-separated state on a periodic orbit at t = 0 (default: x = 0)");
  const auto parsed = parse_scene_command(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->vm;
  const models::Scene& scene = parsed->scene;
  spectrum::FloquetOptions o;
  o.jacobian = method(c.jacobian);
  o.period = positive_option(vm, "period", 0.0);
  if (!orbit.empty()) {
    std::vector<double> v;
    std::stringstream in(orbit);
    for (std::string item; std::getline(in, item, ',');) {
      const auto x = parse_finite(item);
      if (!x) throw po::error("--orbit: '" + item + "' is not a number");
      v.push_back(*x);
    }
    o.orbit = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  const auto params = families(scene, c.sensitivity);
  const spectrum::LinearSpectrum s = spectrum::floquet(models::dynamical_system(scene), o, params);
  return print_linear(s, scene, "floquet", c, {}, plot_path);
}

int cmd_eigen(const std::vector<std::string>& args) {
  Common c;
  std::string plot_path;
  po::options_description d("mlce eigen SCENE [--key value ...] [options]");
  add_common(d, c);
  d.add_options()("plot", po::value(&plot_path), "PNG of the eigenvalues in the complex plane (growth rate, frequency)");
  const auto parsed = parse_scene_command(args, d);
  if (!parsed) return 0;
  const models::Scene& scene = parsed->scene;
  models::TimeInvariantForm form;
  try {
    form = models::time_invariant_form(scene);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(scene.source + ": " + e.what());
  }
  // Sensitivities: central differences of the (analytic) time-invariant matrix, then the exact
  // first-order eigenvalue perturbation Re(U^-1 dA U)_ii.
  std::vector<Eigen::MatrixXd> dA;
  std::vector<std::string> names;
  for (const auto& f : families(scene, c.sensitivity)) {
    const double h = 1e-4 * f.scale;
    models::Scene plus = scene, minus = scene;
    models::set_scene_parameter(plus, f.name, f.nominal + h);
    models::set_scene_parameter(minus, f.name, f.nominal - h);
    dA.push_back((models::time_invariant_form(plus).A - models::time_invariant_form(minus).A) / (2.0 * h));
    names.push_back(f.name);
  }
  const spectrum::LinearSpectrum s = spectrum::linear_eigen(form.A, dA, names);
  return print_linear(s, scene, "eigen", c, form.coordinates, plot_path);
}

namespace {

/// The sign of a real part against the spectrum's own rounding: within 1e-8 of the largest |s| (the
/// QZ's relative accuracy on a well-scaled pencil, with margin) it reads neutral (a rigid-body mode's
/// s = 0 comes out at ~1e-15 |s|max, either sign).
const char* sign_word(double real, const std::vector<std::complex<double>>& all) {
  double largest = 0.0;
  for (const auto& s : all) largest = std::max(largest, std::abs(s));
  if (std::abs(real) <= 1e-8 * largest) return "neutral";
  return real > 0.0 ? "unstable" : "stable";
}

}  // namespace

int cmd_eigenanalysis(const std::vector<std::string>& args) {
  bool json = false, quiet = false;
  std::string csv_path, plot_path;
  po::options_description d("mlce eigenanalysis SET|FILE.m|FILE.nc|FILE.out [options]");
  d.add_options()("json", po::bool_switch(&json), "print one JSON object")(
      "csv", po::value(&csv_path), "every eigenvalue as CSV (file, time, real, imag, frequency_hz, damping_ratio)")(
      "plot", po::value(&plot_path), "PNG of the eigenvalues in the complex plane, coloured by the time of their analysis")(
      "quiet", po::bool_switch(&quiet), "no progress line on stderr (printed before solving a pencil of n >= 300)");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  if (!vm.count("file"))
    throw po::error("missing SET (an MBDyn output prefix), one eigenanalysis FILE.m, a FILE.nc or a FILE.out");
  const std::string file = vm["file"].as<std::string>();
  // What to read: one .m file, the eigenanalyses of one .nc file, the eigenvalue tables of one .out file, or
  // those of the set at PREFIX: those in PREFIX.nc when it holds any (NetCDF keeps every number in double
  // precision, the .m file `output precision` digits), else its .m files, else the tables of PREFIX.out
  // (the eigenvalues as printed, 6 significant digits by default, without dCoef or the matrices).
  std::vector<std::string> files;
  reader::MbdynNetcdfEigenanalyses from_netcdf;
  reader::MbdynOutEigenanalyses from_out;
  std::vector<std::string> warnings;
  const auto read_netcdf = [&](const std::string& nc) {
    from_netcdf = reader::read_mbdyn_netcdf_eigenanalyses(nc);
    warnings = from_netcdf.warnings;
    return !from_netcdf.analyses.empty() || !from_netcdf.warnings.empty();
  };
  const auto read_out = [&](const std::string& out) {
    from_out = reader::read_mbdyn_out_eigenanalyses(out);
    warnings = from_out.warnings;
    return !from_out.analyses.empty();
  };
  const char* const how = "MBDyn writes them when its initial-value block has `eigenanalysis: <times>` (`output eigenvectors` "
                          "or `output matrices` for the .m file, `output results: netcdf` for eig.* in the .nc)";
  if (file.size() > 2 && file.ends_with(".m")) {
    files.push_back(file);
  } else if (file.size() > 3 && file.ends_with(".nc")) {
    if (!read_netcdf(file))
      throw std::runtime_error(file + ": no eigenanalysis (no 'eig.time'); MBDyn writes eig.* when its initial-value block "
                               "has `eigenanalysis: <times>, output eigenvectors` and the control data `output results: netcdf`");
  } else if (file.size() > 4 && file.ends_with(".out")) {
    if (!read_out(file)) throw std::runtime_error(file + ": no eigenvalue table ('Mode n.  Real  Imag ...'); " + how);
  } else {
    const std::string prefix = reader::mbdyn_prefix(file);
    std::error_code ec;
    if (!(std::filesystem::is_regular_file(prefix + ".nc", ec) && read_netcdf(prefix + ".nc"))) {
      files = reader::mbdyn_eigenanalysis_files(prefix);
      if (files.empty() && !(std::filesystem::is_regular_file(prefix + ".out", ec) && read_out(prefix + ".out")))
        throw std::runtime_error(prefix + ": no eigenanalysis (no " + prefix + ".m or " + prefix + "_<k>.m, no eig.* in " + prefix +
                                 ".nc, no eigenvalue table in " + prefix + ".out); " + how);
    }
  }
  if (!from_netcdf.warnings.empty() && from_netcdf.analyses.empty())
    throw std::runtime_error(file + ": no eigenanalysis was performed (" + from_netcdf.warnings.front() + ")");
  nlohmann::json analyses = nlohmann::json::array();
  std::string csv = "file,time,real,imag,frequency_hz,damping_ratio\n";
  std::string plot_csv = "time,real,imag\n";
  std::string text;
  // One analysis at a time from .m files (each may hold two 2000 x 2000 matrices); a NetCDF file's, and the
  // tables of a .out, are read at once.
  const std::size_t count = !files.empty() ? files.size() : !from_out.analyses.empty() ? from_out.analyses.size()
                                                                                          : from_netcdf.analyses.size();
  for (std::size_t index = 0; index < count; ++index) {
    const reader::MbdynEigenanalysis e = !files.empty()                ? reader::read_mbdyn_eigenanalysis(files[index])
                                         : !from_out.analyses.empty() ? std::move(from_out.analyses[index])
                                                                      : std::move(from_netcdf.analyses[index]);
    const std::string& path = e.source;  // the file, FILE.nc:eig.<k>, or FILE.out:LINE
    // MBDyn's own eigenvalues when it wrote them (alpha, or the .out's table); otherwise those of the
    // matrices it wrote (LU or QZ).
    // Only the .out's tables come without dCoef: the .m and NetCDF readers refuse an analysis that lacks it.
    const bool from_alpha = !e.alpha.empty(), from_table = !e.coefficient;
    if (!quiet && !from_alpha && !from_table && e.size >= 300)  // O(n^3): 0.2-0.6 s at n = 500 (bench_spectrum solver_pencil), minutes at 2000
      std::fprintf(stderr, "mlce eigenanalysis: %s: eigenvalues of a %zu x %zu pencil (O(n^3): seconds to minutes)...\n",
                   path.c_str(), e.size, e.size);
    const spectrum::SolverPencilSpectrum s =
        from_table   ? spectrum::spectrum_from_eigenvalues(e.printed, e.printed_at_infinity)
        : from_alpha ? spectrum::spectrum_from_multipliers(e.alpha, *e.coefficient)
                     : spectrum::spectrum_from_pencil(e.size, e.aplus, e.aminus, *e.coefficient);
    for (const auto& w : s.warnings) warnings.push_back(path + ": " + w);
    const std::string source =
        from_table   ? "the .out's table, as printed"
        : from_alpha ? "alpha"
                     : fmt::format("Aplus/Aminus {} x {}{} by {}", e.size, e.size, e.sparse ? " (sparse)" : "", s.method);
    const char* stability = s.largest_real_part ? sign_word(*s.largest_real_part, s.eigenvalues) : "undetermined";
    nlohmann::json values = nlohmann::json::array();
    const std::string time = e.time ? fmt::format("{}", *e.time) : std::string();
    std::string rows;  // the text table's rows, written in the same pass as JSON and CSV
    for (const auto& v : s.eigenvalues) {
      const double frequency = std::abs(v.imag()) / (2.0 * M_PI), damping = std::abs(v) > 0.0 ? -v.real() / std::abs(v) : 0.0;
      values.push_back({{"real", v.real()}, {"imag", v.imag()}, {"frequency_hz", frequency}, {"damping_ratio", damping}});
      csv += fmt::format("{},{},{},{},{},{}\n", path, time, v.real(), v.imag(), frequency, damping);
      if (!plot_path.empty()) plot_csv += fmt::format("{},{},{}\n", e.time ? *e.time : 0.0, v.real(), v.imag());
      rows += fmt::format("{:>16.9g} {:>16.9g} {:>14.6g} {:>14.6g}\n", v.real(), v.imag(), frequency, damping);
    }
    nlohmann::json a = {{"file", path},
                        {"time", e.time ? nlohmann::json(*e.time) : nlohmann::json(nullptr)},
                        {"coefficient", e.coefficient ? nlohmann::json(*e.coefficient) : nlohmann::json(nullptr)},
                        {"source", from_table ? "out" : from_alpha ? "alpha" : "matrices"},
                        {"method", s.method},
                        {"size", from_table   ? e.printed.size() + e.printed_at_infinity
                                 : from_alpha ? e.alpha.size()
                                              : e.size},
                        {"eigenvalues", values},
                        {"at_infinity", s.at_infinity},
                        {"largest_real_part", s.largest_real_part ? nlohmann::json(*s.largest_real_part) : nlohmann::json(nullptr)},
                        {"largest_frequency_hz", s.largest_frequency},
                        {"stability", stability}};
    analyses.push_back(a);
    text += fmt::format("# {}: {}{}eigenvalues from {}: {} finite, {} at infinity (constraints, singular Aplus)\n", path,
                        e.time ? fmt::format("t = {}, ", *e.time) : std::string(),
                        e.coefficient ? fmt::format("dCoef {}, ", *e.coefficient) : std::string(), source, s.eigenvalues.size(),
                        s.at_infinity);
    if (s.largest_real_part)
      text += fmt::format("largest real part {:+.9g} 1/time unit at {:.6g} cycles/time unit: {}\n", *s.largest_real_part,
                          s.largest_frequency, stability);
    text += fmt::format("{:>16} {:>16} {:>14} {:>14}\n", "real", "imag (rad)", "frequency", "damping ratio") + rows;
  }
  if (!plot_path.empty()) {
    if (plot_csv.find('\n') + 1 == plot_csv.size())
      throw std::runtime_error(plot_path + ": nothing to plot: no analysis has a finite eigenvalue");
    plot_eigenvalues_by_time_png(plot_csv, "MBDyn eigenanalysis: eigenvalues s = (Lambda - 1) / (dCoef (Lambda + 1))", plot_path);
  }
  if (!csv_path.empty()) write_file_atomically(csv_path, csv);
  if (json) {
    std::cout << nlohmann::json{{"analyses", analyses}, {"warnings", warnings}}.dump() << "\n";
  } else {
    std::cout << text;
  }
  print_warnings(warnings);
  return 0;
}

}  // namespace mlce::cli
