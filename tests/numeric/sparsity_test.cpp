// sparsity_test.cpp — the pattern mbgc gives for IDA's matrix dF/dy + c_j dF/dy'
// (Model::residual_sparsity, reduce/sparsity.hpp) must hold every entry that
// can be nonzero: checked against a dense finite-difference Jacobian of the
// generated residual at a generic point (every unknown and derivative moved
// off its initial value), column by column, for y and y' separately.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "sparsity_andrews.hpp"
#include "sparsity_crank_rocker.hpp"
#include "sparsity_crank_rocker_flexible.hpp"

namespace {

struct Coverage {
  std::size_t n = 0, stored = 0, missing = 0, nonzero = 0;
  std::string first_missing;
};

Coverage check(mbgrt::Model& m) {
  Coverage c;
  c.n = m.size();
  const std::size_t n = c.n;
  std::vector<double> y(n), yp(n), r0(n), r1(n);
  m.initial(0.0, y.data(), yp.data());
  for (std::size_t i = 0; i < n; ++i) {
    y[i] += 0.013 * std::sin(1.0 + static_cast<double>(i));
    yp[i] += 0.021 * std::cos(2.0 + static_cast<double>(i));
  }
  std::vector<long> starts, rows;
  EXPECT_TRUE(m.residual_sparsity(starts, rows));
  EXPECT_EQ(starts.size(), n + 1);
  std::vector<std::set<long>> column(n);
  for (std::size_t j = 0; j + 1 < starts.size() && j < n; ++j)
    for (long k = starts[j]; k < starts[j + 1]; ++k) column[j].insert(rows[static_cast<std::size_t>(k)]);
  c.stored = rows.size();
  const double t = 0.1;
  m.residual(t, y.data(), yp.data(), r0.data());
  for (std::size_t j = 0; j < n; ++j)
    for (std::vector<double>* v : {&y, &yp}) {
      const double saved = (*v)[j], h = 1e-7 * (1.0 + std::abs(saved));
      (*v)[j] = saved + h;
      m.residual(t, y.data(), yp.data(), r1.data());
      (*v)[j] = saved;
      for (std::size_t i = 0; i < n; ++i) {
        const double d = (r1[i] - r0[i]) / h;
        if (d == 0.0) continue;
        ++c.nonzero;
        if (column[j].count(static_cast<long>(i))) continue;
        if (c.missing++ == 0)
          c.first_missing = "d(residual " + std::to_string(i) + ")/d(" + (v == &y ? "y" : "y'") + " of " +
                            m.variable_name(j) + ") = " + std::to_string(d);
      }
    }
  return c;
}

TEST(ResidualSparsity, CoversTheJacobianOfTheCrankRocker) {
  crank_rocker::crank_rocker_model m;
  const Coverage c = check(m);
  EXPECT_EQ(c.missing, 0u) << c.first_missing;
  EXPECT_GT(c.nonzero, c.n);                  // the check saw the Jacobian
  EXPECT_LT(c.stored, c.n * c.n / 5) << c.n;  // and the pattern is sparse: 801 of 6400 entries
}

TEST(ResidualSparsity, CoversTheJacobianOfAndrewsSqueezer) {
  andrews::andrews_model m;
  const Coverage c = check(m);
  EXPECT_EQ(c.missing, 0u) << c.first_missing;
  EXPECT_GT(c.nonzero, c.n);
  EXPECT_LT(c.stored, c.n * c.n / 10) << c.n;  // 2427 of 37249
}

TEST(ResidualSparsity, CoversTheJacobianOfTheFlexibleCrankRocker) {
  crank_rocker_flexible::crank_rocker_flexible_model m;
  const Coverage c = check(m);
  EXPECT_EQ(c.missing, 0u) << c.first_missing;
  EXPECT_GT(c.nonzero, c.n);
}

}  // namespace
