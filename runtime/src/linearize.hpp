// --linearize-at: small-signal modes of an ODE model around x(T).
#pragma once

#include <cstddef>
#include <vector>

#include "csv.hpp"
#include "guard.hpp"

namespace mbgrt::detail {

struct Mode {
  double omega_rad_s;    ///< |lambda|: undamped natural frequency
  double f_hz;           ///< |Im lambda| / 2 pi: damped frequency
  double damping_ratio;  ///< -Re lambda / |lambda| (NaN for lambda = 0)
};

/// Central-difference Jacobian df/dx at (t, x), row-major n x n. False if an
/// evaluation was non-finite; the blame is then recorded in `model`.
bool numeric_jacobian(GuardedModel& model, double t, const double* x, std::vector<double>& jac);

/// One mode per eigenvalue with Im >= 0 (a complex pair is one mode),
/// sorted by omega_rad_s, lowest first.
std::vector<Mode> modes_of(const std::vector<double>& jac, std::size_t n);

/// DAE F(t, y, y') = 0: central-difference pencil dF/dy (a) and dF/dy' (b),
/// row-major n x n. False if an evaluation was non-finite.
bool numeric_pencil(GuardedModel& model, double t, const double* y, const double* yp, std::vector<double>& a,
                    std::vector<double>& b);

/// The finite eigenvalues lambda of (dF/dy + lambda dF/dy') v = 0, as modes:
/// the linearised motion on the constraint manifold (the constraint rows and
/// multipliers give infinite eigenvalues, which are dropped).
std::vector<Mode> modes_of_pencil(const std::vector<double>& a, const std::vector<double>& b, std::size_t n);

void write_modes(OutputFile& out, const std::vector<Mode>& modes);

}  // namespace mbgrt::detail
