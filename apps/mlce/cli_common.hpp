#pragma once
// What every subcommand shares: exit codes, option parsing with --help, warnings, scene loading,
// and progress lines on stderr.
#include <boost/program_options.hpp>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "mlce/models/scene.hpp"

namespace mlce::cli {

constexpr int kExitData = 1;   // bad input file or data
constexpr int kExitUsage = 2;  // bad command line

/// Parses a subcommand's options (one positional FILE; with several_files any number of them, stored
/// as a std::vector<std::string>) and adds --help. Returns nullopt when --help was given: the
/// description is then printed and the command has nothing else to do.
std::optional<boost::program_options::variables_map> parse(const std::vector<std::string>& args,
                                                           boost::program_options::options_description& d,
                                                           bool several_files = false);

void print_warnings(const std::vector<std::string>& w);

/// The value of a repeatable --channel option, stored into `specs` with every range expanded
/// (reader::expand_channel_ranges: rel:11..14:4:z is four channels); a malformed range is an
/// OptionError naming it.
boost::program_options::typed_value<std::vector<std::string>>* channel_specs(std::vector<std::string>* specs);

/// The whole of `text` as a finite number ("1e-3", "-2"), or nullopt ("", "1x", "nan", "inf").
std::optional<double> parse_finite(const std::string& text);

/// The scene named by the positional FILE (optional) with every scene key given on the command
/// line as an override. Scene errors are data errors (std::runtime_error).
models::Scene scene_from(const boost::program_options::variables_map& vm,
                         const boost::program_options::options_description& scene_keys);

/// A command on a scene: adds every scene key to `d` as an override, parses (nullopt after --help)
/// and loads the scene named by the positional FILE.
struct SceneCommand {
  boost::program_options::variables_map vm;
  models::Scene scene;
};
std::optional<SceneCommand> parse_scene_command(const std::vector<std::string>& args,
                                                boost::program_options::options_description& d);

/// "mlce: 3.2 s: <what> 40 %" on stderr, at most every half second and only after the first second.
class ProgressLine {
 public:
  ProgressLine(std::string what, bool quiet) : what_(std::move(what)), quiet_(quiet) {}
  void operator()(double fraction);

 private:
  std::string what_;
  bool quiet_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double last_ = 0.0;
};

}  // namespace mlce::cli
