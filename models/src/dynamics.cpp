#include "mlce/models/dynamics.hpp"

#include <Eigen/LU>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

namespace mlce::models {
namespace {

/// Any model with operator(), rhs (complex), jacobian, dimension and state_names.
template <class Model>
ode::DynamicalSystem wrap(std::shared_ptr<const Model> m, double period) {
  ode::DynamicalSystem s;
  s.dimension = m->dimension();
  s.rhs = [m](const Eigen::VectorXd& x, Eigen::VectorXd& dx, double t) { (*m)(x, dx, t); };
  s.jacobian = [m](const Eigen::VectorXd& x, double t) { return m->jacobian(x, t); };
  s.rhs_complex = [m](const Eigen::VectorXcd& x, Eigen::VectorXcd& dx, double t) { m->rhs(x, dx, t); };
  s.period = period;
  s.state_names = m->state_names();
  return s;
}

ode::DynamicalSystem system_of(const Scene& s, bool check) {
  if (s.model == "hammond") {
    const double w = std::abs(s.hammond.omega());
    return wrap(std::make_shared<const HammondModel>(s.hammond, check), w != 0.0 ? 2.0 * std::numbers::pi / w : 0.0);
  }
  if (s.model == "flapping") return wrap(std::make_shared<const FlappingModel>(s.flapping, check), 2.0 * std::numbers::pi);
  throw std::invalid_argument("model '" + s.model + "': expected hammond or flapping");
}

/// Per-blade parameter "c3" -> (vector, 0-based index); "c" -> (vector, -1).
struct BladeKey {
  std::vector<double>* values = nullptr;
  int index = -1;
};

BladeKey blade_key(HammondParameters& p, const std::string& name) {
  for (auto [prefix, vec] : {std::pair<const char*, std::vector<double>*>{"CL", &p.C_L}, {"c", &p.c}, {"k", &p.k}}) {
    const std::string pre = prefix;
    if (name == pre) return {vec, -1};
    if (name.size() > pre.size() && name.compare(0, pre.size(), pre) == 0 &&
        name.find_first_not_of("0123456789", pre.size()) == std::string::npos) {
      const int i = std::stoi(name.substr(pre.size()));
      if (i < 1 || i > p.blades)
        throw std::invalid_argument("parameter " + name + ": blade index expected 1.." + std::to_string(p.blades));
      return {vec, i - 1};
    }
  }
  return {};
}

double* scalar_key(Scene& s, const std::string& name) {
  if (s.model == "flapping") {
    auto& f = s.flapping;
    if (name == "mu") return &f.mu;
    if (name == "gamma") return &f.gamma;
    if (name == "nu") return &f.nu;
    return nullptr;
  }
  auto& p = s.hammond;
  if (name == "rpm") return &p.rpm;
  if (name == "cx") return &p.c_x;
  if (name == "cy") return &p.c_y;
  if (name == "kx") return &p.k_x;
  if (name == "ky") return &p.k_y;
  if (name == "mx") return &p.m_x;
  if (name == "my") return &p.m_y;
  if (name == "mb") return &p.m_b;
  if (name == "Sb") return &p.S_b;
  if (name == "Ib") return &p.I_b;
  if (name == "e") return &p.e;
  if (name == "chibar") return &p.chibar;
  return nullptr;
}

[[noreturn]] void unknown(const Scene& s, const std::string& name) {
  std::string known;
  for (const auto& n : parameter_names(s)) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("parameter '" + name + "' is not a " + s.model + " parameter (expected one of " + known + ")");
}

}  // namespace

ode::DynamicalSystem dynamical_system(const Scene& scene) { return system_of(scene, true); }

std::vector<std::string> parameter_names(const Scene& s) {
  if (s.model == "flapping") return {"mu", "gamma", "nu"};
  std::vector<std::string> n{"rpm", "CL", "c", "cx", "cy", "kx", "ky", "mx", "my", "mb", "Sb", "Ib", "e", "chibar"};
  for (const char* pre : {"CL", "c", "k"})
    for (int i = 1; i <= s.hammond.blades; ++i) n.push_back(pre + std::to_string(i));
  return n;
}

double scene_parameter(const Scene& scene, const std::string& name) {
  Scene s = scene;
  if (double* v = scalar_key(s, name)) return *v;
  if (s.model == "hammond") {
    const BladeKey b = blade_key(s.hammond, name);
    if (b.values) {
      if (b.index >= 0) return (*b.values)[static_cast<std::size_t>(b.index)];
      for (double v : *b.values)
        if (v != b.values->front())
          throw std::invalid_argument("parameter " + name + " differs between blades: name one blade (" + name + "1..)");
      return b.values->front();
    }
  }
  unknown(scene, name);
}

void set_scene_parameter(Scene& s, const std::string& name, double value) {
  if (!std::isfinite(value)) throw std::invalid_argument("parameter " + name + ": expected a finite value");
  if (double* v = scalar_key(s, name)) {
    *v = value;
    return;
  }
  if (s.model == "hammond") {
    const BladeKey b = blade_key(s.hammond, name);
    if (b.values) {
      if (b.index >= 0) (*b.values)[static_cast<std::size_t>(b.index)] = value;
      else std::fill(b.values->begin(), b.values->end(), value);
      return;
    }
  }
  unknown(s, name);
}

ode::ParameterFamily parameter_family(const Scene& scene, const std::string& name) {
  ode::ParameterFamily f;
  f.name = name;
  f.nominal = scene_parameter(scene, name);
  f.scale = f.nominal != 0.0 ? std::abs(f.nominal) : 1.0;
  f.make = [scene, name](double v) {
    Scene s = scene;
    set_scene_parameter(s, name, v);
    return system_of(s, false);
  };
  return f;
}

TimeInvariantForm time_invariant_form(const Scene& scene) {
  TimeInvariantForm out;
  if (scene.model == "flapping") {
    if (scene.flapping.mu != 0.0)
      throw std::invalid_argument("flapping with mu > 0 is time-periodic: use floquet (eigen needs mu = 0)");
    out.A = FlappingModel(scene.flapping).jacobian(Eigen::Vector2d::Zero(), 0.0);
    out.coordinates = {"beta", "betadot"};
    return out;
  }
  const HammondParameters& p = scene.hammond;
  const HammondModel m(p, false);  // validated when the scene loaded; sensitivities step just past bounds
  const int N = p.blades, nq = N + 2, n = 2 * nq;
  const double W = p.omega();
  const int cyclic = (N - 1) / 2;
  const bool reactionless = N % 2 == 0 && N > 1;
  if (1 + 2 * cyclic + (reactionless ? 1 : 0) != N) throw std::logic_error("multiblade coordinate count");
  out.coordinates.push_back("zeta_0");
  for (int k = 1; k <= cyclic; ++k) out.coordinates.insert(out.coordinates.end(), {"zeta_" + std::to_string(k) + "c", "zeta_" + std::to_string(k) + "s"});
  if (reactionless) out.coordinates.push_back("zeta_" + std::to_string(N / 2));
  out.coordinates.insert(out.coordinates.end(), {"x_h", "y_h"});
  for (int i = 0, q = static_cast<int>(out.coordinates.size()); i < q; ++i) out.coordinates.push_back(out.coordinates[static_cast<std::size_t>(i)] + "_dot");

  // zeta_i = zeta_0 + sum_k (zeta_kc cos k psi_i + zeta_ks sin k psi_i) + zeta_{N/2} (-1)^i.
  auto transform = [&](double t) {
    Eigen::MatrixXd T0 = Eigen::MatrixXd::Identity(nq, nq), T1 = Eigen::MatrixXd::Zero(nq, nq), T2 = T1;
    for (int i = 0; i < N; ++i) {
      const double psi = W * t + p.azimuth0(i);
      T0(i, i) = 0.0;
      T0(i, 0) = 1.0;
      for (Eigen::Index k = 1; k <= cyclic; ++k) {
        const double kd = static_cast<double>(k), c = std::cos(kd * psi), s = std::sin(kd * psi), kw = kd * W;
        T0(i, 2 * k - 1) = c, T0(i, 2 * k) = s;
        T1(i, 2 * k - 1) = -kw * s, T1(i, 2 * k) = kw * c;
        T2(i, 2 * k - 1) = -kw * kw * c, T2(i, 2 * k) = -kw * kw * s;
      }
      if (reactionless) T0(i, N - 1) = (i % 2 == 0) ? 1.0 : -1.0;
    }
    Eigen::MatrixXd Tx = Eigen::MatrixXd::Zero(n, n), Td = Tx;
    Tx.topLeftCorner(nq, nq) = T0, Tx.bottomRightCorner(nq, nq) = T0, Tx.bottomLeftCorner(nq, nq) = T1;
    Td.topLeftCorner(nq, nq) = T1, Td.bottomRightCorner(nq, nq) = T1, Td.bottomLeftCorner(nq, nq) = T2;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    return Eigen::MatrixXd(Tx.partialPivLu().solve(m.jacobian(zero, t) * Tx - Td));
  };
  out.A = transform(0.0);
  // Time invariance is a property of the rotor, not an assumption: check it at other azimuths.
  const double period = W != 0.0 ? 2.0 * std::numbers::pi / std::abs(W) : 1.0;
  for (double f : {0.137, 0.5, 0.731}) {
    const double diff = (transform(f * period) - out.A).cwiseAbs().maxCoeff();
    if (diff > 1e-8 * std::max(1.0, out.A.cwiseAbs().maxCoeff()))
      throw std::invalid_argument(
          "the rotor is not isotropic (blade parameters differ): its multiblade form is time-periodic, use floquet");
  }
  return out;
}

}  // namespace mlce::models
