#include "linearize.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace mbgrt::detail {

bool numeric_jacobian(GuardedModel& model, double t, const double* x, std::vector<double>& jac) {
  const std::size_t n = model.size();
  jac.assign(n * n, 0.0);
  std::vector<double> xp(x, x + n), fp(n), fm(n);
  for (std::size_t j = 0; j < n; ++j) {
    // Central differences balance truncation (~h^2) against rounding (~eps/h)
    // near h ~ 1e-6 relative; the floor of 1 (SI units) keeps h away from
    // zero for states that sit at an equilibrium value of 0.
    const double h = 1e-6 * std::max(std::abs(x[j]), 1.0);
    xp[j] = x[j] + h;
    const double up = xp[j];
    if (model.derivative(t, xp.data(), fp.data()) != 0) return false;
    xp[j] = x[j] - h;
    const double down = xp[j];
    if (model.derivative(t, xp.data(), fm.data()) != 0) return false;
    xp[j] = x[j];
    // Divide by the step actually represented in floating point.
    const double width = up - down;
    for (std::size_t i = 0; i < n; ++i) jac[i * n + j] = (fp[i] - fm[i]) / width;
  }
  return true;
}

std::vector<Mode> modes_of(const std::vector<double>& jac, std::size_t n) {
  std::vector<Mode> modes;
  if (n == 0) return modes;
  const auto rows = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd a(rows, rows);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < rows; ++j)
      a(i, j) = jac[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j)];

  Eigen::EigenSolver<Eigen::MatrixXd> solver(a, /*computeEigenvectors=*/false);
  for (const std::complex<double>& lambda : solver.eigenvalues()) {
    // Eigen returns complex eigenvalues of a real matrix as exact conjugate pairs.
    if (lambda.imag() < 0.0) continue;
    const double omega = std::abs(lambda);
    double zeta = omega > 0.0 ? -lambda.real() / omega : std::nan("");
    if (zeta == 0.0) zeta = 0.0;  // print an undamped mode as 0, not -0
    modes.push_back({omega, std::abs(lambda.imag()) / (2 * std::numbers::pi), zeta});
  }
  std::stable_sort(modes.begin(), modes.end(),
                   [](const Mode& a, const Mode& b) { return a.omega_rad_s < b.omega_rad_s; });
  return modes;
}

void write_modes(OutputFile& out, const std::vector<Mode>& modes) {
  std::string text = "index,omega_rad_s,f_hz,damping_ratio\n";
  for (std::size_t k = 0; k < modes.size(); ++k)
    text += fmt::format("{},{},{},{}\n", k + 1, modes[k].omega_rad_s, modes[k].f_hz,
                        modes[k].damping_ratio);
  out.write(text);
}

}  // namespace mbgrt::detail
