#pragma once
// mlce compare A B --channel SPEC...: two runs (MBDyn or ad-hoc, text or NetCDF) side by side.
#include <string>
#include <vector>

namespace mlce::cli {
int cmd_compare(const std::vector<std::string>& args);
}  // namespace mlce::cli
