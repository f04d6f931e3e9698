#pragma once
// FFTW plans for the estimators (mean_period.cpp, surrogate.cpp): made and destroyed under one
// lock, since FFTW's planner is not thread-safe; executed without it.
#include <fftw3.h>

#include <cstddef>
#include <mutex>

namespace mlce::detail {

inline std::mutex& planner_mutex() {  // one mutex for every translation unit (inline: one instance)
  static std::mutex m;
  return m;
}

/// An FFTW plan made and destroyed under the planner's lock; executed without it.
class Plan {
 public:
  explicit Plan(fftw_plan plan) : plan_(plan) {}
  ~Plan() {
    std::lock_guard lock(planner_mutex());
    fftw_destroy_plan(plan_);
  }
  Plan(const Plan&) = delete;
  Plan& operator=(const Plan&) = delete;
  void execute() const { fftw_execute(plan_); }

 private:
  fftw_plan plan_;
};

/// Real-to-complex (n reals into n / 2 + 1 complex) and complex-to-real (back) plans.
inline Plan forward_plan(std::size_t n, double* in, fftw_complex* out) {
  std::lock_guard lock(planner_mutex());
  return Plan(fftw_plan_dft_r2c_1d(static_cast<int>(n), in, out, FFTW_ESTIMATE));
}
inline Plan backward_plan(std::size_t n, fftw_complex* in, double* out) {
  std::lock_guard lock(planner_mutex());
  return Plan(fftw_plan_dft_c2r_1d(static_cast<int>(n), in, out, FFTW_ESTIMATE));
}

}  // namespace mlce::detail
