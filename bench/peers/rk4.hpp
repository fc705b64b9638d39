// rk4.hpp — the one fixed-step classical Runge-Kutta loop every engine but
// MuJoCo (which has its own RK4) is driven by, so that only the derivative
// differs between them.
#pragma once
#include <cstddef>
#include <vector>

namespace bench {

/// Integrates y' = f(t, y) from t = 0 over `steps` steps of h; f(t, y, ydot).
template <class F>
void rk4(F&& f, std::vector<double>& y, double h, long steps) {
  const std::size_t n = y.size();
  std::vector<double> k1(n), k2(n), k3(n), k4(n), tmp(n);
  double t = 0;
  for (long s = 0; s < steps; ++s) {
    f(t, y.data(), k1.data());
    for (std::size_t i = 0; i < n; ++i) tmp[i] = y[i] + 0.5 * h * k1[i];
    f(t + 0.5 * h, tmp.data(), k2.data());
    for (std::size_t i = 0; i < n; ++i) tmp[i] = y[i] + 0.5 * h * k2[i];
    f(t + 0.5 * h, tmp.data(), k3.data());
    for (std::size_t i = 0; i < n; ++i) tmp[i] = y[i] + h * k3[i];
    f(t + h, tmp.data(), k4.data());
    for (std::size_t i = 0; i < n; ++i) y[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    t = (s + 1) * h;
  }
}

}  // namespace bench
