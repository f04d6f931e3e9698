#include "mlce/ode/runge_kutta.hpp"

namespace mlce::ode {

Scheme scheme_from_name(const std::string& n) {
  if (n == "rk23" || n == "bs23" || n == "ode23") return Scheme::bs23;
  if (n == "rk45" || n == "dp45" || n == "ode45" || n == "dopri5") return Scheme::dp45;
  if (n == "rk4") return Scheme::rk4;
  throw std::invalid_argument("integrator '" + n + "': expected rk23, rk45 or rk4");
}

const char* scheme_name(Scheme s) {
  switch (s) {
    case Scheme::bs23: return "rk23";
    case Scheme::dp45: return "rk45";
    default: return "rk4";
  }
}

void IntegratorOptions::validate() const {
  if (!(rtol > 0.0 && rtol < 1.0)) throw std::invalid_argument("rtol: expected 0 < rtol < 1");
  if (!(atol > 0.0)) throw std::invalid_argument("atol: expected > 0");
  if (h_initial < 0.0 || h_max < 0.0 || h_fixed < 0.0) throw std::invalid_argument("step sizes must not be negative");
}

namespace detail {

const Tableau& tableau(Scheme s) {
  static const Tableau bs23{4,
                            {{}, {1.0 / 2}, {0.0, 3.0 / 4}, {2.0 / 9, 1.0 / 3, 4.0 / 9}},
                            {2.0 / 9, 1.0 / 3, 4.0 / 9, 0.0},
                            {7.0 / 24, 1.0 / 4, 1.0 / 3, 1.0 / 8},
                            {0.0, 1.0 / 2, 3.0 / 4, 1.0},
                            3,
                            2,
                            true};
  static const Tableau dp45{7,
                            {{},
                             {1.0 / 5},
                             {3.0 / 40, 9.0 / 40},
                             {44.0 / 45, -56.0 / 15, 32.0 / 9},
                             {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
                             {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
                             {35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}},
                            {35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0.0},
                            {5179.0 / 57600, 0.0, 7571.0 / 16695, 393.0 / 640, -92097.0 / 339200, 187.0 / 2100,
                             1.0 / 40},
                            {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0},
                            5,
                            4,
                            true};
  static const Tableau rk4{4,
                           {{}, {0.5}, {0.0, 0.5}, {0.0, 0.0, 1.0}},
                           {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6},
                           {},
                           {0.0, 0.5, 0.5, 1.0},
                           4,
                           0,
                           false};
  switch (s) {
    case Scheme::bs23: return bs23;
    case Scheme::dp45: return dp45;
    default: return rk4;
  }
}

}  // namespace detail
}  // namespace mlce::ode
