#include "cli_common.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/table.hpp"
#include "mlce/series.hpp"

namespace po = boost::program_options;

namespace mlce::cli {

/// One positional FILE, or with several_files any number (a std::vector<std::string>); adds --help.
/// nullopt when --help was given: the description is then printed and there is nothing else to do.
std::optional<po::variables_map> parse(const std::vector<std::string>& args, po::options_description& d, bool several_files) {
  d.add_options()("help", "this help");
  po::positional_options_description pos;
  pos.add("file", several_files ? -1 : 1);
  po::options_description all = d;
  if (several_files) all.add_options()("file", po::value<std::vector<std::string>>()->composing(), "input files");
  else all.add_options()("file", po::value<std::string>(), "input file");
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(all).positional(pos).run(), vm);
  if (vm.count("help")) {
    std::cout << d;
    return std::nullopt;
  }
  po::notify(vm);
  return vm;
}

std::optional<double> parse_finite(const std::string& text) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

po::typed_value<std::vector<std::string>>* channel_specs(std::vector<std::string>* specs) {
  // The notifier runs after the value is stored (po::notify), so it rewrites what was stored.
  return po::value(specs)->composing()->notifier([specs](const std::vector<std::string>& given) {
    std::vector<std::string> expanded;
    for (const auto& spec : given) {
      try {
        for (auto& one : reader::expand_channel_ranges(spec)) expanded.push_back(std::move(one));
      } catch (const reader::ReadError& e) {
        throw OptionError(e.what());  // a command-line mistake, not bad data
      }
    }
    *specs = std::move(expanded);
  });
}

void print_warnings(const std::vector<std::string>& w) {
  for (const auto& s : w) std::fprintf(stderr, "mlce: warning: %s\n", s.c_str());
}

models::Scene scene_from(const po::variables_map& vm, const po::options_description& scene_keys) {
  std::vector<std::string> overrides;
  for (const auto& opt : scene_keys.options())
    if (vm.count(opt->long_name())) overrides.insert(overrides.end(), {"--" + opt->long_name(), vm[opt->long_name()].as<std::string>()});
  const std::string scene_path = vm.count("file") ? vm["file"].as<std::string>() : "";
  try {
    return models::load_scene(scene_path, overrides);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
}

std::optional<SceneCommand> parse_scene_command(const std::vector<std::string>& args, po::options_description& d) {
  const po::options_description scene_keys = models::scene_options();
  d.add(scene_keys);
  auto vm = parse(args, d);
  if (!vm) return std::nullopt;
  SceneCommand c{*vm, scene_from(*vm, scene_keys)};
  return c;
}

void ProgressLine::operator()(double fraction) {
  if (quiet_) return;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (s < 1.0 || (s - last_ < 0.5 && fraction < 1.0)) return;
  last_ = s;
  std::fprintf(stderr, "mlce: %.1f s: %s %.0f %%\n", s, what_.c_str(), 100.0 * fraction);
}

}  // namespace mlce::cli
