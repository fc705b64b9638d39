// Unit tests for reduce/row_facts: what a tree's joint rows say of the loop's
// solution, on small loops written by hand (variables by number).
#include <gtest/gtest.h>

#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "ir/expr.hpp"
#include "reduce/row_facts.hpp"

namespace {

using namespace mbgc::ir;
using mbgc::reduce::RowFacts;
using mbgc::reduce::TornLoop;

struct Loop {
  TornLoop loop;
  std::unordered_map<int, std::vector<int>> refs;
  std::unordered_map<int, int> body;
  std::unordered_set<int> multipliers;

  void tear(int t, const Expr& residual, std::vector<int> reads) {
    loop.tears.push_back(t);
    loop.tear_residuals.push_back(residual);
    refs[t] = std::move(reads);
    body[t] = 0;
  }
  void unknown(int u, const Expr& solution, std::vector<int> reads) {
    loop.order.push_back(u);
    loop.solution[u] = solution;
    refs[u] = std::move(reads);
    body[u] = 0;
  }
};

TEST(RowFacts, AFreeDirectionsEffortAndWhatReadsOnlyItVanish) {
  // row of tear 1: v2 = 0; v2 = v3 (an alias the row reaches), v4 = 2 v3 (the
  // torque the parent reads), v5 = v3 + v6 (reads something else too)
  Loop l;
  l.tear(1, var(2), {2});
  l.unknown(3, var(7), {7});
  l.unknown(2, var(3), {3});
  l.unknown(7, param(0), {});
  l.unknown(4, mul(constant(2), var(3)), {3});
  l.unknown(6, param(1), {});
  l.unknown(5, add(var(3), var(6)), {3, 6});
  RowFacts f(l.loop, l.refs, l.body, l.multipliers, -2);
  EXPECT_TRUE(f.zero(2));
  EXPECT_TRUE(f.zero(3));
  EXPECT_TRUE(f.zero(7));  // v3 = v7: v7 vanishes too
  EXPECT_TRUE(f.zero(4));
  EXPECT_FALSE(f.zero(5));
  EXPECT_FALSE(f.zero(6));
  EXPECT_FALSE(f.zero(1));  // a tear is never one
  EXPECT_TRUE(is_zero(f.without_zeros(add(var(4), mul(param(2), var(2))))));
  EXPECT_TRUE(equal(f.without_zeros(add(var(5), var(4))), var(5)));
}

TEST(RowFacts, ARowOverTwoEffortsConfinesThemToOneDirection) {
  // row of tear 10: v11 = 0, v11 = cos(p) v12 + sin(p) v13; v14 = a v12 + b v13
  // is (a, b) . (-sin p, cos p) mu = (b cos p - a sin p) mu
  Loop l;
  const Expr c = call(Fn::Cos, {param(0)}), s = call(Fn::Sin, {param(0)});
  l.unknown(12, param(3), {});
  l.unknown(13, param(4), {});
  l.tear(10, var(11), {11});
  l.unknown(11, add(mul(c, var(12)), mul(s, var(13))), {12, 13});
  l.unknown(14, add(mul(param(1), var(12)), mul(param(2), var(13))), {12, 13});
  l.unknown(16, param(5), {});
  l.unknown(15, add(var(12), var(16)), {12, 16});
  RowFacts f(l.loop, l.refs, l.body, l.multipliers, -2);
  EXPECT_TRUE(f.zero(11));
  EXPECT_FALSE(f.zero(12));
  auto m = f.multiple_of_pair(14);
  ASSERT_TRUE(m.has_value());
  const RowFacts::Pair& q = f.pair(m->first);
  EXPECT_EQ(q.v1, 12);
  EXPECT_EQ(q.v2, 13);
  EXPECT_TRUE(equal(m->second, sub(mul(param(2), c), mul(param(1), s))));
  EXPECT_FALSE(f.multiple_of_pair(15).has_value());  // reads v16 too
  EXPECT_FALSE(f.multiple_of_pair(10).has_value());  // a tear
}

TEST(RowFacts, ARowWithAnElementOnItSaysNothing) {
  // row of tear 20: v21 = k q (a spring on the direction, q its state): the
  // effort is not zero, and what reads it is not confined
  Loop l;
  l.unknown(21, param(1), {});
  l.tear(20, sub(var(21), mul(param(2), param(3))), {21});
  l.unknown(23, mul(param(4), var(21)), {21});
  RowFacts f(l.loop, l.refs, l.body, l.multipliers, -2);
  EXPECT_FALSE(f.zero(21));
  EXPECT_FALSE(f.zero(23));
  EXPECT_FALSE(f.multiple_of_pair(23).has_value());
}

}  // namespace
