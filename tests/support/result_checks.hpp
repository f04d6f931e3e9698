#pragma once
// Checks on an estimate's result shared by the tests.
#include <algorithm>
#include <string>

#include "mlce/estimate.hpp"

namespace mlce::testing {

/// Some warning of `r` contains `text`.
inline bool has_warning(const MlceResult& r, const std::string& text) {
  return std::any_of(r.warnings.begin(), r.warnings.end(), [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

}  // namespace mlce::testing
