// mlce sweep: stability over a parameter grid (paper 001 §5.2), by any of the four methods.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <boost/program_options.hpp>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <thread>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli_common.hpp"
#include "mlce/estimate.hpp"
#include "mlce/modes.hpp"
#include "mlce/reading.hpp"
#include "mlce/transient.hpp"
#include "mlce/models/dynamics.hpp"
#include "mlce/models/scene.hpp"
#include "mlce/models/simulate.hpp"
#include "mlce/spectrum/floquet.hpp"
#include "mlce/spectrum/qr_spectrum.hpp"
#include "plot.hpp"
#include "spectrum_commands.hpp"
#include "sweep_runner.hpp"

namespace po = boost::program_options;

namespace mlce::cli {
namespace {

/// Speed/accuracy presets. Each names what it changes; the scene's own values are the baseline.
struct Preset {
  std::string name;
  double output_step_factor;  ///< rosenstein: dt_out x this
  double run_factor;          ///< rosenstein: t_end x this
  double rtol;                ///< integrator tolerance (every method)
  std::size_t max_references; ///< rosenstein: reference points of the divergence curve
  double qr_run_factor;       ///< qr: run length = this x the scene's t_end
  std::size_t modal_replicates; ///< modes: replicates of lambda's interval (modes.hpp step 8)
};

Preset preset_named(const std::string& name) {
  // From bench/speed_accuracy.sh (README): the run length decides the limit-cycle points, a
  // coarser output step costs less and loses nothing down to ~50 samples per limit-cycle period,
  // the integrator tolerance and the reference count hardly matter.
  if (name == "fast") return {"fast", 4.0, 2.0, 1e-6, 2000, 3.0, 20};
  if (name == "balanced") return {"balanced", 4.0, 3.0, 1e-8, 5000, 5.0, 50};
  if (name == "accurate") return {"accurate", 2.0, 6.0, 1e-10, 20000, 20.0, 100};
  throw po::error("--preset '" + name + "': expected fast, balanced or accurate");
}

std::string describe(const Preset& p) {
  return fmt::format("preset {}: rosenstein output step x{}, run x{}, {} references; integrator rtol {}; qr run {} x t_end; "
                     "modes {} replicates",
                     p.name, p.output_step_factor, p.run_factor, p.max_references, p.rtol, p.qr_run_factor, p.modal_replicates);
}

std::string cell(double v) { return fmt::format("{:.10g}", v); }

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The Stability a `stability` cell names (to_string's inverse; a resumed journal's cell too).
Stability stability_from_string(const std::string& text) {
  for (const Stability s : {Stability::stable, Stability::neutral, Stability::unstable})
    if (text == to_string(s)) return s;
  return Stability::undetermined;
}

/// The channel a rosenstein sweep estimates on: a state name, by default the lag of the blade
/// with the weakest damper (the failed one; blade 1 when all are equal) or flapping's beta.
std::size_t channel_index(const models::Scene& scene, const std::vector<std::string>& names, std::string& channel) {
  if (channel.empty()) {
    if (scene.model == "hammond") {
      const auto& h = scene.hammond;
      auto slope = [&](std::size_t i) { return h.damper[i] == models::DamperLaw::linear ? h.c[i] : h.C_L[i]; };
      std::size_t weakest = 0;
      for (std::size_t i = 1; i < h.c.size(); ++i)
        if (slope(i) < slope(weakest)) weakest = i;
      channel = "zeta" + std::to_string(weakest + 1);
    } else {
      channel = names.front();
    }
  }
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == channel) return i;
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw po::error("--channel '" + channel + "': not a state of the " + scene.model + " model (" + known + ")");
}

}  // namespace

int cmd_sweep(const std::vector<std::string>& args) {
  std::vector<std::string> params;
  std::string method = "floquet", preset_name = "balanced", out_path, plot_path, channel, sensitivity;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  double from = -1;
  bool json = false, quiet = false;
  std::size_t max_points = 0;
  int count = 0;
  po::options_description d("mlce sweep SCENE --param NAME=a:b:step [--param ...] --out RESULT.csv [options]");
  d.add_options()
      ("param", po::value(&params)->composing(), "swept scene parameter NAME=first:last:step (repeatable; the grid is their product)")
      ("method", po::value(&method), "rosenstein | modes | qr | floquet | eigen (default floquet)")
      ("preset", po::value(&preset_name), "fast | balanced | accurate (default balanced; see README)")
      ("jobs", po::value(&jobs), "points computed at once (default: all cores); results do not depend on it")
      ("out", po::value(&out_path), "result CSV (written at the end; OUT.partial keeps finished points for resuming)")
      ("plot", po::value(&plot_path), "PNG: lines for one parameter, a colour map of lambda_1 for two")
      ("sensitivity", po::value(&sensitivity), "qr, floquet: comma-separated parameters; adds columns dlambda_i/dP (paper 000 eqs. 12-28)")
      ("count", po::value(&count), "qr: only the K largest exponents (K tangent vectors; 1 = the MLCE); default all")
      ("channel", po::value(&channel), "rosenstein, modes: state to estimate on (default: lag of the weakest-damped blade; flapping: beta)")
      ("from", po::value(&from), "rosenstein: start of the analysed window (default: auto, the end of the transient as 'mlce estimate --from auto' finds it); modes: default 0")
      ("max-points", po::value(&max_points), "compute at most this many new points, then stop (exit 3; rerun to continue)")
      ("json", po::bool_switch(&json), "print one JSON object (settings, columns, rows)")
      ("quiet", po::bool_switch(&quiet), "no progress messages");
  const auto parsed = parse_scene_command(args, d);
  if (!parsed) return 0;
  const models::Scene& base = parsed->scene;
  if (params.empty()) throw po::error("give at least one --param NAME=first:last:step");
  if (out_path.empty()) throw po::error("give --out RESULT.csv");
  if (jobs == 0) throw po::error("--jobs: expected at least 1");
  if (method != "rosenstein" && method != "modes" && method != "qr" && method != "floquet" && method != "eigen")
    throw po::error("--method '" + method + "': expected rosenstein, modes, qr, floquet or eigen");
  const Preset preset = preset_named(preset_name);
  if (!plot_path.empty() && params.size() > 2)
    throw po::error("--plot: a plot needs one or two swept parameters (" + std::to_string(params.size()) + " given)");

  SweepPlan plan;
  plan.out_path = out_path;
  plan.jobs = jobs;
  plan.quiet = quiet;
  plan.max_new_points = max_points;
  for (const auto& spec : params) {
    try {
      plan.axes.push_back(parse_sweep_axis(spec));
    } catch (const std::invalid_argument& e) {
      throw po::error(e.what());
    }
    const auto names = models::parameter_names(base);
    const std::string& axis = plan.axes.back().name;
    // One parameter on two axes would make a grid whose points set it twice (the last wins): give
    // its values in one --param. A blade's value (c2) and the value of all blades (c) overlap too.
    const auto overlaps = [](const std::string& all, const std::string& one) {
      return one.size() > all.size() && one.compare(0, all.size(), all) == 0 &&
             std::all_of(one.begin() + static_cast<std::ptrdiff_t>(all.size()), one.end(),
                         [](unsigned char ch) { return std::isdigit(ch) != 0; });
    };
    // The swept key given on the command line as well (--rpm 300) would be overridden at every
    // point. (--c 300 with --param c3=... is a base for the other blades, and fine.)
    if (parsed->vm.count(axis) && !parsed->vm[axis].defaulted())
      throw po::error("--param " + spec + ": --" + axis + " sets it too (give it one or the other)");
    for (std::size_t k = 0; k + 1 < plan.axes.size(); ++k) {
      const std::string& other = plan.axes[k].name;
      if (other == axis)
        throw po::error("--param " + spec + ": " + axis + " is swept twice (give its range in one --param: " + axis +
                        "=FIRST:LAST:STEP)");
      if (overlaps(other, axis) || overlaps(axis, other))
        throw po::error("--param " + spec + ": " + axis + " and " + other + " set the same blade's value");
    }
    if (axis.rfind("init:", 0) == 0) {  // an initial state, by the model's state name
      const auto& states = models::dynamical_system(base).state_names;
      if (std::find(states.begin(), states.end(), axis.substr(5)) == states.end()) {
        std::string known;
        for (const auto& n : states) known += (known.empty() ? "" : " ") + n;
        throw po::error("--param " + spec + ": '" + axis.substr(5) + "' is not a state of the " + base.model + " model (" + known + ")");
      }
      continue;
    }
    if (std::find(names.begin(), names.end(), plan.axes.back().name) == names.end()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : " ") + n;
      throw po::error("--param " + spec + ": '" + plan.axes.back().name + "' is not a " + base.model + " parameter (" + known + ")");
    }
  }
  const ode::DynamicalSystem sys0 = models::dynamical_system(base);
  if (count != 0 && method != "qr") throw po::error("--count: only with --method qr");
  if (count < 0 || count > sys0.dimension)
    throw po::error(fmt::format("--count {}: expected 1..{} (the model's states)", count, sys0.dimension));
  const int exponents = count > 0 ? count : sys0.dimension;  // result columns per quantity
  std::vector<std::string> sensitivities;
  std::size_t channel_state = 0;
  if (method == "rosenstein") {
    channel_state = channel_index(base, sys0.state_names, channel);
    plan.result_columns = {"lambda", "ci95_low", "ci95_high", "curve_end", "n_points", "amplitude", "stability", "motion", "in_decay_floor", "note"};
  } else if (method == "modes") {
    channel_state = channel_index(base, sys0.state_names, channel);
    plan.result_columns = {"lambda", "ci95_low", "ci95_high", "frequency", "residual", "analysed_to", "stability", "reading", "note"};
  } else {
    for (int i = 0; i < exponents; ++i) plan.result_columns.push_back(fmt::format("lambda_{}", i + 1));
    if (!sensitivity.empty() && method == "eigen") throw po::error("--sensitivity: with --method qr or floquet");
    std::stringstream list(sensitivity);
    for (std::string p; std::getline(list, p, ',');) {
      if (p.empty()) continue;
      try {
        models::parameter_family(base, p);
      } catch (const std::invalid_argument& e) {
        throw po::error(std::string("--sensitivity: ") + e.what());
      }
      sensitivities.push_back(p);
      for (int i = 0; i < exponents; ++i) plan.result_columns.push_back(fmt::format("dlambda_{}/d{}", i + 1, p));
    }
    plan.result_columns.push_back("note");
  }
  const std::string unit = base.model == "flapping" ? "rad of azimuth" : "s";
  std::string settings = fmt::format("method {}, {}", method, describe(preset));
  if (method == "rosenstein") settings += fmt::format(", channel {}, from {}", channel, from < 0 ? "auto" : cell(from));
  if (method == "modes") settings += fmt::format(", channel {}, from {}", channel, cell(std::max(from, 0.0)));
  if (count > 0) settings += fmt::format(", count {} (the largest exponents only)", count);
  plan.header_comment = "# mlce sweep of " + base.source + ": " + settings + "; exponents in 1/" + unit + ", natural log\n";
  std::istringstream scene_text(models::describe_scene(base));
  for (std::string line; std::getline(scene_text, line);) plan.header_comment += "# scene: " + line + "\n";
  std::string signature_text = plan.header_comment;
  for (const auto& p : params) signature_text += p + ";";
  for (const auto& c : plan.result_columns) signature_text += c + ",";  // a journal of other columns is not resumed
  plan.signature = fmt::format("{:016x}", std::hash<std::string>{}(signature_text));

  const auto compute = [&](const std::vector<double>& values) -> std::vector<std::string> {
#ifdef _OPENMP
    if (jobs > 1) omp_set_num_threads(1);  // the points are the parallelism
#endif
    models::Scene scene = base;
    for (std::size_t a = 0; a < plan.axes.size(); ++a) {
      const std::string& axis = plan.axes[a].name;
      if (axis.rfind("init:", 0) == 0) {
        const auto& states = sys0.state_names;
        scene.x0(std::find(states.begin(), states.end(), axis.substr(5)) - states.begin()) = values[a];
      } else {
        models::set_scene_parameter(scene, axis, values[a]);
      }
    }
    scene.integrator.rtol = preset.rtol;
    std::vector<std::string> cells;
    std::vector<std::string> warnings;
    if (method == "rosenstein") {
      scene.dt_out *= preset.output_step_factor;
      scene.t_end *= preset.run_factor;
      const double t0 = from < 0 ? 0.0 : from;
      Series s;
      s.dt = scene.dt_out;
      s.time_unit = unit;
      s.names = {channel};
      s.channels.emplace_back();
      // Only the analysed channel is kept, sample by sample (not every state of the run); the samples
      // before the window only for the record's scale.
      Series record = s;
      models::simulate(scene, [&s, &record, t0, &scene, channel_state](std::size_t, double t, const Eigen::VectorXd& x) {
        const double value = x(static_cast<Eigen::Index>(channel_state));
        record.channels[0].push_back(value);
        if (t < t0 - 1e-9 * scene.dt_out) return;
        if (s.channels[0].empty()) s.t0 = t;
        s.channels[0].push_back(value);
      });
      // --from auto: cut the transient as `mlce estimate --from auto` does (a decay or a growth is
      // kept whole; a decay into the noise floor is cut at the floor by the estimator itself).
      if (from < 0) s = skip_transient(s);
      MlceOptions o;
      // The window is judged against the run it was cut from, as `mlce estimate --from` judges it: a
      // window that holds only the floor a decay ended in (solver residue, ~1e-11 of the start) reads
      // stable, decayed to rest, not "unstable" at the residue's +0.7..+1.5 1/s.
      o.record_deviation = peak_deviations(record);
      o.max_references = preset.max_references;
      o.skip_nonrecurrent_start = from < 0;  // as mlce estimate: a given window is kept
      const MlceResult r = estimate_mlce(s, o);
      // Amplitude: half the peak-to-peak range over the last quarter of the run (the settled
      // motion of a long run: limit-cycle amplitude, or what is left of a decay).
      const auto& x = s.channels[0];
      const auto [lo, hi] = std::minmax_element(x.end() - static_cast<std::ptrdiff_t>(std::max<std::size_t>(1, x.size() / 4)), x.end());
      const Reading reading = read_stability(r);
      // in_decay_floor 1: lambda is the solver's residue in the floor a decay ended in, not the motion's.
      cells = {cell(r.lambda), cell(r.ci95_low), cell(r.ci95_high), to_string(r.fit.end), std::to_string(r.n_points),
               cell(0.5 * (*hi - *lo)), to_string(reading.stability), reading.motion, r.in_decay_floor ? "1" : "0"};
      warnings = r.warnings;
    } else if (method == "modes") {
      // The run as the scene gives it (no longer run, no coarser output: a growth saturates, a decay reaches
      // its floor, and the modes need neither more periods nor fewer samples), from --from (default 0: the
      // release is the motion's clearest part).
      const double t0 = std::max(from, 0.0);
      Series s;
      s.dt = scene.dt_out;
      s.time_unit = unit;
      s.names = {channel};
      s.channels.emplace_back();
      models::simulate(scene, [&s, t0, &scene, channel_state](std::size_t, double t, const Eigen::VectorXd& x) {
        if (t < t0 - 1e-9 * scene.dt_out) return;
        if (s.channels[0].empty()) s.t0 = t;
        s.channels[0].push_back(x(static_cast<Eigen::Index>(channel_state)));
      });
      ModalOptions o;
      o.interval_replicates = preset.modal_replicates;
      // A growth that saturates is read over its leading part, a decay up to its floor (modes.hpp steps 8-9):
      // n_points samples from the window's start.
      const ModalResult r = identify_modes(s, o);
      const double analysed_to = s.time(r.n_points - 1);
      const auto optional_cell = [](const std::optional<double>& v) { return v ? cell(*v) : std::string(); };
      cells = {optional_cell(r.lambda), optional_cell(r.lambda_low), optional_cell(r.lambda_high), cell(r.lambda_mode_frequency),
               cell(r.residual), cell(analysed_to), to_string(r.stability), r.reading};
      warnings = r.warnings;
    } else {
      Eigen::VectorXd ex;
      Eigen::MatrixXd sens;
      std::vector<ode::ParameterFamily> families;
      for (const auto& p : sensitivities) families.push_back(models::parameter_family(scene, p));
      if (method == "eigen") {
        const spectrum::LinearSpectrum ls = spectrum::linear_eigen(models::time_invariant_form(scene).A);
        ex = ls.exponents, warnings = ls.warnings;
      } else if (method == "floquet") {
        spectrum::FloquetOptions o;
        o.integrator.rtol = std::min(o.integrator.rtol, preset.rtol);
        const spectrum::LinearSpectrum ls = spectrum::floquet(models::dynamical_system(scene), o, families);
        ex = ls.exponents, sens = ls.sensitivities, warnings = ls.warnings;
      } else {
        spectrum::QrOptions o;
        o.t_end = preset.qr_run_factor * scene.t_end;
        o.step = scene.dt_out;
        o.transient = 0.1 * o.t_end;
        o.integrator = scene.integrator;
        o.count = static_cast<std::size_t>(count);
        const spectrum::QrResult r = spectrum::qr_spectrum(models::dynamical_system(scene), scene.x0, o, families);
        ex = r.exponents, sens = r.sensitivities, warnings = r.warnings;
      }
      for (Eigen::Index i = 0; i < ex.size(); ++i) cells.push_back(cell(ex(i)));
      for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(families.size()); ++k)
        for (Eigen::Index i = 0; i < ex.size(); ++i) cells.push_back(cell(sens(k, i)));
    }
    std::string note;
    for (const auto& w : warnings) note += (note.empty() ? "" : " | ") + w;
    cells.push_back(note);
    return cells;
  };
  const SweepOutcome outcome = run_sweep(plan, compute);
  if (outcome.all_failed) {  // a setup the method cannot take (wrong method for the scene, too short a run)
    std::string at;
    for (std::size_t a = 0; a < plan.axes.size(); ++a)
      at += fmt::format("{}{} = {:g}", a ? ", " : "", plan.axes[a].name, outcome.values[0][a]);
    throw std::runtime_error(fmt::format("every one of the {} points failed ({} not written); the first ({}): {}",
                                         outcome.points, out_path, at,
                                         outcome.results[0].back().substr(std::string("error: ").size())));
  }
  if (outcome.failed > 0)
    print_warnings(
        {fmt::format("{} of {} points failed (see their 'note' column in {})", outcome.failed, outcome.points, out_path)});
  if (!outcome.complete) {
    std::cerr << fmt::format("mlce: sweep stopped after {} new points ({} of {} done, kept in {}.partial); rerun to continue\n",
                             outcome.computed, outcome.resumed + outcome.computed, outcome.points, out_path);
    return 3;
  }

  if (!plot_path.empty()) {
    const std::string what = method == "rosenstein" ? "MLCE (Rosenstein) on " + channel
                             : method == "modes"    ? "least damped mode (matrix pencil) of " + channel
                                                    : method + " exponents";
    if (method == "rosenstein" || method == "modes") {  // both: lambda, ci95_low, ci95_high, ..., stability at 6
      // Points drawn by their reading; one in the floor of a decay is not drawn at its residue lambda.
      std::vector<PlottedReading> points;
      for (std::size_t k = 0; k < outcome.points; ++k) {
        const auto& cells = outcome.results[k];
        const auto lambda = parse_finite(cells[0]);
        if (!lambda) continue;  // a failed point
        PlottedReading p{.x = outcome.values[k][0],
                         .y = plan.axes.size() > 1 ? outcome.values[k][1] : 0.0,
                         .lambda = *lambda,
                         .low = parse_finite(cells[1]).value_or(kNaN),
                         .high = parse_finite(cells[2]).value_or(kNaN),
                         .stability = stability_from_string(cells[6]),
                         .in_decay_floor = method == "rosenstein" && cells[8] == "1"};
        points.push_back(p);
      }
      if (plan.axes.size() == 1)
        plot_readings_png(points, what + " over " + plan.axes[0].name, plan.axes[0].name, "lambda (1/" + unit + ")",
                          plot_path, true);
      else
        plot_reading_map_png(points, what, plan.axes[0].name, plan.axes[1].name, "lambda (1/" + unit + ")", plot_path);
    } else if (plan.axes.size() == 1) {
      std::string csv = plan.axes[0].name;
      for (int c = 0; c < exponents; ++c) csv += "," + plan.result_columns[static_cast<std::size_t>(c)];
      csv += "\n";
      for (std::size_t k = 0; k < outcome.points; ++k) {
        csv += cell(outcome.values[k][0]);
        for (int c = 0; c < exponents; ++c) csv += "," + outcome.results[k][static_cast<std::size_t>(c)];
        csv += "\n";
      }
      plot_columns_png(csv, what + " over " + plan.axes[0].name, plan.axes[0].name, "lambda (1/" + unit + ")", plot_path);
    } else if (plan.axes.size() == 2) {
      std::string csv = plan.axes[0].name + "," + plan.axes[1].name + "," + plan.result_columns[0] + "\n";
      for (std::size_t k = 0; k < outcome.points; ++k)
        csv += cell(outcome.values[k][0]) + "," + cell(outcome.values[k][1]) + "," + outcome.results[k][0] + "\n";
      plot_map_png(csv, what + ": " + plan.result_columns[0], plan.axes[0].name, plan.axes[1].name,
                   plan.result_columns[0] + " (1/" + unit + ")", plot_path);
    }
  }
  if (json) {
    nlohmann::json j;
    j["scene"] = base.source;
    j["method"] = method;
    j["preset"] = preset.name;
    j["settings"] = settings;
    j["out"] = out_path;
    j["points"] = outcome.points;
    j["resumed"] = outcome.resumed;
    j["computed"] = outcome.computed;
    std::vector<std::string> columns;
    for (const auto& a : plan.axes) columns.push_back(a.name);
    columns.insert(columns.end(), plan.result_columns.begin(), plan.result_columns.end());
    j["columns"] = columns;
    j["rows"] = nlohmann::json::array();
    for (std::size_t k = 0; k < outcome.points; ++k) {
      nlohmann::json row = outcome.values[k];
      for (const auto& c : outcome.results[k]) {
        if (const auto v = parse_finite(c)) row.push_back(*v);
        else if (c.empty()) row.push_back(nullptr);  // a failed point's value
        else row.push_back(c);
      }
      j["rows"].push_back(row);
    }
    std::cout << j.dump() << "\n";
  } else {
    std::cout << fmt::format("# {} points ({} resumed, {} computed) -> {}\n", outcome.points, outcome.resumed,
                             outcome.computed, out_path);
    std::cout << "# " << settings << "\n";
  }
  return 0;
}

}  // namespace mlce::cli
