// mbgrt/linear_solve.hpp — the dense solve generated code calls for an
// algebraic loop whose symbolic pivots could vanish at run time (e.g. a
// modulus cos(theta) passing through zero): Gaussian elimination with partial
// pivoting, in place. Header-only so the compiler can inline it into the
// model's derivative function.
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

namespace mbgrt {
namespace detail {

/// Swap rows i and j of A (n x n, row-major) and of b.
inline void swap_rows(int n, double* a, double* x, int i, int j) {
  for (int c = 0; c < n; ++c) {
    double t = a[i * n + c];
    a[i * n + c] = a[j * n + c];
    a[j * n + c] = t;
  }
  double t = x[i];
  x[i] = x[j];
  x[j] = t;
}

/// Swap columns i and j of A (n x n, row-major).
inline void swap_columns(int n, double* a, int i, int j) {
  for (int r = 0; r < n; ++r) {
    double t = a[r * n + i];
    a[r * n + i] = a[r * n + j];
    a[r * n + j] = t;
  }
}

/// Eliminate column k below the pivot a[k][k] (rows k+1..n-1, and b).
inline void eliminate_below(int n, double* a, double* x, int k) {
  for (int r = k + 1; r < n; ++r) {
    double factor = a[r * n + k] / a[k * n + k];
    if (factor == 0.0) continue;
    for (int c = k + 1; c < n; ++c) a[r * n + c] -= factor * a[k * n + c];
    x[r] -= factor * x[k];
  }
}

}  // namespace detail

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
    if (pivot != k) detail::swap_rows(n, a, x, k, pivot);
    detail::eliminate_below(n, a, x, k);
  }
  for (int k = n - 1; k >= 0; --k) {
    double s = x[k];
    for (int c = k + 1; c < n; ++c) s -= a[k * n + c] * x[c];
    x[k] = s / a[k * n + k];
  }
}

namespace detail {

/// solve_rank_revealing's algorithm; Size is int, or std::integral_constant
/// when the generated code knows n, so that the C++ compiler unrolls it.
/// col, row (n each) and y (n) are scratch space.
template <class Size>
inline int rank_revealing_in(Size n, double* a, double* x, double rel_tol, int* dependent, double* closest, int* col,
                             int* row, double* y) {
  double scale = 0.0;
  bool finite = true;
  for (int i = 0; i < n * n; ++i) {
    const double v = std::fabs(a[i]);
    finite = finite && v <= std::numeric_limits<double>::max();  // false for inf and NaN
    scale = v > scale ? v : scale;
  }
  if (closest) *closest = finite && scale > 0.0 ? 1.0 : 0.0;
  if (!finite) {
    for (int i = 0; i < n; ++i) x[i] = std::numeric_limits<double>::quiet_NaN();
    return 0;
  }
  // col[k]: the unknown eliminated at step k; row[k]: the equation (as
  // numbered on entry) now in row k
  for (int k = 0; k < n; ++k) col[k] = k, row[k] = k;
  int rank = n;
  for (int k = 0; k < n; ++k) {
    int pr = k, pc = k;
    double best = -1.0;
    for (int r = k; r < n; ++r)
      for (int c = k; c < n; ++c)
        if (std::fabs(a[r * n + c]) > best) best = std::fabs(a[r * n + c]), pr = r, pc = c;
    if (!(best > rel_tol * scale)) {
      rank = k;
      break;
    }
    if (closest && scale > 0.0 && best / scale < *closest) *closest = best / scale;
    if (pr != k) {
      swap_rows(n, a, x, k, pr);
      std::swap(row[k], row[pr]);
    }
    if (pc != k) {
      swap_columns(n, a, k, pc);
      std::swap(col[k], col[pc]);
    }
    eliminate_below(n, a, x, k);
  }
  for (int k = n - 1; k >= 0; --k) {
    if (k >= rank) {
      y[k] = 0.0;
      continue;
    }
    double s = x[k];
    for (int c = k + 1; c < rank; ++c) s -= a[k * n + c] * y[c];
    y[k] = s / a[k * n + k];
  }
  for (int k = 0; k < n; ++k) x[col[k]] = y[k];
  if (dependent)
    for (int k = rank; k < n; ++k) dependent[k - rank] = row[k];
  return rank;
}

/// With scratch on the stack up to kMax unknowns (the generated code's
/// systems), on the heap beyond (a row of 40 four-bars has 80 multipliers).
template <class Size>
inline int rank_revealing(Size n, double* a, double* x, double rel_tol, int* dependent, double* closest) {
  constexpr int kMax = 64;
  if (n > kMax) {
    std::vector<int> col(static_cast<std::size_t>(n)), row(static_cast<std::size_t>(n));
    std::vector<double> y(static_cast<std::size_t>(n));
    return rank_revealing_in(n, a, x, rel_tol, dependent, closest, col.data(), row.data(), y.data());
  }
  int col[kMax], row[kMax];
  double y[kMax];
  return rank_revealing_in(n, a, x, rel_tol, dependent, closest, col, row, y);
}

}  // namespace detail

/// Solve A x = b where A may be rank deficient (the multipliers of cut
/// joints whose rows become dependent, a parallelogram whose links align):
/// Gaussian elimination with complete pivoting; once every remaining entry is
/// below `rel_tol` times the largest entry of A, the remaining unknowns are
/// set to 0 and the rest back-substituted (a basic solution: for a consistent
/// system, any solution gives the same motion). `a` (n x n, row-major) is
/// overwritten, `x` holds b on entry and the solution on return; returns the
/// rank found. With `dependent`, its first n - rank entries receive the rows
/// (as numbered on entry) left without a pivot: the rows the others imply.
/// With `closest`, it receives the smallest pivot kept over the largest entry
/// of A (1 for a single unknown, about 1e-1 for a well-conditioned system):
/// how close A came to losing rank beyond the rank found.
/// Non-finite entries give NaN, as solve_linear does.
inline int solve_rank_revealing(int n, double* a, double* x, double rel_tol = 1e-10, int* dependent = nullptr,
                                double* closest = nullptr) {
  return detail::rank_revealing(n, a, x, rel_tol, dependent, closest);
}

/// The same with n known at compile time (what generated code calls): the
/// loops unroll, a 2 x 2 system costs a few dozen instructions.
template <int N>
inline int solve_rank_revealing(double* a, double* x, double rel_tol = 1e-10, int* dependent = nullptr,
                                double* closest = nullptr) {
  return detail::rank_revealing(std::integral_constant<int, N>{}, a, x, rel_tol, dependent, closest);
}

}  // namespace mbgrt
