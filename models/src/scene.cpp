#include "mlce/models/scene.hpp"

#include <boost/program_options.hpp>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace po = boost::program_options;

namespace mlce::models {
namespace {

/// The shortest decimal that reads back as v (std::to_chars): 242.4, 0.005, 3e+13. A scene written
/// out (describe_scene) reloads bit for bit, and a message shows a number as the user typed it.
std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

struct Key {
  const char* name;
  const char* help;
};
// One table: the option description, the file keys and the README all come from it.
const Key kKeys[] = {
    {"model", "hammond | flapping"},
    {"blades", "hammond: number of blades N_b (4)"},
    {"rpm", "hammond: rotor speed (242.4)"},
    {"c", "hammond: linear lag dampers, N m s/rad, one value or one per blade (4067.5; 0 = inoperative)"},
    {"k", "hammond: lag springs, N m/rad, one or per blade (0)"},
    {"damper", "hammond: linear | nonlinear, one or per blade (linear)"},
    {"CL", "hammond: nonlinear damper slope at zero rate C_L, one or per blade (4067.5)"},
    {"chibar", "hammond: nonlinear damper chi-bar, N m s^2/rad^2 (1.2203e6)"},
    {"zetadot_L", "hammond: nonlinear damper saturation rate, rad/s (1 deg/s)"},
    {"cx", "hammond: airframe damper x, N s/m (51078.7)"},
    {"cy", "hammond: airframe damper y, N s/m (25539.35: Table 1's 51078.7 is a misprint, see README)"},
    {"kx", "hammond: airframe spring x, N/m (1240481.8)"},
    {"ky", "hammond: airframe spring y, N/m (1240481.8)"},
    {"mx", "hammond: airframe mass x, kg (8026.6)"},
    {"my", "hammond: airframe mass y, kg (3283.6)"},
    {"mb", "hammond: blade mass, kg (94.9)"},
    {"Sb", "hammond: blade static moment, kg m (289.1)"},
    {"Ib", "hammond: blade inertia about the hinge, kg m^2 (1084.7)"},
    {"e", "hammond: hinge offset, m (0.3048)"},
    {"placement", "hammond: mbdyn (blade i at (i-1) 2pi/N, default) | paper (2 pi i/N)"},
    {"x0", "hammond: initial x_h, m (0.1)"},
    {"y0", "hammond: initial y_h, m (0)"},
    {"xdot0", "hammond: initial x_h rate, m/s (0)"},
    {"ydot0", "hammond: initial y_h rate, m/s (0)"},
    {"zeta0", "hammond: initial lag angles, rad, one or per blade (0)"},
    {"zetadot0", "hammond: initial lag rates, rad/s, one or per blade (0)"},
    {"gamma", "flapping: Lock number (8)"},
    {"nu", "flapping: flap frequency nu_beta (1)"},
    {"mu", "flapping: advance ratio (0.15)"},
    {"beta0", "flapping: initial flap angle (0.1)"},
    {"betadot0", "flapping: initial flap rate (0)"},
    {"t_end", "duration (hammond 30 s; flapping 100)"},
    {"dt_out", "output step (hammond 0.005 s; flapping 0.05)"},
    {"integrator", "rk23 | rk45 | rk4 (rk45)"},
    {"rtol", "relative tolerance (1e-8)"},
    {"atol", "absolute tolerance (1e-10)"},
    {"h", "rk4 step (dt_out / 4)"},
};

class KeyReader {
 public:
  KeyReader(std::map<std::string, std::string> v, std::string source) : v_(std::move(v)), source_(std::move(source)) {}
  bool has(const std::string& k) const { return v_.count(k) > 0; }
  std::string text(const std::string& k, const std::string& def) const { return has(k) ? v_.at(k) : def; }
  double number(const std::string& k, double def) const {
    if (!has(k)) return def;
    return parse(k, v_.at(k));
  }
  std::vector<double> list(const std::string& k, std::size_t n, double def) const {
    if (!has(k)) return std::vector<double>(n, def);
    std::vector<double> out;
    std::stringstream s(v_.at(k));
    for (std::string item; std::getline(s, item, ',');) out.push_back(parse(k, item));
    if (out.size() == 1) out.assign(n, out[0]);
    if (out.size() != n)
      throw std::invalid_argument(source_ + ": " + k + " = " + v_.at(k) + ": expected one value or " +
                                  std::to_string(n) + " comma-separated values");
    return out;
  }
  std::vector<std::string> words(const std::string& k, std::size_t n, const std::string& def) const {
    if (!has(k)) return std::vector<std::string>(n, def);
    std::vector<std::string> out;
    std::stringstream s(v_.at(k));
    for (std::string item; std::getline(s, item, ',');) out.push_back(trim(item));
    if (out.size() == 1) out.assign(n, out[0]);
    if (out.size() != n)
      throw std::invalid_argument(source_ + ": " + k + " = " + v_.at(k) + ": expected one value or " +
                                  std::to_string(n) + " comma-separated values");
    return out;
  }
  const std::string& source() const { return source_; }

 private:
  static std::string trim(const std::string& s) {
    const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
  }
  double parse(const std::string& k, const std::string& text) const {
    const std::string t = trim(text);
    try {
      std::size_t used = 0;
      const double v = std::stod(t, &used);
      if (used == t.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    throw std::invalid_argument(source_ + ": " + k + " = '" + text + "': expected a finite number");
  }
  std::map<std::string, std::string> v_;
  std::string source_;
};

}  // namespace

std::size_t Scene::samples() const { return static_cast<std::size_t>(std::floor(t_end / dt_out + 1e-9)) + 1; }

po::options_description scene_options() {
  po::options_description d("scene keys (file `key = value`, or --key value to override)");
  for (const auto& k : kKeys) d.add_options()(k.name, po::value<std::string>(), k.help);
  return d;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  const po::options_description d = scene_options();
  po::variables_map vm;
  const std::string source = path.empty() ? "(command line)" : path;
  try {
    // The command line first: po::store keeps the first value it sees, so it wins over the file.
    po::store(po::command_line_parser(overrides).options(d).run(), vm);
    if (!path.empty()) {
      std::ifstream in(path);
      if (!in) throw std::invalid_argument(path + ": cannot open the scene file");
      // A UTF-8 byte-order mark (Windows editors save one) is not part of the first key: it made
      // "model = hammond" an unknown option whose name printed as "model".
      char bom[3] = {};
      if (!in.read(bom, 3) || std::string_view(bom, 3) != "\xEF\xBB\xBF") {
        in.clear();
        in.seekg(0);
      }
      po::store(po::parse_config_file(in, d, false), vm);
    }
  } catch (const po::error& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  std::map<std::string, std::string> v;
  for (const auto& [k, val] : vm) v[k] = val.as<std::string>();
  const KeyReader r(v, source);

  Scene s;
  s.source = source;
  s.model = r.text("model", "hammond");
  try {
    s.integrator.scheme = ode::scheme_from_name(r.text("integrator", "rk45"));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  s.integrator.rtol = r.number("rtol", 1e-8);
  s.integrator.atol = r.number("atol", 1e-10);
  if (s.model == "hammond") {
    auto& p = s.hammond;
    const double nb = r.number("blades", 4);
    if (nb != std::floor(nb) || nb < 1 || nb > 64) throw std::invalid_argument(source + ": blades: expected 1..64");
    p.blades = static_cast<int>(nb);
    const auto n = static_cast<std::size_t>(p.blades);
    p.rpm = r.number("rpm", p.rpm);
    p.c = r.list("c", n, 4067.5);
    p.k = r.list("k", n, 0.0);
    p.C_L = r.list("CL", n, 4067.5);
    p.damper.clear();
    for (const auto& w : r.words("damper", n, "linear")) {
      if (w == "linear") p.damper.push_back(DamperLaw::linear);
      else if (w == "nonlinear") p.damper.push_back(DamperLaw::nonlinear);
      else throw std::invalid_argument(source + ": damper = " + w + ": expected linear or nonlinear");
    }
    p.chibar = r.number("chibar", p.chibar);
    p.zetadot_L = r.number("zetadot_L", p.zetadot_L);
    p.c_x = r.number("cx", p.c_x), p.c_y = r.number("cy", p.c_y);
    p.k_x = r.number("kx", p.k_x), p.k_y = r.number("ky", p.k_y);
    p.m_x = r.number("mx", p.m_x), p.m_y = r.number("my", p.m_y);
    p.m_b = r.number("mb", p.m_b), p.S_b = r.number("Sb", p.S_b), p.I_b = r.number("Ib", p.I_b);
    p.e = r.number("e", p.e);
    const std::string placement = r.text("placement", "mbdyn");
    if (placement != "mbdyn" && placement != "paper")
      throw std::invalid_argument(source + ": placement = " + placement + ": expected mbdyn or paper");
    p.paper_placement = placement == "paper";
    try {
      p.validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(source + ": " + e.what());
    }
    const int nq = p.blades + 2;
    s.x0 = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(nq));
    const auto z0 = r.list("zeta0", n, 0.0), zd0 = r.list("zetadot0", n, 0.0);
    for (int i = 0; i < p.blades; ++i) s.x0(i) = z0[static_cast<std::size_t>(i)], s.x0(nq + i) = zd0[static_cast<std::size_t>(i)];
    s.x0(p.blades) = r.number("x0", 0.1);
    s.x0(p.blades + 1) = r.number("y0", 0.0);
    s.x0(nq + p.blades) = r.number("xdot0", 0.0);
    s.x0(nq + p.blades + 1) = r.number("ydot0", 0.0);
    s.t_end = r.number("t_end", 30.0);
    s.dt_out = r.number("dt_out", 0.005);
  } else if (s.model == "flapping") {
    auto& p = s.flapping;
    p.gamma = r.number("gamma", p.gamma), p.nu = r.number("nu", p.nu), p.mu = r.number("mu", p.mu);
    try {
      p.validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(source + ": " + e.what());
    }
    s.x0 = Eigen::Vector2d(r.number("beta0", 0.1), r.number("betadot0", 0.0));
    s.t_end = r.number("t_end", 100.0);
    s.dt_out = r.number("dt_out", 0.05);
  } else {
    throw std::invalid_argument(source + ": model = " + s.model + ": expected hammond or flapping");
  }
  s.integrator.h_fixed = r.number("h", 0.0);
  if (s.integrator.h_fixed < 0.0)
    throw std::invalid_argument(source + ": h = " + r.text("h", "") + ": expected a step >= 0 (0: dt_out / 4)");
  if (!(s.dt_out > 0) || !(s.t_end > 0) || s.dt_out > s.t_end)
    throw std::invalid_argument(source + ": dt_out = " + shortest(s.dt_out) + ", t_end = " + shortest(s.t_end) +
                                ": expected 0 < dt_out <= t_end");
  // Every sample is kept in memory (and written): bound it before allocating.
  constexpr double kMaxSamples = 5e7;
  if (s.t_end / s.dt_out > kMaxSamples)
    throw std::invalid_argument(source + ": t_end / dt_out = " + shortest(s.t_end / s.dt_out) +
                                " output samples: expected at most 5e7 (raise dt_out)");
  try {
    s.integrator.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  return s;
}

std::string describe_scene(const Scene& s) {
  std::ostringstream o;
  auto list = [&](const std::vector<double>& v) {
    std::string l;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i > 0) l += ',';
      l += shortest(v[i]);
    }
    return l;
  };
  o << "model = " << s.model << "\n";
  if (s.model == "hammond") {
    const auto& p = s.hammond;
    std::string dampers;
    for (std::size_t i = 0; i < p.damper.size(); ++i)
      dampers += std::string(i ? "," : "") + (p.damper[i] == DamperLaw::linear ? "linear" : "nonlinear");
    const int N = p.blades, nq = N + 2;
    std::vector<double> z0, zd0;
    for (int i = 0; i < N; ++i) z0.push_back(s.x0(i)), zd0.push_back(s.x0(nq + i));
    o << "blades = " << N << "\nrpm = " << shortest(p.rpm) << "\nc = " << list(p.c) << "\nk = " << list(p.k)
      << "\ndamper = " << dampers << "\nCL = " << list(p.C_L) << "\nchibar = " << shortest(p.chibar)
      << "\nzetadot_L = " << shortest(p.zetadot_L) << "\ncx = " << shortest(p.c_x) << "\ncy = " << shortest(p.c_y)
      << "\nkx = " << shortest(p.k_x) << "\nky = " << shortest(p.k_y) << "\nmx = " << shortest(p.m_x)
      << "\nmy = " << shortest(p.m_y) << "\nmb = " << shortest(p.m_b) << "\nSb = " << shortest(p.S_b)
      << "\nIb = " << shortest(p.I_b) << "\ne = " << shortest(p.e)
      << "\nplacement = " << (p.paper_placement ? "paper" : "mbdyn") << "\nx0 = " << shortest(s.x0(N))
      << "\ny0 = " << shortest(s.x0(N + 1)) << "\nxdot0 = " << shortest(s.x0(nq + N))
      << "\nydot0 = " << shortest(s.x0(nq + N + 1)) << "\nzeta0 = " << list(z0) << "\nzetadot0 = " << list(zd0) << "\n";
  } else {
    o << "gamma = " << shortest(s.flapping.gamma) << "\nnu = " << shortest(s.flapping.nu)
      << "\nmu = " << shortest(s.flapping.mu) << "\nbeta0 = " << shortest(s.x0(0))
      << "\nbetadot0 = " << shortest(s.x0(1)) << "\n";
  }
  o << "t_end = " << shortest(s.t_end) << "\ndt_out = " << shortest(s.dt_out)
    << "\nintegrator = " << ode::scheme_name(s.integrator.scheme) << "\nrtol = " << shortest(s.integrator.rtol)
    << "\natol = " << shortest(s.integrator.atol) << "\n";
  if (s.integrator.h_fixed > 0) o << "h = " << shortest(s.integrator.h_fixed) << "\n";
  return o.str();
}

}  // namespace mlce::models
