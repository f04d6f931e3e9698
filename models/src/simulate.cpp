#include "mlce/models/simulate.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include "mlce/models/dynamics.hpp"
#include "mlce/models/flapping.hpp"
#include "mlce/models/hammond.hpp"
#include "mlce/ode/step_budget.hpp"

namespace mlce::models {
namespace {

template <class Model>
Trajectory run(const Model& model, const Scene& s, const std::function<void(double)>& progress) {
  Trajectory tr;
  tr.names = model.state_names();
  const std::size_t n = s.samples();
  tr.time.reserve(n);
  tr.states.reserve(n);
  // Progress by the time reached, every few thousand steps: output samples may be far apart.
  ode::IntegratorOptions integrator = s.integrator;
  const double t_last = s.dt_out * static_cast<double>(n > 0 ? n - 1 : 0);
  if (progress && t_last > 0) integrator.progress = [&progress, t_last](double t) { progress(std::min(1.0, t / t_last)); };
  tr.stats = ode::integrate_uniform(model, s.x0, 0.0, s.dt_out, n, integrator,
                                    [&](std::size_t, double t, const Eigen::VectorXd& x) {
                                      tr.time.push_back(t);
                                      tr.states.push_back(x);
                                    });
  return tr;
}

/// Degrees wrapped to (-180, 180], as MBDyn writes Euler angles.
double wrap_degrees(double rad) {
  double d = std::remainder(rad * 180.0 / std::numbers::pi, 360.0);
  if (d <= -180.0) d += 360.0;
  return d;
}

void commit(const std::vector<std::pair<std::string, std::string>>& files) {
  for (const auto& [tmp, final_name] : files) {
    std::error_code ec;
    std::filesystem::rename(tmp, final_name, ec);
    if (ec) throw std::runtime_error(final_name + ": cannot write (" + ec.message() + ")");
  }
}

}  // namespace

Trajectory simulate(const Scene& s, const std::function<void(double)>& progress) {
  // Refuse at once a run that cannot finish within the step budget (integrate_uniform's rk4
  // default step is dt_out / 4).
  ode::IntegratorOptions budget = s.integrator;
  if (budget.h_fixed <= 0) budget.h_fixed = s.dt_out / 4.0;
  ode::require_step_budget(dynamical_system(s), s.x0, 0.0, s.t_end, 1, budget, s.source);
  if (s.model == "hammond") return run(HammondModel(s.hammond), s, progress);
  if (s.model == "flapping") return run(FlappingModel(s.flapping), s, progress);
  throw std::invalid_argument("unknown model '" + s.model + "'");
}

void write_trajectory_columns(const Trajectory& t, std::ostream& os) {
  os << "# time";
  for (const auto& n : t.names) os << ' ' << n;
  os << '\n';
  std::string row;
  char buf[64];
  for (std::size_t k = 0; k < t.time.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%.17g", t.time[k]);
    row = buf;
    for (Eigen::Index i = 0; i < t.states[k].size(); ++i) {
      std::snprintf(buf, sizeof buf, " %.17g", t.states[k](i));
      row += buf;
    }
    row += '\n';
    os << row;
  }
}

void write_mbdyn_set(const Scene& s, const Trajectory& t, const std::string& prefix) {
  if (s.model != "hammond") throw std::invalid_argument("--format mbdyn needs a hammond scene (model = " + s.model + ")");
  const auto& p = s.hammond;
  const int N = p.blades, nq = N + 2;
  const double W = p.omega();
  std::vector<std::pair<std::string, std::string>> files;
  auto open = [&](const std::string& ext) {
    const std::string name = prefix + ext, tmp = name + ".tmp";
    files.emplace_back(tmp, name);
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error(name + ": cannot write");
    return f;
  };
  try {
    {
      std::ofstream log = open(".log");
      log.precision(10);
      log << "output frequency: 1\n";
      // The reference (zero-lag) configuration, so that rel:10+i:4:z is zeta_i itself.
      log << "structural node: 2 " << s.x0(N) << " 0 0 euler123 0 0 0\n";
      log << "structural node: 3 " << s.x0(N) << " " << s.x0(N + 1) << " 0 euler123 0 0 0\n";
      log << "structural node: 4 " << s.x0(N) << " " << s.x0(N + 1) << " 0 euler123 0 0 0\n";
      for (int i = 0; i < N; ++i) {
        const double a = p.azimuth0(i);
        log << "structural node: " << 11 + i << " " << s.x0(N) + p.e * std::cos(a) << " " << s.x0(N + 1) + p.e * std::sin(a)
            << " 0 euler123 0 0 " << wrap_degrees(a) << "\n";
      }
      log << "# written by mlce simulate (ad-hoc Hammond model), not by MBDyn\n";
      if (!log) throw std::runtime_error(prefix + ".log: write error");
    }
    {
      std::ofstream out = open(".out");
      out << "# Key for lines starting with \"Step\":\n# Step Time TStep NIter ResErr SolErr SolConv Out\n";
      char buf[96];
      for (std::size_t k = 0; k < t.time.size(); ++k) {
        std::snprintf(buf, sizeof buf, "Step %zu %.17g %.17g 0 0 0 0 1\n", k, t.time[k], k ? t.time[k] - t.time[k - 1] : 0.0);
        out << buf;
      }
      if (!out) throw std::runtime_error(prefix + ".out: write error");
    }
    {
      std::ofstream mov = open(".mov");
      char buf[512];
      auto row = [&](int label, double x, double y, double ez, double vx, double vy, double wz) {
        std::snprintf(buf, sizeof buf,
                      "%8d %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e\n", label, x, y,
                      0.0, 0.0, 0.0, ez, vx, vy, 0.0, 0.0, 0.0, wz);
        mov << buf;
      };
      for (std::size_t k = 0; k < t.time.size(); ++k) {
        const auto& q = t.states[k];
        const double xh = q(N), yh = q(N + 1), xd = q(nq + N), yd = q(nq + N + 1), tt = t.time[k];
        row(2, xh, 0.0, 0.0, xd, 0.0, 0.0);
        row(3, xh, yh, 0.0, xd, yd, 0.0);
        row(4, xh, yh, wrap_degrees(W * tt), xd, yd, W);
        for (int i = 0; i < N; ++i) {
          const double psi = W * tt + p.azimuth0(i);
          row(11 + i, xh + p.e * std::cos(psi), yh + p.e * std::sin(psi), wrap_degrees(psi + q(i)),
              xd - p.e * W * std::sin(psi), yd + p.e * W * std::cos(psi), W + q(nq + i));
        }
      }
      if (!mov) throw std::runtime_error(prefix + ".mov: write error");
    }
    commit(files);
  } catch (...) {
    for (const auto& f : files) std::filesystem::remove(f.first);
    throw;
  }
}

}  // namespace mlce::models
