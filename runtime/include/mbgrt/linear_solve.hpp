// mbgrt/linear_solve.hpp — the dense solve generated code calls for an
// algebraic loop whose symbolic pivots could vanish at run time (e.g. a
// modulus cos(theta) passing through zero): Gaussian elimination with partial
// pivoting, in place. Header-only so the compiler can inline it into the
// model's derivative function.
#pragma once

#include <cmath>
#include <limits>

namespace mbgrt {

/// Solve A x = b for x. `a` is n x n row-major and is overwritten; `x` holds
/// b on entry and the solution on return. A singular A gives NaN in every
/// component, which the runtime then reports as a non-finite derivative.
inline void solve_linear(int n, double* a, double* x) {
  for (int k = 0; k < n; ++k) {
    int pivot = k;
    double best = std::fabs(a[k * n + k]);
    for (int r = k + 1; r < n; ++r) {
      double v = std::fabs(a[r * n + k]);
      if (v > best) {
        best = v;
        pivot = r;
      }
    }
    if (!(best > 0.0) || !std::isfinite(best)) {
      for (int i = 0; i < n; ++i) x[i] = std::numeric_limits<double>::quiet_NaN();
      return;
    }
    if (pivot != k) {
      for (int c = 0; c < n; ++c) {
        double tmp = a[k * n + c];
        a[k * n + c] = a[pivot * n + c];
        a[pivot * n + c] = tmp;
      }
      double tmp = x[k];
      x[k] = x[pivot];
      x[pivot] = tmp;
    }
    for (int r = k + 1; r < n; ++r) {
      double factor = a[r * n + k] / a[k * n + k];
      if (factor == 0.0) continue;
      for (int c = k + 1; c < n; ++c) a[r * n + c] -= factor * a[k * n + c];
      x[r] -= factor * x[k];
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    double s = x[k];
    for (int c = k + 1; c < n; ++c) s -= a[k * n + c] * x[c];
    x[k] = s / a[k * n + k];
  }
}

}  // namespace mbgrt
