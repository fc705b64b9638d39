#include "linearize.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <complex>
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

bool numeric_pencil(GuardedModel& model, double t, const double* y, const double* yp, std::vector<double>& a,
                    std::vector<double>& b) {
  const std::size_t n = model.size();
  a.assign(n * n, 0.0);
  b.assign(n * n, 0.0);
  std::vector<double> yv(y, y + n), ypv(yp, yp + n), rp(n), rm(n);
  // one column of dF/dy (perturb = yv) or of dF/dy' (perturb = ypv), as in numeric_jacobian
  auto column = [&](std::vector<double>& perturb, std::vector<double>& into, std::size_t j) {
    const double x = perturb[j], h = 1e-6 * std::max(std::abs(x), 1.0);
    perturb[j] = x + h;
    const double up = perturb[j];
    if (model.residual(t, yv.data(), ypv.data(), rp.data()) != 0) return false;
    perturb[j] = x - h;
    const double down = perturb[j];
    if (model.residual(t, yv.data(), ypv.data(), rm.data()) != 0) return false;
    perturb[j] = x;
    for (std::size_t i = 0; i < n; ++i) into[i * n + j] = (rp[i] - rm[i]) / (up - down);
    return true;
  };
  for (std::size_t j = 0; j < n; ++j)
    if (!column(yv, a, j) || !column(ypv, b, j)) return false;
  return true;
}

namespace {

Mode mode_of(std::complex<double> lambda) {
  const double omega = std::abs(lambda);
  double zeta = omega > 0.0 ? -lambda.real() / omega : std::nan("");
  if (zeta == 0.0) zeta = 0.0;  // print an undamped mode as 0, not -0
  return {omega, std::abs(lambda.imag()) / (2 * std::numbers::pi), zeta};
}

void sort_modes(std::vector<Mode>& modes) {
  std::stable_sort(modes.begin(), modes.end(),
                   [](const Mode& a, const Mode& b) { return a.omega_rad_s < b.omega_rad_s; });
}

}  // namespace

std::vector<Mode> modes_of_pencil(const std::vector<double>& a, const std::vector<double>& b, std::size_t n) {
  std::vector<Mode> modes;
  if (n == 0) return modes;
  const auto rows = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd A(rows, rows), Bm(rows, rows);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < rows; ++j) {
      A(i, j) = a[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j)];
      Bm(i, j) = -b[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j)];
    }
  // A v = lambda (-B) v by the QZ algorithm: lambda = alpha / beta, infinite for beta = 0
  Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> qz(A, Bm, /*computeEigenvectors=*/false);
  const double scale = A.cwiseAbs().maxCoeff() + Bm.cwiseAbs().maxCoeff();
  for (Eigen::Index k = 0; k < rows; ++k) {
    const std::complex<double> alpha = qz.alphas()(k);
    const double beta = qz.betas()(k);
    // A beta at rounding level of the pencil is an infinite eigenvalue (a constraint row)
    if (std::abs(beta) <= 1e-10 * scale || std::abs(alpha) > 1e10 * std::abs(beta)) continue;
    const std::complex<double> lambda = alpha / beta;
    if (lambda.imag() < 0.0) continue;
    modes.push_back(mode_of(lambda));
  }
  sort_modes(modes);
  return modes;
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
    modes.push_back(mode_of(lambda));
  }
  sort_modes(modes);
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
