// mlce: the analyst's command line. It only wires the reader and the estimators together.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <boost/program_options.hpp>
#include <charconv>
#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <iterator>
#include <optional>
#include <tuple>
#include <string>
#include <vector>

#include "mlce/each_channel.hpp"
#include "mlce/estimate.hpp"
#include "mlce/kantz.hpp"
#include "mlce/modes.hpp"
#include "mlce/space_time.hpp"
#include "mlce/convergence.hpp"
#include "mlce/models/scene.hpp"
#include "mlce/models/simulate.hpp"
#include "mlce/reader/format.hpp"
#include "mlce/reader/table.hpp"
#include "plot.hpp"
#include "report.hpp"
#include "series_input.hpp"
#include "cli_common.hpp"
#include "spectrum_commands.hpp"
#include "compare_command.hpp"
#include "estimate_runs.hpp"

namespace po = boost::program_options;
using namespace mlce;

namespace {

using cli::kExitData;
using cli::kExitUsage;
using cli::parse;
using cli::channel_specs;
using cli::print_warnings;

const char* kUsage =
    "usage: mlce <command> [options]\n"
    "commands:\n"
    "  estimate FILE   maximum Lyapunov exponent (Rosenstein), every parameter automatic;\n"
    "                  of several runs (FILE FILE ...) as a table, against --param NAME=values\n"
    "  ami FILE        average mutual information curve and the chosen delay\n"
    "  fnn FILE        false-nearest-neighbour fractions and the chosen dimension (--method cao: Cao's E1, E2)\n"
    "  kantz FILE      Kantz's divergence curves over several radii: a second estimate beside Rosenstein's\n"
    "  modes FILE      damped modes by the matrix pencil: the least damped one's rate is a linear motion's MLCE\n"
    "  stsp FILE       space-time separation plot: how long points stay correlated (checks the Theiler window)\n"
    "  convergence FILE  MLCE of the run's leading parts: has the estimate settled, is the run long enough?\n"
    "  simulate SCENE  integrate an ad-hoc model (Hammond, flapping) and write its time history\n"
    "  spectrum SCENE  all Lyapunov exponents by the discrete QR method, with sensitivities\n"
    "  floquet SCENE   Floquet exponents of the model linearised about x = 0 (or an orbit)\n"
    "  eigen SCENE     eigenvalues of the time-invariant (multiblade) linearisation\n"
    "  eigenanalysis SET  MBDyn's own eigenanalyses (PREFIX.m, PREFIX_<k>.m, eig.* in PREFIX.nc, or the tables of\n"
    "                  PREFIX.out) as eigenvalues in 1/s\n"
    "  channels SET    what an MBDyn output set (prefix or .nc) or column file holds\n"
    "  extract SET     write the selected channels with their time as CSV\n"
    "  compare A B     two runs side by side on the same channels (max/RMS difference, ranges)\n"
    "  sweep SCENE     exponents over a parameter grid (rosenstein|modes|qr|floquet|eigen), parallel, resumable\n"
    "FILE/SET: a column file, an MBDyn output prefix (run/hammond or run/hammond.mov), or a .nc file.\n"
    "Channels (--channel, repeatable): node:L:x|y|z|r1..r9|vx..|wx.., joint:L:K, EXT:L:K (ine:11:2),\n"
    "  rel:A:B:x|y|z (rotation of node A relative to node B about B's axis, rad), col:K;\n"
    "  a number given as FIRST..LAST is one channel each: rel:11..14:4:z (four blades' lags), col:2..5.\n"
    "Run 'mlce <command> --help' for the options of a command; 'mlce --version' prints the version.\n";

/// "auto" -> nullopt, else a non-negative integer.
std::optional<std::size_t> auto_or_count(const std::string& value, const char* option) {
  if (value == "auto") return std::nullopt;
  try {
    std::size_t used = 0;
    const long long v = std::stoll(value, &used);
    if (used == value.size() && v >= 0) return static_cast<std::size_t>(v);
  } catch (const std::exception&) {
  }
  throw po::error(fmt::format("--{} '{}': expected 'auto' or a non-negative integer", option, value));
}

/// --delay, --dim, --theiler and --horizon of the commands that embed a series as mlce estimate does,
/// each 'auto' or a count. A command offers those it uses, each with its own help (nullptr: not offered).
struct EmbeddingArgs {
  struct Help {
    const char* delay = nullptr;
    const char* dim = nullptr;
    const char* theiler = nullptr;
    const char* horizon = nullptr;
  };
  std::string delay = "auto", dim = "auto", theiler = "auto", horizon = "auto";

  void add_to(po::options_description& d, const Help& help) {
    const std::tuple<const char*, std::string*, const char*> offered[] = {
        {"delay", &delay, help.delay}, {"dim", &dim, help.dim}, {"theiler", &theiler, help.theiler}, {"horizon", &horizon, help.horizon}};
    for (const auto& [name, value, text] : offered)
      if (text) d.add_options()(name, po::value(value), text);
  }
  /// Into the estimator's options: nullopt where 'auto'; anything else than a count is a usage error naming the option.
  void apply(MlceOptions& o) const {
    o.delay = auto_or_count(delay, "delay");
    o.dim = auto_or_count(dim, "dim");
    o.theiler = auto_or_count(theiler, "theiler");
    o.horizon = auto_or_count(horizon, "horizon");
  }
};

/// --align-phase auto|on|off.
PhaseAlignment phase_alignment_option(const std::string& value) {
  if (value == "auto") return PhaseAlignment::automatic;
  if (value == "on") return PhaseAlignment::on;
  if (value == "off") return PhaseAlignment::off;
  throw po::error("--align-phase '" + value + "': expected auto, on or off");
}

po::options_description series_options(cli::SeriesInput& in) {
  po::options_description d("series");
  d.add_options()
      ("channel", channel_specs(&in.channels), "channel spec (repeat for a multivariate series): node:L:F, joint:L:K, rel:A:B:AXIS, EXT:L:K, col:K; a range "
                                                    "FIRST..LAST in a number is a channel each (rel:11..14:4:z)")
      ("column", po::value(&in.columns)->composing(), "column(s) to analyse, 1-based number or header name (repeat for a multivariate series)")
      ("time-column", po::value<std::string>(), "column holding time, 1-based number or header name (must be uniform)")
      ("dt", po::value<double>(), "sampling step when the file has no time column")
      ("time-unit", po::value(&in.time_unit)->default_value("s"), "name of the time unit")
      ("resample", po::bool_switch(&in.resample), "resample a non-uniform time column linearly (explicit opt-in)")
      ("despike", po::bool_switch(&in.despike), "replace isolated spikes (1-3 samples jumped into and out of by more than 8 times any other jump: a glitch) by the line between their neighbours, with a warning each; without it they are an error")
      ("from", po::value(&in.from), "start of the analysed window (time units), or 'auto' to skip the transient")
      ("to", po::value<double>(), "end of the analysed window (time units); later samples are not read, so a run that diverged after it can be analysed");
  return d;
}

void finish_series_options(const po::variables_map& vm, cli::SeriesInput& in) {
  if (vm.count("time-column")) in.time_column = vm["time-column"].as<std::string>();
  if (vm.count("dt")) in.dt = vm["dt"].as<double>();
  if (vm.count("to")) in.to = vm["to"].as<double>();
  if (in.to && std::isnan(*in.to)) throw po::error("--to 'nan': expected a time (inf reads to the end)");
  if (!vm.count("file")) throw po::error("missing FILE");
  // One FILE, or the first of several (mlce estimate RUN1 RUN2 ...: parse(..., several_files)).
  const auto* several = boost::any_cast<std::vector<std::string>>(&vm["file"].value());
  in.file = several ? several->front() : vm["file"].as<std::string>();
}

/// Stage messages on stderr once a run has lasted a second (short runs stay quiet).
ProgressCallback progress_printer(bool quiet) {
  if (quiet) return {};
  const auto start = std::chrono::steady_clock::now();
  return [start](std::string_view stage, double) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (s > 1.0) std::fprintf(stderr, "mlce: %.1f s: %.*s\n", s, static_cast<int>(stage.size()), stage.data());
  };
}

/// What an estimate's JSON says of its input: the file, where the analysis starts, and the
/// transient rule when --from auto decided it.
void add_input(nlohmann::json& j, const cli::SeriesInput& in, const cli::LoadedSeries& loaded, double analysed_from) {
  j["file"] = in.file;
  j["from"] = analysed_from;
  if (!loaded.transient_rule.empty()) j["transient_rule"] = loaded.transient_rule;
}

/// The same for people: the file line, and the window's line when --from auto moved its start.
std::string input_lines(const cli::SeriesInput& in, const cli::LoadedSeries& loaded) {
  std::string s = "file            " + in.file + "\n";
  if (!loaded.transient_rule.empty())
    s += fmt::format("window          from {:.6g} ({})\n", loaded.series.t0, loaded.transient_rule);
  return s;
}

/// mlce estimate --each: every channel of the loaded series on its own, and the verdict.
int estimate_each(const cli::SeriesInput& in, const cli::LoadedSeries& loaded, const MlceOptions& o, bool json,
                  const std::string& curve_path, const std::string& plot_path) {
  EachChannelOptions eo;
  eo.estimate = o;
  EachChannelResult r = cli::on_file(in, [&] { return estimate_each_channel(loaded.series, eo); });
  r.warnings.insert(r.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
  if (!curve_path.empty()) cli::write_file_atomically(curve_path, cli::each_channel_curves_csv(r));
  if (!plot_path.empty()) cli::plot_each_channel_png(r, plot_path);
  if (json) {
    auto j = cli::to_json(r);
    add_input(j, in, loaded, loaded.series.time(0));  // each channel's own skipped_start is in its entry
    std::cout << j.dump() << "\n";
  } else {
    std::cout << input_lines(in, loaded) << cli::to_text(r, loaded.series.t0);
  }
  // Every channel is analysed or the run is a data error: a script must not take a table with a
  // hole in it for the whole answer (the table and the verdict over the rest are printed above),
  // and stderr says so in one line, as for any other data error.
  if (r.estimated == r.channels.size()) return 0;
  std::vector<std::string> missing;
  for (const auto& c : r.channels)
    if (!c.result) missing.push_back(c.name);
  std::fprintf(stderr, "mlce estimate: error: %s: %zu of %zu channels could not be estimated (%s); the others are above\n",
               in.file.c_str(), missing.size(), r.channels.size(), fmt::format("{}", fmt::join(missing, ", ")).c_str());
  return kExitData;
}

int cmd_estimate(const std::vector<std::string>& args) {
  cli::SeriesInput in;
  EmbeddingArgs embedding;
  std::string fit = "auto", refs = "20000", align = "auto", interpolation = "linear", compensation = "auto";
  std::string curve_path, plot_path, csv_path, param;
  bool json = false, quiet = false, keep_start = false, each = false;
  po::options_description d("mlce estimate FILE [FILE ...] [options]");
  d.add(series_options(in));
  po::options_description e("estimator");
  embedding.add_to(e, {.delay = "reconstruction delay J in samples, or auto (first AMI minimum)",
                       .dim = "embedding dimension m, or auto (false nearest neighbours)",
                       .theiler = "Theiler window in samples, or auto (mean period, eq. 19)",
                       .horizon = "divergence curve length in samples, or auto (adaptive)"});
  e.add_options()
      ("fit", po::value(&fit), "fit region A:B in curve steps, or auto")
      ("refs", po::value(&refs), "reference points of the curve (evenly strided, >= 1), or 'all'; default (and auto) 20000")
      ("eps", po::value<double>(), "approximate neighbour search: neighbours within (1+eps) x the nearest distance are accepted (nanoflann eps; default 0 = exact)")
      ("align-phase", po::value(&align), "move each neighbour along its trajectory to the reference's sub-sample phase: auto (sampled flows whose curve saturates), on, off")
      ("phase-interpolation", po::value(&interpolation), "how an aligned neighbour's trajectory is read between samples: linear (default) or cubic (for output with few samples per loop of the motion)")
      ("noise-compensation", po::value(&compensation), "auto (default): a decay whose increments show white measurement noise is read from the noise-compensated curve, ln <d^2>/2 less the noise's share; off: eq. 23's <ln d> always")
      ("dither", po::value<double>(), "add uniform noise of this width (the signal's quantum, in its units) before estimating: for quantised signals; default 0 = none")
      ("seed", po::value<std::string>(), "seed of the dither's noise (default 1; the same seed gives the same result)")
      ("surrogates", po::value<std::string>(), "test the divergence against surrogates with the series' spectrum and values (IAAFT; several channels embedded jointly: multivariate, keeping their cross-spectra): chaos is read only when it exceeds all of them (p = 1/(K+1)) by 3 standard deviations. auto (default): 19, on the first 4096 samples (30 IAAFT passes, 2000 references), where the curve alone reads chaos; K: K on the whole part analysed (several channels: its segment whose ends meet), whatever the curve reads (19 gives p = 0.05); 0: no test")
      ("keep-start", po::bool_switch(&keep_start), "analyse the series from its first sample (or --from) even when its start does not recur (by default such a start-up transient is left out, with a warning; a --from time keeps its start too)")
      ("each", po::bool_switch(&each), "estimate every channel (two or more --channel/--column) on its own and say whether their 95 % intervals agree: the observables of one motion share its exponent")
      ("json", po::bool_switch(&json), "print one JSON object on stdout")
      ("curve", po::value(&curve_path), "write the divergence curve as CSV (--each: every channel's, one after the other)")
      ("plot", po::value(&plot_path), "write the divergence curve and fit as PNG (gnuplot; --each: every channel's)")
      ("quiet", po::bool_switch(&quiet), "no progress messages");
  d.add(e);
  po::options_description runs("several runs (FILE FILE ...: the same channels of each, one estimate a run, as a table)");
  runs.add_options()
      ("param", po::value(&param), "NAME=v1,v2,... or NAME=first:last:step: the value of a parameter in each run, in the order "
                                   "the runs are given (the table's column and the plot's x axis)")
      ("csv", po::value(&csv_path), "write the table as CSV");
  d.add(runs);
  const auto parsed = parse(args, d, /*several_files=*/true);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  finish_series_options(vm, in);
  MlceOptions o;
  embedding.apply(o);
  if (refs == "all") o.max_references = 0;  // the estimator's 0 means every admissible point
  else o.max_references = auto_or_count(refs, "refs").value_or(20000);
  if (refs != "all" && o.max_references == 0) throw po::error("--refs '0': expected 'all', 'auto' or a count >= 1");
  if (vm.count("eps")) {
    o.eps = vm["eps"].as<double>();
    if (!(o.eps >= 0.0) || !std::isfinite(o.eps)) throw po::error("--eps: expected a non-negative number");
  }
  if (vm.count("dither")) {
    o.dither = vm["dither"].as<double>();
    if (!(o.dither >= 0.0) || !std::isfinite(o.dither)) throw po::error("--dither: expected a width >= 0");
  }
  if (vm.count("seed")) {
    const std::string seed = vm["seed"].as<std::string>();  // parsed here: "-3" is an error, not 2^64 - 3
    const auto [end, ec] = std::from_chars(seed.data(), seed.data() + seed.size(), o.dither_seed);
    if (ec != std::errc() || end != seed.data() + seed.size())
      throw po::error("--seed '" + seed + "': expected an integer 0 .. 2^64-1");
  }
  if (vm.count("surrogates") && vm["surrogates"].as<std::string>() != "auto") {
    const std::string k = vm["surrogates"].as<std::string>();
    const auto [end, ec] = std::from_chars(k.data(), k.data() + k.size(), o.surrogates.count);
    if (ec != std::errc() || end != k.data() + k.size() || o.surrogates.count > 999)
      throw po::error("--surrogates '" + k + "': expected auto or a count 0 .. 999");
    o.surrogates_when = o.surrogates.count == 0 ? SurrogateWhen::never : SurrogateWhen::always;
    o.surrogates = SurrogateOptions{.count = o.surrogates.count};  // asked for: the whole part analysed, 200 passes
  }
  o.phase_alignment = phase_alignment_option(align);
  if (compensation == "auto") o.noise_compensation = NoiseCompensation::automatic;
  else if (compensation == "off") o.noise_compensation = NoiseCompensation::off;
  else throw po::error("--noise-compensation '" + compensation + "': expected auto or off");
  if (interpolation == "linear") o.phase_interpolation = RosensteinOptions::Interpolation::linear;
  else if (interpolation == "cubic") o.phase_interpolation = RosensteinOptions::Interpolation::cubic;
  else throw po::error("--phase-interpolation '" + interpolation + "': expected linear or cubic");
  if (fit != "auto") {
    const auto colon = fit.find(':');
    if (colon == std::string::npos) throw po::error("--fit '" + fit + "': expected auto or A:B");
    const auto a = auto_or_count(fit.substr(0, colon), "fit"), b = auto_or_count(fit.substr(colon + 1), "fit");
    if (!a || !b) throw po::error("--fit '" + fit + "': expected auto or A:B");
    o.fit.range = std::make_pair(*a, *b);
  }
  o.progress = progress_printer(quiet);
  // A start the user chose is kept; --from auto is a transient rule too, and both apply.
  o.skip_nonrecurrent_start = !keep_start && in.start_is_automatic();

  if (each && in.channels.size() + in.columns.size() < 2)
    throw po::error("--each: give two or more --channel or --column to estimate one by one");

  const auto& files = vm["file"].as<std::vector<std::string>>();
  if (files.size() > 1) {
    if (each) throw po::error("--each: one FILE's channels one by one; with several runs give one channel set");
    if (!curve_path.empty()) throw po::error("--curve: one run's divergence curve; with several runs --csv writes the table");
    std::optional<cli::RunParameter> parameter;
    if (!param.empty()) {
      try {
        parameter = cli::parse_run_parameter(param, files.size());
      } catch (const std::invalid_argument& x) {
        throw po::error(x.what());
      }
    }
    return cli::estimate_runs(files, in, o, parameter, {json, quiet, csv_path, plot_path});
  }
  if (!param.empty() || !csv_path.empty())
    throw po::error(std::string(param.empty() ? "--csv" : "--param") +
                    ": the table of several runs; give two or more FILEs (one run's curve: --curve)");

  in.constant_channels_allowed = each;
  cli::LoadedSeries loaded = cli::load_series(in);
  o.record_deviation = loaded.record_deviation;
  if (each) return estimate_each(in, loaded, o, json, curve_path, plot_path);
  MlceResult r = cli::on_file(in, [&] { return estimate_mlce(loaded.series, o); });
  const double analysed_from = loaded.series.time(r.skipped_start);
  r.warnings.insert(r.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
  if (!curve_path.empty()) cli::write_file_atomically(curve_path, cli::curve_csv(r));
  if (!plot_path.empty()) cli::plot_curve_png(r, plot_path);
  if (json) {
    auto j = cli::to_json(r);
    add_input(j, in, loaded, analysed_from);
    std::cout << j.dump() << "\n";
  } else {
    std::cout << input_lines(in, loaded);
    if (r.skipped_start > 0)
      std::cout << fmt::format("window          from {:.6g} (the first {} samples do not recur: left out)\n",
                               analysed_from, r.skipped_start);
    std::cout << cli::to_text(r);
  }
  return 0;
}

int cmd_ami(const std::vector<std::string>& args) {
  cli::SeriesInput in;
  AmiOptions o;
  bool json = false;
  std::string csv_path, plot_path;
  po::options_description d("mlce ami FILE [options]");
  d.add(series_options(in));
  d.add_options()
      ("max-delay", po::value(&o.max_delay), "largest delay (0 = auto)")
      ("bins", po::value(&o.bins), "histogram bins (0 = Sturges)")
      ("csv", po::value(&csv_path), "write the curve as CSV (tau, ami, smoothed)")
      ("plot", po::value(&plot_path), "write the curve with the chosen delay as PNG (gnuplot)")
      ("json", po::bool_switch(&json), "print one JSON object");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  finish_series_options(vm, in);
  const auto loaded = cli::load_series(in);
  const AmiResult r = cli::on_file(in, [&] {
    const MeanPeriodResult mp = estimate_mean_period(loaded.series, {});  // as mlce estimate's delay rule
    o.mean_period = mp.rule_period(), o.map = mp.map;
    return estimate_delay_ami(loaded.series, o);
  });
  if (!csv_path.empty()) cli::write_file_atomically(csv_path, cli::ami_csv(r));
  if (!plot_path.empty())
    cli::plot_columns_png(cli::ami_csv(r), "average mutual information: " + in.file, "delay tau (samples)",
                          "I(tau) (nats)", plot_path,
                          {{static_cast<double>(r.delay), fmt::format("delay {} ({})", r.delay, to_string(r.rule))}});
  if (json) std::cout << cli::to_json(r).dump() << "\n";
  else std::cout << cli::to_text(r);
  print_warnings(loaded.warnings);
  return 0;
}

int cmd_fnn(const std::vector<std::string>& args) {
  cli::SeriesInput in;
  FnnOptions o;
  CaoOptions cao;
  EmbeddingArgs embedding;
  std::string method = "kennel", csv_path, plot_path;
  bool json = false;
  bool quiet = false;
  po::options_description d("mlce fnn FILE [options]");
  d.add(series_options(in));
  d.add_options()
      ("method", po::value(&method), "kennel (false fractions, the estimator's rule) or cao (Cao's E1, E2: a second "
                                     "estimate of m and a test of determinism)");
  embedding.add_to(d, {.delay = "delay in samples, or auto (first AMI minimum)",
                       .theiler = "Theiler window, or auto (mean period)"});
  d.add_options()
      ("max-dim", po::value(&o.max_dim), "largest dimension tested")
      ("rtol", po::value(&o.rtol), "Kennel R_tol")
      ("atol", po::value(&o.atol), "Kennel A_tol")
      ("threshold", po::value(&o.threshold), "false fraction that accepts m (kennel)")
      ("saturation", po::value(&cao.saturation), "E1 within this of 1 accepts d (cao)")
      ("stochastic-tolerance", po::value(&cao.stochastic_tolerance), "every E2 within this of 1: looks stochastic (cao)")
      ("quiet", po::bool_switch(&quiet), "no progress messages")
      ("csv", po::value(&csv_path), "write the fractions as CSV (m, false_fraction, tested, tree_points; "
                                    "cao: d, E, E1, E2, pairs)")
      ("plot", po::value(&plot_path), "write the fractions (cao: E1, E2), the threshold and the chosen m as PNG (gnuplot)")
      ("json", po::bool_switch(&json), "print one JSON object");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  if (method != "kennel" && method != "cao") throw po::error("--method '" + method + "': expected kennel or cao");
  o.progress = cao.progress = progress_printer(quiet);
  finish_series_options(vm, in);
  const auto loaded = cli::load_series(in);
  MlceOptions delay_only;  // the delay and Theiler window given, else as the estimator chooses them
  embedding.apply(delay_only);
  delay_only.dim = 1;  // the dimension is what this command shows
  std::size_t J = 0;
  const auto embedding_before_dimension = [&] {
    const MeanPeriodResult mean_period = estimate_mean_period(loaded.series, {});
    o.theiler = cao.theiler = delay_only.theiler.value_or(mean_period.mean_period);
    J = choose_embedding(loaded.series, delay_only, mean_period).delay;
  };
  // One way out for either method: CSV, the plotted curves with the chosen m, JSON or text.
  const auto write = [&](const auto& r, const std::string& csv, const std::string& plotted, const std::string& title,
                         const char* ylabel) {
    if (!csv_path.empty()) cli::write_file_atomically(csv_path, csv);
    if (!plot_path.empty())
      cli::plot_columns_png(plotted, fmt::format("{} (delay {}, Theiler window {}): {}", title, J, o.theiler, in.file),
                            "embedding dimension m", ylabel, plot_path,
                            {{static_cast<double>(r.dim), fmt::format("m = {}", r.dim)}});
    if (json) {
      auto j = cli::to_json(r);
      j["delay"] = J;
      j["theiler"] = o.theiler;
      std::cout << j.dump() << "\n";
    } else {
      std::cout << fmt::format("# delay {} samples, Theiler window {} samples\n", J, o.theiler) << cli::to_text(r);
    }
    print_warnings(loaded.warnings);
    return 0;
  };
  if (method == "cao") {
    cao.max_dim = o.max_dim;
    const CaoResult r = cli::on_file(in, [&] {
      embedding_before_dimension();
      return estimate_dimension_cao(loaded.series, J, cao);
    });
    std::string plotted = "d,E1,E2\n";
    for (std::size_t k = 0; k < r.e1.size(); ++k) plotted += fmt::format("{},{:.10g},{:.10g}\n", k + 1, r.e1[k], r.e2[k]);
    return write(r, cli::cao_csv(r), plotted, "Cao's E1 and E2", "E1, E2");
  }
  const FnnResult r = cli::on_file(in, [&] {
    embedding_before_dimension();
    return estimate_dimension_fnn(loaded.series, J, o);
  });
  std::string plotted = "m,false fraction,threshold\n";
  for (std::size_t m = 0; m < r.fraction.size(); ++m) plotted += fmt::format("{},{:.10g},{:g}\n", m + 1, r.fraction[m], o.threshold);
  return write(r, cli::fnn_csv(r), plotted, "false nearest neighbours", "false fraction");
}

/// "a,b,c" -> the numbers, each accepted by `valid` (given the numbers before it), else one usage error
/// naming --`option` and what it expects.
template <class Valid>
std::vector<double> number_list(const std::string& text, const char* option, const char* expected, Valid valid) {
  std::vector<double> v;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const auto value = cli::parse_finite(text.substr(start, comma - start));
    if (!value || !valid(*value, v)) throw po::error(fmt::format("--{} '{}': expected {}", option, text, expected));
    v.push_back(*value);
    start = comma + 1;
  }
  return v;
}

/// "0.01,0.1,0.5" -> fractions (validated by SpaceTimeOptions).
std::vector<double> fraction_list(const std::string& text) {
  return number_list(text, "fractions", "comma-separated fractions in (0, 1)",
                     [](double f, const std::vector<double>&) { return f > 0.0 && f < 1.0; });
}

/// "0.01,0.02,0.05" -> increasing radii (validated by KantzOptions).
std::vector<double> radius_list(const std::string& text) {
  return number_list(text, "radii", "'auto' or increasing comma-separated radii > 0",
                     [](double r, const std::vector<double>& before) { return r > 0.0 && (before.empty() || r > before.back()); });
}

int cmd_stsp(const std::vector<std::string>& args) {
  cli::SeriesInput in;
  SpaceTimeOptions o;
  EmbeddingArgs embedding;
  std::string fractions, csv_path, plot_path;
  bool json = false;
  po::options_description d("mlce stsp FILE [options]");
  d.add(series_options(in));
  embedding.add_to(d, {.delay = "delay in samples, or auto (first AMI minimum, as estimate)",
                       .dim = "embedding dimension, or auto (false nearest neighbours, as estimate)"});
  d.add_options()
      ("max-separation", po::value(&o.max_separation), "largest separation in samples (0 = 4 mean periods)")
      ("step", po::value(&o.step), "spacing of the separations in samples (0 = about 200 rows)")
      ("fractions", po::value(&fractions), "contour levels, comma-separated (default 0.01,0.1,0.5)")
      ("pairs", po::value(&o.max_pairs), "pairs per separation, evenly strided (0 = all)")
      ("json", po::bool_switch(&json), "print one JSON object")
      ("csv", po::value(&csv_path), "write the contours as CSV")
      ("plot", po::value(&plot_path), "write the contours as PNG (gnuplot)");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  finish_series_options(vm, in);
  if (!fractions.empty()) o.fractions = fraction_list(fractions);
  MlceOptions eo;  // the embedding given, else the estimator's: AMI delay, then FNN with the mean-period Theiler window
  embedding.apply(eo);
  if (eo.delay == 0u || eo.dim == 0u) throw po::error("--delay and --dim: expected 'auto' or at least 1");
  const auto loaded = cli::load_series(in);
  const SpaceTimeResult r = cli::on_file(in, [&] {
    const MeanPeriodResult mp = estimate_mean_period(loaded.series, {});
    o.mean_period = mp.mean_period;
    const Embedding e = choose_embedding(loaded.series, eo, mp);
    o.delay = e.delay, o.dim = e.dim;
    return space_time_separation(loaded.series, o);
  });
  const double dt = loaded.series.dt;
  const std::string& unit = loaded.series.time_unit;
  if (!csv_path.empty()) cli::write_file_atomically(csv_path, cli::space_time_csv(r, dt));
  if (!plot_path.empty()) {
    const std::string x_label = unit.empty() ? "separation (samples)" : "separation (" + unit + ")";
    std::string data = x_label;
    for (const double f : r.fractions) data += fmt::format(",{:g} of the pairs", f);
    data += "\n";
    for (std::size_t k = 0; k < r.separation.size(); ++k) {
      data += fmt::format("{:.10g}", dt * static_cast<double>(r.separation[k]));
      for (const auto& c : r.contour) data += fmt::format(",{:.10g}", c[k]);
      data += "\n";
    }
    cli::plot_columns_png(data, "space-time separation: " + in.file, x_label, "distance (standard deviations)", plot_path,
                          {{dt * static_cast<double>(r.mean_period), "mean period (Theiler window)"},
                           {dt * static_cast<double>(r.decorrelation), "decorrelation"}});
  }
  if (json) {
    auto j = cli::to_json(r, dt, unit);
    j["file"] = in.file;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << cli::to_text(r, dt, unit);
  }
  print_warnings(loaded.warnings);
  return 0;
}

int cmd_kantz(const std::vector<std::string>& args) {
  cli::SeriesInput in;
  KantzOptions ko;
  EmbeddingArgs embedding;
  std::string radii = "auto", align = "auto", csv_path, plot_path;
  bool json = false, quiet = false, keep_start = false;
  po::options_description d("mlce kantz FILE [options]");
  d.add(series_options(in));
  embedding.add_to(d, {.delay = "delay in samples, or auto (as estimate)",
                       .dim = "embedding dimension, or auto (as estimate)",
                       .theiler = "Theiler window in samples, or auto (as estimate)",
                       .horizon = "curve length in samples, or auto (the estimate's adaptive horizon)"});
  d.add_options()
      ("radii", po::value(&radii), "neighbourhood radii, comma-separated and increasing, in standard deviations of the "
                                   "channels (Euclidean distance of delay vectors), or auto: 4 radii doubling from the "
                                   "median nearest-neighbour distance")
      ("refs", po::value(&ko.max_references), "reference points, evenly strided (0 = all; default 4000)")
      ("neighbours", po::value(&ko.max_neighbours), "neighbours averaged per reference at most, evenly strided in time "
                                                    "(0 = all; default 64)")
      ("align-phase", po::value(&align), "move each neighbour along its trajectory to the reference's sub-sample phase: "
                                         "auto (as the estimate's reported curve), on, off")
      ("keep-start", po::bool_switch(&keep_start), "analyse from the first sample even when the start does not recur (as estimate)")
      ("json", po::bool_switch(&json), "print one JSON object")
      ("csv", po::value(&csv_path), "write the curves S(radius, step) as CSV")
      ("plot", po::value(&plot_path), "write the curves, with the median radius' fit region, as PNG (gnuplot)")
      ("quiet", po::bool_switch(&quiet), "no progress messages");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  finish_series_options(vm, in);
  MlceOptions o;
  embedding.apply(o);
  if (radii != "auto") ko.radii = radius_list(radii);
  ko.phase_alignment = phase_alignment_option(align);
  o.progress = ko.progress = progress_printer(quiet);
  o.skip_nonrecurrent_start = !keep_start && in.start_is_automatic();
  o.surrogates_when = SurrogateWhen::never;  // Kantz's curves take the estimate's settings, not its reading
  const cli::LoadedSeries loaded = cli::load_series(in);
  o.record_deviation = loaded.record_deviation;
  // The estimate chooses the embedding, the Theiler window and the horizon, and its fit options read
  // the series (its period, its own decay); Kantz's curves are fitted alike and set beside it.
  KantzResult r = cli::on_file(in, [&] { return estimate_kantz(loaded.series, estimate_mlce(loaded.series, o), ko); });
  r.warnings.insert(r.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
  const std::string csv = cli::kantz_csv(r);
  if (!csv_path.empty()) cli::write_file_atomically(csv_path, csv);
  if (!plot_path.empty()) {
    const KantzRadius& middle = r.radii[r.radii.size() / 2];
    const std::string plotted = cli::kantz_csv(r, /*with_step=*/false);  // time against the curves
    const std::string x_label = r.time_unit.empty() ? "step (samples)" : "time (" + r.time_unit + ")";
    cli::plot_columns_png(plotted, "Kantz's curves S(radius, t): " + in.file, x_label, "S = <ln <distance>> (natural log)",
                          plot_path,
                          {{r.dt * static_cast<double>(middle.fit.first), "fit (median radius)"},
                           {r.dt * static_cast<double>(middle.fit.last), ""}});
  }
  if (json) {
    auto j = cli::to_json(r);
    j["file"] = in.file;
    j["from"] = loaded.series.time(r.first_sample);
    std::cout << j.dump() << "\n";
  } else {
    std::cout << input_lines(in, loaded) << cli::to_text(r);
  }
  return 0;
}

int cmd_modes(const std::vector<std::string>& args) {
  cli::SeriesInput in;
  ModalOptions o;
  std::string order = "auto", csv_path, plot_path;
  bool json = false, quiet = false;
  long long replicates = 100;  // signed: "-1" is refused as -1, not wrapped to 2^64 - 1
  po::options_description d("mlce modes FILE [options]");
  d.add(series_options(in));
  d.add_options()
      ("order", po::value(&order), "model order (poles, a complex pair counting 2), or auto: the Hankel matrix's singular "
                                   "values above 4 x its noise floor")
      ("replicates", po::value(&replicates), "records of the fitted modes plus noise like the residual whose "
                                                         "spread gives lambda's 95 % interval (default 100; 0 = no interval)")
      ("quiet", po::bool_switch(&quiet), "no progress messages")
      ("json", po::bool_switch(&json), "print one JSON object")
      ("csv", po::value(&csv_path), "write the modes as CSV (sigma,frequency,damping_ratio,share,peak_share,offset)")
      ("plot", po::value(&plot_path), "write the record and its modal fit as PNG (gnuplot)");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  finish_series_options(vm, in);
  o.order = auto_or_count(order, "order");
  if (o.order && (*o.order < 1 || *o.order > o.max_order))
    throw po::error(fmt::format("--order '{}': expected auto or 1 .. {}", order, o.max_order));
  if (replicates < 0 || replicates == 1 || replicates > 100000)
    throw po::error(fmt::format("--replicates {}: expected 0 (no interval) or 2 .. 100000", replicates));
  o.interval_replicates = static_cast<std::size_t>(replicates);
  const cli::LoadedSeries loaded = cli::load_series(in);
  o.record_deviation = loaded.record_deviation;  // a --from/--to window is judged against its record's floor
  o.progress = progress_printer(quiet);
  ModalResult r = cli::on_file(in, [&] { return identify_modes(loaded.series, o); });
  r.warnings.insert(r.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
  if (!csv_path.empty()) cli::write_file_atomically(csv_path, cli::modes_csv(r));
  if (!plot_path.empty()) {
    // The record and its modal fit; a long record every k-th sample (at most 20000 rows drawn).
    const auto fitted = modal_reconstruction(r);
    const Series& s = loaded.series;
    std::string data = "time";
    for (std::size_t c = 0; c < s.channel_count(); ++c) data += "," + channel_name(s, c) + ",modes of " + channel_name(s, c);
    data += "\n";
    const std::size_t every = (r.n_points + 19999) / 20000;
    for (std::size_t i = 0; i < r.n_points; i += every) {  // the samples analysed (up to a floor cut off)
      data += fmt::format("{:.10g}", s.time(i));
      for (std::size_t c = 0; c < s.channel_count(); ++c) data += fmt::format(",{:.10g},{:.10g}", s.channels[c][i], fitted[c][i]);
      data += "\n";
    }
    const std::string unit = s.time_unit.empty() ? "sample" : "time (" + s.time_unit + ")";
    cli::plot_columns_png(data, fmt::format("modes of {}: residual {:.3g}", in.file, r.residual), unit, "value", plot_path);
  }
  if (json) {
    auto j = cli::to_json(r);
    add_input(j, in, loaded, loaded.series.t0);
    std::cout << j.dump() << "\n";
  } else {
    std::cout << input_lines(in, loaded) << cli::to_text(r);
  }
  return 0;
}

int cmd_convergence(const std::vector<std::string>& args) {
  cli::SeriesInput in;
  ConvergenceOptions o;
  EmbeddingArgs embedding;
  std::string csv_path, plot_path;
  bool json = false, quiet = false;
  po::options_description d("mlce convergence FILE [options]");
  d.add(series_options(in));
  d.add_options()("parts", po::value(&o.parts), "estimate the first k/parts of the run, k = 1..parts (default 8)");
  embedding.add_to(d, {.delay = "delay in samples for every part, or auto (re-estimated per part)",
                       .dim = "embedding dimension for every part, or auto",
                       .theiler = "Theiler window for every part, or auto (each part's mean period)"});
  d.add_options()
      ("json", po::bool_switch(&json), "print one JSON object")
      ("csv", po::value(&csv_path), "write the table as CSV")
      ("plot", po::value(&plot_path), "write lambda and its interval against the run length as PNG (gnuplot)")
      ("quiet", po::bool_switch(&quiet), "no progress messages");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  finish_series_options(vm, in);
  embedding.apply(o.estimate);
  o.estimate.progress = progress_printer(quiet);
  o.estimate.skip_nonrecurrent_start = in.start_is_automatic();  // as mlce estimate
  const auto loaded = cli::load_series(in);
  o.estimate.record_deviation = loaded.record_deviation;  // each part is a window of the record, as in estimate
  ConvergenceResult r = cli::on_file(in, [&] { return estimate_convergence(loaded.series, o); });
  r.warnings.insert(r.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
  const std::string unit = loaded.series.time_unit.empty() ? "1/sample" : "1/" + loaded.series.time_unit;
  if (!csv_path.empty()) cli::write_file_atomically(csv_path, cli::convergence_csv(r));
  if (!plot_path.empty()) {
    const std::string x_label =
        loaded.series.time_unit.empty() ? "end of the part (sample)" : "end of the part (" + loaded.series.time_unit + ")";
    // Each part by its reading; a part in the floor a decay ended in is not drawn at its residue.
    std::vector<cli::PlottedReading> points;
    for (const auto& p : r.points)
      if (p.estimated)
        points.push_back({.x = p.t_end,
                          .lambda = p.lambda,
                          .low = p.ci95_low,
                          .high = p.ci95_high,
                          .stability = p.stability,
                          .in_decay_floor = p.in_decay_floor});
    if (!points.empty())
      cli::plot_readings_png(points, "MLCE of the leading parts: " + in.file, x_label, "lambda (" + unit + ")",
                             plot_path, true, {{loaded.series.time(loaded.series.size() / 2), "half the run"}});
  }
  if (json) {
    auto j = cli::to_json(r, unit);
    j["file"] = in.file;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "file " << in.file << "\n" << cli::to_text(r, unit);
  }
  return 0;
}

int cmd_simulate(const std::vector<std::string>& args) {
  std::string out_prefix, format = "mbdyn";
  bool quiet = false;
  po::options_description d("mlce simulate SCENE [--key value ...] --out PREFIX [options]");
  d.add_options()
      ("out", po::value(&out_prefix), "output prefix: PREFIX.{log,out,mov} (mbdyn) or PREFIX.txt (columns)")
      ("format", po::value(&format), "mbdyn (MBDyn text set, Hammond only) | columns (time and every state)")
      ("quiet", po::bool_switch(&quiet), "no progress messages");
  const auto parsed = cli::parse_scene_command(args, d);
  if (!parsed) return 0;
  if (out_prefix.empty()) throw po::error("give --out PREFIX");
  if (format != "mbdyn" && format != "columns") throw po::error("--format '" + format + "': expected mbdyn or columns");
  const models::Scene& scene = parsed->scene;
  const auto start = std::chrono::steady_clock::now();
  cli::ProgressLine progress("simulated", quiet);
  // The samples are written as the integration reaches them (a run of any length in constant
  // memory), through temporaries that only a finished run renames into place.
  std::size_t samples = 0;
  double t_reached = 0.0;
  ode::IntegrationStats stats;
  auto counted = [&](auto& writer) {
    return [&](std::size_t k, double t, const Eigen::VectorXd& x) {
      writer(k, t, x);
      samples = k + 1, t_reached = t;
    };
  };
  if (format == "mbdyn") {
    const cli::ScratchGuard scratch(models::MbdynSetWriter::scratch_files(out_prefix));  // before they exist
    models::MbdynSetWriter writer(scene, out_prefix);
    stats = models::simulate(scene, counted(writer), std::ref(progress));
    writer.commit();
  } else {
    cli::AtomicFile f(out_prefix + ".txt");
    models::ColumnsWriter writer(f.stream(), models::state_names(scene), out_prefix + ".txt");
    stats = models::simulate(scene, counted(writer), std::ref(progress));
    f.commit();
  }
  cli::write_file_atomically(out_prefix + ".scene", "# the scene as run (mlce simulate)\n" + models::describe_scene(scene));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "mlce: %zu samples to t = %g, %zu steps (%zu rejected), %zu evaluations, %.3f s; wrote %s.%s\n",
               samples, t_reached, stats.steps, stats.rejected, stats.evaluations, secs,
               out_prefix.c_str(), format == "mbdyn" ? "{log,out,mov}" : "txt");
  return 0;
}

int cmd_channels(const std::vector<std::string>& args) {
  bool json = false;
  po::options_description d("mlce channels SET [options]");
  d.add_options()("json", po::bool_switch(&json), "print one JSON object");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  if (!vm.count("file")) throw po::error("missing SET (an MBDyn output prefix, a .nc file or a column file)");
  const std::string file = vm["file"].as<std::string>();
  const reader::Inventory inv = reader::default_registry().for_path(file).describe(file);
  if (json) {
    nlohmann::json j;
    j["source"] = inv.source;
    j["format"] = inv.format;
    j["blocks"] = inv.blocks;
    j["time"] = {inv.t_first, inv.t_last};
    j["nodes"] = nlohmann::json::array();
    for (const auto& n : inv.nodes)
      j["nodes"].push_back({{"label", n.label}, {"kind", n.kind}, {"orientation", n.orientation}, {"columns", n.columns}});
    j["entities"] = nlohmann::json::array();
    for (const auto& e : inv.entities)
      // A label with a sub-index (.mod's "12.3") is the string the channel spec takes.
      j["entities"].push_back({{"file", e.file},
                               {"label", e.label >= 0 ? nlohmann::json(e.label) : nlohmann::json(reader::row_label_text(e.label))},
                               {"type", e.type},
                               {"columns", e.columns}});
    if (!inv.variables.empty()) {
      j["variables"] = nlohmann::json::array();
      for (const auto& v : inv.variables) j["variables"].push_back({{"name", v.name}, {"components", v.components}});
    }
    if (!inv.columns.empty()) j["columns"] = inv.columns;
    if (inv.format != "column") j["eigenanalyses"] = inv.eigenanalyses;
    j["warnings"] = inv.warnings;
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::cout << fmt::format("{} ({})\n", inv.source, inv.format);
  if (!inv.columns.empty()) {
    std::cout << fmt::format("{} rows, {} columns (col:1 .. col:{})\n", inv.blocks, inv.columns.size(), inv.columns.size());
    // Named by a header line: list the names, which --column / --time-column accept as well.
    bool named = false;
    for (std::size_t k = 0; k < inv.columns.size(); ++k) named = named || inv.columns[k] != fmt::format("column {}", k + 1);
    for (std::size_t k = 0; named && k < inv.columns.size(); ++k)
      std::cout << fmt::format("  col:{:<4} {}\n", k + 1, inv.columns[k]);
  } else {
    std::cout << fmt::format("{} output blocks, t = {:.6g} .. {:.6g}\n", inv.blocks, inv.t_first, inv.t_last);
    std::cout << "structural nodes (node:L:x|y|z|r1..|vx..|wx..; rel:A:B:AXIS; a range of labels, node:11..14:x, is one channel each):\n";
    for (const auto& n : inv.nodes)
      std::cout << fmt::format("  node {:>6}  {:<13} orientation {:<9}{}\n", n.label, n.kind, n.orientation,
                               n.columns ? fmt::format(" {} columns", n.columns) : "");
    std::cout << "entities (EXT:L:K; joint:L:K for .jnt):\n";
    for (const auto& e : inv.entities)
      std::cout << fmt::format("  {:<4}{:>7}  {:<30}{}\n", e.file, reader::row_label_text(e.label), e.type,
                               e.columns ? fmt::format(" {} columns", e.columns) : "");
    if (!inv.variables.empty()) {
      std::cout << "other time histories (var:NAME:K, K = 1 .. components):\n";
      for (const auto& v : inv.variables) std::cout << fmt::format("  {:<40} {} component(s)\n", v.name, v.components);
    }
    if (inv.eigenanalyses > 0)
      std::cout << fmt::format("MBDyn eigenanalyses: {} (mlce eigenanalysis {})\n", inv.eigenanalyses, file);
  }
  print_warnings(inv.warnings);
  return 0;
}

int cmd_extract(const std::vector<std::string>& args) {
  std::vector<std::string> channels;
  std::string csv_path, plot_path;
  reader::ReadOptions read_options;
  po::options_description d("mlce extract SET --channel SPEC... [options]");
  d.add_options()
      ("channel", channel_specs(&channels), "channel spec (repeatable; FIRST..LAST in a number: a channel each)")
      ("to", po::value(&read_options.until), "last time to write (solver output sets); later steps are not read, so a "
                                             "run that diverged after it can be extracted")
      ("csv", po::value(&csv_path), "write to this file instead of stdout")
      ("plot", po::value(&plot_path), "also draw the channels against time as PNG (gnuplot)");
  const auto parsed = parse(args, d);
  if (!parsed) return 0;
  const po::variables_map& vm = *parsed;
  if (!vm.count("file")) throw po::error("missing SET (an MBDyn output prefix, a .nc file or a column file)");
  if (channels.empty()) throw po::error("give at least one --channel SPEC");
  const std::string file = vm["file"].as<std::string>();
  if (std::isnan(read_options.until)) throw po::error("--to: expected a time");
  if (vm.count("to") && reader::default_registry().for_path(file).name() == "column")
    throw po::error("--to needs a set with a time axis (MBDyn output); a column file is written whole");
  const reader::ChannelSet cs = cli::load_channels(file, channels, read_options);
  // Streamed row by row: a long run's CSV is never held in memory whole.
  const auto write_csv = [&cs](std::ostream& os) {
    os << (cs.time.empty() ? "sample" : "time");
    for (const auto& name : cs.names) os << ',' << name;
    os << '\n';
    const std::size_t n = cs.values.empty() ? 0 : cs.values[0].size();
    fmt::memory_buffer row;
    for (std::size_t k = 0; k < n; ++k) {
      row.clear();
      if (cs.time.empty()) fmt::format_to(std::back_inserter(row), "{}", k);
      else fmt::format_to(std::back_inserter(row), "{}", cs.time[k]);
      for (const auto& v : cs.values) fmt::format_to(std::back_inserter(row), ",{}", v[k]);
      row.push_back('\n');
      os.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
  };
  if (csv_path.empty()) {
    write_csv(std::cout);
  } else {
    cli::AtomicFile f(csv_path);
    write_csv(f.stream());
    f.commit();
  }
  if (!plot_path.empty()) {
    // Up to kPlotRows rows are drawn as they are; a longer record as its envelope: per bucket of
    // rows, each channel's minimum and maximum (plain decimation would alias a rotor's harmonics).
    constexpr std::size_t kPlotRows = 200000;
    const std::size_t n = cs.values.empty() ? 0 : cs.values[0].size();
    const std::size_t bucket = n > kPlotRows ? (2 * n + kPlotRows - 1) / kPlotRows : 1;
    const auto time_of = [&cs](std::size_t k) { return cs.time.empty() ? static_cast<double>(k) : cs.time[k]; };
    std::string data = cs.time.empty() ? "sample" : "time";
    for (const auto& name : cs.names) data += "," + name;
    data += "\n";
    for (std::size_t first = 0; first < n; first += bucket) {
      const std::size_t last = std::min(n, first + bucket) - 1;
      std::string low = fmt::format("{}", time_of(first)), high = fmt::format("{}", time_of((first + last + 1) / 2));
      for (const auto& v : cs.values) {
        const auto [lo, hi] = std::minmax_element(v.begin() + static_cast<std::ptrdiff_t>(first),
                                                  v.begin() + static_cast<std::ptrdiff_t>(last) + 1);
        low += fmt::format(",{}", *lo), high += fmt::format(",{}", *hi);
      }
      data += low + "\n";
      if (bucket > 1) data += high + "\n";
    }
    cli::plot_columns_png(data, file + (bucket > 1 ? fmt::format(" (envelope: min and max of every {} rows)", bucket) : ""),
                          cs.time.empty() ? "sample" : "time", "value", plot_path);
  }
  print_warnings(cs.warnings);
  return 0;
}

int run_command(const std::string& cmd, const std::vector<std::string>& args) {
  try {
    if (cmd == "estimate") return cmd_estimate(args);
    if (cmd == "ami") return cmd_ami(args);
    if (cmd == "fnn") return cmd_fnn(args);
    if (cmd == "kantz") return cmd_kantz(args);
    if (cmd == "modes") return cmd_modes(args);
    if (cmd == "stsp") return cmd_stsp(args);
    if (cmd == "convergence") return cmd_convergence(args);
    if (cmd == "channels") return cmd_channels(args);
    if (cmd == "simulate") return cmd_simulate(args);
    if (cmd == "extract") return cmd_extract(args);
    if (cmd == "spectrum") return cli::cmd_spectrum(args);
    if (cmd == "floquet") return cli::cmd_floquet(args);
    if (cmd == "eigen") return cli::cmd_eigen(args);
    if (cmd == "eigenanalysis") return cli::cmd_eigenanalysis(args);
    if (cmd == "compare") return cli::cmd_compare(args);
    if (cmd == "sweep") return cli::cmd_sweep(args);
    if (cmd == "--version" || cmd == "version") {
      std::printf("mlce %s\n", MLCE_VERSION);
      return 0;
    }
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    std::fprintf(stderr, "mlce: unknown command '%s'\n%s", cmd.c_str(), kUsage);
    return kExitUsage;
  } catch (const po::error& e) {
    std::fprintf(stderr, "mlce %s: error: %s\n", cmd.c_str(), e.what());
    return kExitUsage;
  } catch (const OptionError& e) {
    std::fprintf(stderr, "mlce %s: error: %s\n", cmd.c_str(), e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mlce %s: error: %s\n", cmd.c_str(), e.what());
    return kExitData;
  }
}

/// The results printed on stdout reached it, or the command fails: `mlce extract ... > out.csv` on a
/// full disk (or a closed stdout) would otherwise end with status 0 and a truncated file, since
/// buffered writes fail only when flushed at exit, unseen (what coreutils' close_stdout guards).
int finish_standard_output(const std::string& cmd, int status) {
  std::cout.flush();
  errno = 0;
  if (std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good()) return status;
  const int error = errno;
  std::fprintf(stderr, "mlce %s: error: standard output: write failed%s%s%s\n", cmd.c_str(), error ? " (" : "",
               error ? std::strerror(error) : "", error ? ")" : "");
  return status == 0 ? kExitData : status;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return kExitUsage;
  }
  const std::string cmd = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  cli::remove_scratch_files_on_interrupt();
  return finish_standard_output(cmd, run_command(cmd, args));
}
