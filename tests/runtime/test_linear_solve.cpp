// mbgrt::solve_linear: the dense solve generated code uses for algebraic loops
// whose pivots depend on the state.
#include <gtest/gtest.h>

#include <cmath>
#include <mbgrt/linear_solve.hpp>
#include <random>
#include <vector>

TEST(LinearSolve, RecoversAKnownSolutionOfRandomSystems) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {1, 2, 3, 6, 12}) {
    std::vector<double> a(static_cast<std::size_t>(n * n)), x_true(static_cast<std::size_t>(n)), b(static_cast<std::size_t>(n), 0.0);
    for (double& v : a) v = u(rng);
    for (double& v : x_true) v = u(rng);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) b[static_cast<std::size_t>(r)] += a[static_cast<std::size_t>(r * n + c)] * x_true[static_cast<std::size_t>(c)];
    mbgrt::solve_linear(n, a.data(), b.data());
    for (int i = 0; i < n; ++i) EXPECT_NEAR(b[static_cast<std::size_t>(i)], x_true[static_cast<std::size_t>(i)], 1e-10) << "n = " << n;
  }
}

TEST(LinearSolve, PivotsPastAZeroDiagonal) {
  // [[0, 1], [1, 0]] x = [2, 3]: the leading entry is zero, a symbolic
  // elimination in this order would divide by it.
  double a[4] = {0.0, 1.0, 1.0, 0.0};
  double x[2] = {2.0, 3.0};
  mbgrt::solve_linear(2, a, x);
  EXPECT_DOUBLE_EQ(x[0], 3.0);
  EXPECT_DOUBLE_EQ(x[1], 2.0);
}

TEST(LinearSolve, SingularSystemGivesNaNForTheGuardToReport) {
  double a[4] = {1.0, 2.0, 2.0, 4.0};
  double x[2] = {1.0, 1.0};
  mbgrt::solve_linear(2, a, x);
  EXPECT_TRUE(std::isnan(x[0]));
  EXPECT_TRUE(std::isnan(x[1]));
}
