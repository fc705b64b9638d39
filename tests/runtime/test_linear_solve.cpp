// mbgrt::solve_linear: the dense solve generated code uses for algebraic loops
// whose pivots depend on the state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
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

TEST(RankRevealingSolve, AFullRankSystemIsSolvedAsByPartialPivoting) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {1, 2, 5, 9}) {
    std::vector<double> a(static_cast<std::size_t>(n * n)), x_true(static_cast<std::size_t>(n)), b(static_cast<std::size_t>(n), 0.0);
    for (double& v : a) v = u(rng);
    for (double& v : x_true) v = u(rng);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) b[static_cast<std::size_t>(r)] += a[static_cast<std::size_t>(r * n + c)] * x_true[static_cast<std::size_t>(c)];
    EXPECT_EQ(mbgrt::solve_rank_revealing(n, a.data(), b.data()), n);
    for (int i = 0; i < n; ++i) EXPECT_NEAR(b[static_cast<std::size_t>(i)], x_true[static_cast<std::size_t>(i)], 1e-10) << "n = " << n;
  }
}

TEST(RankRevealingSolve, ADependentRowGivesASolutionAndTheRankNotNaN) {
  // Rows 1 and 3 are the same constraint twice (b consistent): rank 2; the
  // dependent direction's unknown is 0 and A x = b holds.
  const double a0[9] = {1.0, 2.0, 0.5, 0.0, 1.0, -1.0, 2.0, 4.0, 1.0};
  const double b0[3] = {3.0, 1.0, 6.0};
  double a[9], x[3];
  std::copy(a0, a0 + 9, a);
  std::copy(b0, b0 + 3, x);
  EXPECT_EQ(mbgrt::solve_rank_revealing(3, a, x), 2);
  for (int r = 0; r < 3; ++r) {
    double s = 0;
    for (int c = 0; c < 3; ++c) s += a0[r * 3 + c] * x[c];
    EXPECT_NEAR(s, b0[r], 1e-12) << "row " << r;
  }
  for (double v : x) EXPECT_TRUE(std::isfinite(v));
  // partial pivoting on the same system gives NaN
  std::copy(a0, a0 + 9, a);
  std::copy(b0, b0 + 3, x);
  mbgrt::solve_linear(3, a, x);
  EXPECT_TRUE(std::isnan(x[0]));
}

TEST(RankRevealingSolve, BeyondSixtyFourUnknownsTheRankIsStillFound) {
  // 80 multipliers (a row of 40 four-bars): the scratch space moves to the
  // heap, the algorithm stays (it used to fall back to partial pivoting and
  // report full rank). Row 79 repeats row 3; b consistent.
  const int n = 80;
  std::vector<double> a0(n * n), b0(n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) a0[r * n + c] = r == c ? 4.0 : (std::abs(r - c) == 1 ? -1.0 : 0.0);
    b0[r] = 1.0 + 0.01 * r;
  }
  for (int c = 0; c < n; ++c) a0[79 * n + c] = a0[3 * n + c];
  b0[79] = b0[3];
  std::vector<double> a = a0, x = b0;
  std::vector<int> dependent(n, -1);
  EXPECT_EQ(mbgrt::solve_rank_revealing(n, a.data(), x.data(), 1e-10, dependent.data()), n - 1);
  EXPECT_TRUE(dependent[0] == 3 || dependent[0] == 79) << dependent[0];
  for (int r = 0; r < n; ++r) {
    double s = 0;
    for (int c = 0; c < n; ++c) s += a0[r * n + c] * x[c];
    EXPECT_NEAR(s, b0[r], 1e-12) << "row " << r;
  }
}

TEST(RankRevealingSolve, TheSizeKnownAtCompileTimeGivesTheSameBits) {
  // Generated code calls solve_rank_revealing<N>: the same algorithm, the
  // loops unrolled. Full rank, a dependent row and a NaN entry alike.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    double a[9], b[3];
    for (double& v : a) v = u(rng);
    for (double& v : b) v = u(rng);
    if (trial % 5 == 1) std::copy(a, a + 3, a + 6), b[2] = b[0];  // row 3 = row 1
    if (trial % 5 == 2) a[4] = NAN;
    double a1[9], x1[3], a2[9], x2[3];
    std::copy(a, a + 9, a1), std::copy(b, b + 3, x1);
    std::copy(a, a + 9, a2), std::copy(b, b + 3, x2);
    int dep1[3] = {-1, -1, -1}, dep2[3] = {-1, -1, -1};
    const int r1 = mbgrt::solve_rank_revealing(3, a1, x1, 1e-10, dep1);
    const int r2 = mbgrt::solve_rank_revealing<3>(a2, x2, 1e-10, dep2);
    EXPECT_EQ(r1, r2) << "trial " << trial;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(std::memcmp(&x1[i], &x2[i], sizeof(double)), 0) << "trial " << trial << " x[" << i << "]";
      EXPECT_EQ(dep1[i], dep2[i]) << "trial " << trial;
    }
  }
}

/// `closest` measures how near A came to losing rank beyond the rank found:
/// a row implied by the others throughout (a redundant loop) is not "close",
/// while a kept pivot that is small is.
TEST(RankRevealingSolve, ClosestIsTheSmallestPivotKept) {
  // rows 1 and 2 equal: rank 2; the kept pivots are 2 and 1 (of 2)
  double a[9] = {2, 0, 0, 0, 1, 1, 0, 1, 1};
  double x[3] = {2, 1, 1};
  double closest = -1.0;
  int dependent[3] = {-1, -1, -1};
  EXPECT_EQ(mbgrt::solve_rank_revealing(3, a, x, 1e-10, dependent, &closest), 2);
  EXPECT_DOUBLE_EQ(closest, 0.5);
  // full rank, one pivot 1e-6 of the largest entry
  double b[4] = {1, 0, 0, 1e-6};
  double y[2] = {1, 1};
  EXPECT_EQ(mbgrt::solve_rank_revealing(2, b, y, 1e-10, nullptr, &closest), 2);
  EXPECT_DOUBLE_EQ(closest, 1e-6);
}
