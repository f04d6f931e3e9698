#pragma once
// How a long computation reports where it is: the CLI prints the stages on stderr once a run has
// lasted a second (mlce estimate, convergence, fnn); the library itself never prints.
#include <functional>
#include <string_view>

namespace mlce {

/// Called with the stage name and the fraction of the stage done.
using ProgressCallback = std::function<void(std::string_view stage, double fraction)>;

}  // namespace mlce
