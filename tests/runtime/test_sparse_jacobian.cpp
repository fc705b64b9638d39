// test_sparse_jacobian.cpp — IDA's matrix by grouped finite differences on a
// sparsity pattern (runtime/src/solvers/sparse_jacobian.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "solvers/sparse_jacobian.hpp"

namespace {

using mbgrt::detail::SparseJacobian;

// r_i = y_i^3 + y_{i-1} y_{i+1} + (i + 1) y'_i: tridiagonal in y, diagonal in y'.
constexpr std::size_t kN = 12;
int residual(const double* y, const double* yp, double* r) {
  for (std::size_t i = 0; i < kN; ++i) {
    const double left = i > 0 ? y[i - 1] : 0.0, right = i + 1 < kN ? y[i + 1] : 0.0;
    r[i] = y[i] * y[i] * y[i] + left * right + static_cast<double>(i + 1) * yp[i];
  }
  return 0;
}
// d r_i / d y_j + c d r_i / d y'_j
double exact(const double* y, double c, std::size_t i, std::size_t j) {
  if (i == j) return 3 * y[i] * y[i] + c * static_cast<double>(i + 1);
  if (j + 1 == i) return i + 1 < kN ? y[i + 1] : 0.0;
  if (j == i + 1) return i > 0 ? y[i - 1] : 0.0;
  return 0.0;
}

/// The tridiagonal pattern without its diagonal (SparseJacobian adds it).
SparseJacobian tridiagonal_without_diagonal() {
  std::vector<long> starts{0}, rows;
  for (std::size_t j = 0; j < kN; ++j) {
    if (j > 0) rows.push_back(static_cast<long>(j - 1));
    if (j + 1 < kN) rows.push_back(static_cast<long>(j + 1));
    starts.push_back(static_cast<long>(rows.size()));
  }
  return SparseJacobian(starts, rows);
}

TEST(SparseJacobian, AddsTheDiagonalAndGroupsColumnsThatShareNoRow) {
  const SparseJacobian sj = tridiagonal_without_diagonal();
  EXPECT_EQ(sj.size(), kN);
  EXPECT_EQ(sj.nonzeros(), 3 * kN - 2);
  EXPECT_EQ(sj.groups(), 3u);  // columns j, j + 3, j + 6, ... share no row
}

TEST(SparseJacobian, FillsDFdyPlusCjDFdypAndRestoresTheUnknowns) {
  SparseJacobian sj = tridiagonal_without_diagonal();
  std::vector<double> y(kN), yp(kN), r0(kN), w(kN, 1e8), values(sj.nonzeros());
  for (std::size_t i = 0; i < kN; ++i) {
    y[i] = 0.5 + 0.1 * static_cast<double>(i);
    yp[i] = -0.3 + 0.05 * static_cast<double>(i);
  }
  const std::vector<double> y_before = y, yp_before = yp;
  residual(y.data(), yp.data(), r0.data());
  const double cj = 250.0, h = 1e-3;
  ASSERT_EQ(sj.fill(residual, cj, h, y.data(), yp.data(), r0.data(), w.data(), values.data()), 0);
  EXPECT_EQ(y, y_before);  // bit for bit
  EXPECT_EQ(yp, yp_before);
  for (std::size_t j = 0; j < kN; ++j)
    for (long k = sj.column_starts()[j]; k < sj.column_starts()[j + 1]; ++k) {
      const auto i = static_cast<std::size_t>(sj.rows()[static_cast<std::size_t>(k)]);
      const double want = exact(y.data(), cj, i, j);
      EXPECT_NEAR(values[static_cast<std::size_t>(k)], want, 1e-6 * (1 + std::abs(want))) << i << ", " << j;
    }
}

TEST(SparseJacobian, PassesOnTheResidualsFailure) {
  SparseJacobian sj = tridiagonal_without_diagonal();
  std::vector<double> y(kN, 1.0), yp(kN, 0.0), r0(kN, 0.0), w(kN, 1.0), values(sj.nonzeros());
  const SparseJacobian::Residual failing = [](const double*, const double*, double*) { return -1; };
  EXPECT_EQ(sj.fill(failing, 1.0, 1e-3, y.data(), yp.data(), r0.data(), w.data(), values.data()), -1);
  EXPECT_EQ(y, std::vector<double>(kN, 1.0));
}

TEST(SparseJacobian, RejectsAPatternThatDoesNotAddUp) {
  EXPECT_THROW(SparseJacobian({0, 2}, {0}), std::invalid_argument);
  EXPECT_THROW(SparseJacobian({0, 1}, {3}), std::invalid_argument);
}

}  // namespace
