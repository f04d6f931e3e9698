#pragma once
// mlce spectrum | floquet | eigen: the Jacobian-based references on a scene.
#include <string>
#include <vector>

namespace mlce::cli {
int cmd_spectrum(const std::vector<std::string>& args);
int cmd_floquet(const std::vector<std::string>& args);
int cmd_eigen(const std::vector<std::string>& args);
/// MBDyn's own eigenanalyses (PREFIX.m, PREFIX_<k>.m) as continuous eigenvalues.
int cmd_eigenanalysis(const std::vector<std::string>& args);
int cmd_sweep(const std::vector<std::string>& args);  // sweep_command.cpp
}  // namespace mlce::cli
