#include "mlce/models/simulate.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "mlce/models/dynamics.hpp"
#include "mlce/models/flapping.hpp"
#include "mlce/models/hammond.hpp"
#include "mlce/ode/step_budget.hpp"

namespace mlce::models {
namespace {

constexpr const char* kScratchSuffix = ".tmp";  // MbdynSetWriter's temporaries: the file's name + this

template <class Model>
ode::IntegrationStats run(const Model& model, const Scene& s, const SampleObserver& observe,
                          const std::function<void(double)>& progress) {
  const std::size_t n = s.samples();
  // Progress by the time reached, every few thousand steps: output samples may be far apart.
  ode::IntegratorOptions integrator = s.integrator;
  const double t_last = s.dt_out * static_cast<double>(n > 0 ? n - 1 : 0);
  if (progress && t_last > 0) integrator.progress = [&progress, t_last](double t) { progress(std::min(1.0, t / t_last)); };
  return ode::integrate_uniform(model, s.x0, 0.0, s.dt_out, n, integrator, observe);
}

/// Degrees wrapped to (-180, 180], as MBDyn writes Euler angles.
double wrap_degrees(double rad) {
  double d = std::remainder(rad * 180.0 / std::numbers::pi, 360.0);
  if (d <= -180.0) d += 360.0;
  return d;
}

/// Buffered text is handed to the stream in pieces of about this size (fmt formats several times
/// faster than snprintf: the .mov of a long run is mostly formatting).
constexpr std::size_t kFlushBytes = std::size_t{1} << 16;

}  // namespace

ode::IntegrationStats simulate(const Scene& s, const SampleObserver& observe, const std::function<void(double)>& progress) {
  // Refuse at once a run that cannot finish within the step budget (integrate_uniform's rk4
  // default step is dt_out / 4).
  ode::IntegratorOptions budget = s.integrator;
  if (budget.h_fixed <= 0) budget.h_fixed = s.dt_out / 4.0;
  ode::require_step_budget(dynamical_system(s), s.x0, 0.0, s.t_end, 1, budget, s.source);
  if (s.model == "hammond") return run(HammondModel(s.hammond), s, observe, progress);
  if (s.model == "flapping") return run(FlappingModel(s.flapping), s, observe, progress);
  throw std::invalid_argument("unknown model '" + s.model + "'");
}

std::vector<std::string> state_names(const Scene& s) {
  if (s.model == "hammond") return HammondModel(s.hammond).state_names();
  if (s.model == "flapping") return FlappingModel(s.flapping).state_names();
  throw std::invalid_argument("unknown model '" + s.model + "'");
}

Trajectory simulate(const Scene& s, const std::function<void(double)>& progress) {
  Trajectory tr;
  tr.names = state_names(s);
  tr.time.reserve(s.samples());
  tr.states.reserve(s.samples());
  tr.stats = simulate(
      s,
      [&tr](std::size_t, double t, const Eigen::VectorXd& x) {
        tr.time.push_back(t);
        tr.states.push_back(x);
      },
      progress);
  return tr;
}

ColumnsWriter::ColumnsWriter(std::ostream& os, const std::vector<std::string>& names, std::string target)
    : os_(&os), target_(std::move(target)) {
  *os_ << "# time";
  for (const auto& n : names) *os_ << ' ' << n;
  *os_ << '\n';
}

void ColumnsWriter::operator()(std::size_t k, double t, const Eigen::VectorXd& x) {
  row_.clear();
  fmt::format_to(std::back_inserter(row_), "{:.17g}", t);
  for (Eigen::Index i = 0; i < x.size(); ++i) fmt::format_to(std::back_inserter(row_), " {:.17g}", x(i));
  row_ += '\n';
  os_->write(row_.data(), static_cast<std::streamsize>(row_.size()));
  if (!*os_) throw std::runtime_error(fmt::format("{}: write failed at sample {} (t = {:g})", target_, k, t));
}

struct MbdynSetWriter::File {
  std::string name, tmp;
  std::ofstream stream;
};

MbdynSetWriter::MbdynSetWriter(const Scene& s, const std::string& prefix) : p_(s.hammond) {
  if (s.model != "hammond") throw std::invalid_argument("--format mbdyn needs a hammond scene (model = " + s.model + ")");
  files_.reserve(3);
  try {
    for (const std::string& tmp : scratch_files(prefix)) {
      File& f = files_.emplace_back();
      f.tmp = tmp;
      f.name = tmp.substr(0, tmp.size() - std::string_view(kScratchSuffix).size());
      f.stream.open(f.tmp);
      if (!f.stream) throw std::runtime_error(f.name + ": cannot write");
    }
    const auto& p = p_;
    const int N = p.blades;
    std::ofstream& log = files_[0].stream;
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
    files_[1].stream << "# Key for lines starting with \"Step\":\n# Step Time TStep NIter ResErr SolErr SolConv Out\n";
  } catch (...) {
    for (File& f : files_) f.stream.close(), std::filesystem::remove(f.tmp);
    throw;
  }
}

MbdynSetWriter::~MbdynSetWriter() {
  if (committed_) return;
  std::error_code ec;
  for (File& f : files_) f.stream.close(), std::filesystem::remove(f.tmp, ec);
}

void MbdynSetWriter::operator()(std::size_t k, double t, const Eigen::VectorXd& q) {
  const auto& p = p_;
  const int N = p.blades, nq = N + 2;
  const double W = p.omega();
  // .out: one Step line per output block (the time of block k).
  fmt::format_to(std::back_inserter(steps_), "Step {} {:.17g} {:.17g} 0 0 0 0 1\n", k, t, k ? t - previous_t_ : 0.0);
  previous_t_ = t;
  auto out = std::back_inserter(rows_);
  // .mov: label, position, Euler 123 angles (deg), velocity, angular velocity.
  auto row = [&](int label, double x, double y, double ez, double vx, double vy, double wz) {
    fmt::format_to(out, "{:8d} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e}\n",
                   label, x, y, 0.0, 0.0, 0.0, ez, vx, vy, 0.0, 0.0, 0.0, wz);
  };
  const double xh = q(N), yh = q(N + 1), xd = q(nq + N), yd = q(nq + N + 1);
  row(2, xh, 0.0, 0.0, xd, 0.0, 0.0);
  row(3, xh, yh, 0.0, xd, yd, 0.0);
  row(4, xh, yh, wrap_degrees(W * t), xd, yd, W);
  for (int i = 0; i < N; ++i) {
    const double psi = W * t + p.azimuth0(i);
    row(11 + i, xh + p.e * std::cos(psi), yh + p.e * std::sin(psi), wrap_degrees(psi + q(i)), xd - p.e * W * std::sin(psi),
        yd + p.e * W * std::cos(psi), W + q(nq + i));
  }
  if (rows_.size() >= kFlushBytes) flush();
}

void MbdynSetWriter::flush() {
  files_[1].stream.write(steps_.data(), static_cast<std::streamsize>(steps_.size()));
  files_[2].stream.write(rows_.data(), static_cast<std::streamsize>(rows_.size()));
  steps_.clear();
  rows_.clear();
  for (const File& f : files_)  // a full disk stops the run now, not after the rest of it
    if (!f.stream) throw std::runtime_error(f.name + ": write failed at t = " + fmt::format("{:g}", previous_t_));
}

std::vector<std::string> MbdynSetWriter::scratch_files(const std::string& prefix) {
  std::vector<std::string> names;
  for (const char* ext : {".log", ".out", ".mov"}) names.push_back(prefix + ext + kScratchSuffix);
  return names;
}

void MbdynSetWriter::commit() {
  flush();
  for (File& f : files_) {
    f.stream.close();
    if (!f.stream) throw std::runtime_error(f.name + ": write error");
  }
  for (File& f : files_) {
    std::error_code ec;
    std::filesystem::rename(f.tmp, f.name, ec);
    if (ec) throw std::runtime_error(f.name + ": cannot write (" + ec.message() + ")");
  }
  committed_ = true;
}

}  // namespace mlce::models
