// Unit tests for ir/constant: the one compile-time evaluator of AST
// expressions (loop bounds and name indices, constant settings, drawn sizes).
// Expressions come from the parser; values are checked against the same
// arithmetic written out, failures by where and why they are reported.
//
// Test suites are named Constant* so that `ctest -R Constant` selects them.
#include "ir/constant.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;
using mbgc::ir::AstExpr;
using mbgc::ir::ConstantRules;
using mbgc::ir::NotConstant;

/// The parsed expression of `param p = <text>`.
mbgc::ir::AstExprPtr parsed(const std::string& text) {
  auto c = run("param p = " + text + "\n", Stage::Parse);
  EXPECT_TRUE(c->ok()) << c->messages();
  for (const auto& s : c->ast.stmts)
    if (auto* p = std::get_if<mbgc::ir::AstParam>(&s)) return p->value;
  ADD_FAILURE() << "no param in " << text;
  return nullptr;
}

/// Rules whose names are `values`; failures recorded as (column, why).
struct Recorder {
  std::map<std::string, double> values;
  std::vector<std::pair<int, NotConstant>> failures;
  std::vector<std::string> unknown;

  ConstantRules rules(bool functions = false) {
    ConstantRules r;
    r.functions = functions;
    r.name = [this](const AstExpr& name, int) -> std::optional<double> {
      if (auto it = values.find(name.name); it != values.end()) return it->second;
      unknown.push_back(name.name);
      return std::nullopt;
    };
    r.failed = [this](const AstExpr& at, NotConstant why) { failures.emplace_back(at.loc.col, why); };
    return r;
  }
};

TEST(Constant, ArithmeticOfNumbersAndNamesAsWritten) {
  Recorder rec;
  rec.values = {{"N", 8}, {"L", 0.25}};
  auto e = parsed("-(N - 2) * L / 4 + 2 ^ 3");
  auto v = mbgc::ir::constant_value(*e, rec.rules());
  ASSERT_TRUE(v);
  EXPECT_DOUBLE_EQ(*v, -(8.0 - 2.0) * 0.25 / 4.0 + 8.0);
  EXPECT_TRUE(rec.failures.empty());
}

TEST(Constant, EveryFailureIsReportedNotOnlyTheFirst) {
  Recorder rec;
  auto e = parsed("a + b * 2");
  EXPECT_FALSE(mbgc::ir::constant_value(*e, rec.rules()));
  EXPECT_EQ(rec.unknown, (std::vector<std::string>{"a", "b"}));
}

TEST(Constant, DivisionByZeroIsReportedAtTheDivision) {
  Recorder rec;
  rec.values = {{"k", 0}};
  auto e = parsed("1 + 3 / k");
  EXPECT_FALSE(mbgc::ir::constant_value(*e, rec.rules()));
  ASSERT_EQ(rec.failures.size(), 1u);
  EXPECT_EQ(rec.failures[0].second, NotConstant::division_by_zero);
  EXPECT_EQ(rec.failures[0].first, 17);  // the `/` of "param p = 1 + 3 / k"
}

TEST(Constant, FunctionsAndPiOnlyWhereAllowed) {
  auto e = parsed("tan(30 * pi / 180) + sqrt(4)");
  Recorder without;
  EXPECT_FALSE(mbgc::ir::constant_value(*e, without.rules(false)));
  // a call is then not arithmetic (its arguments are not looked at)
  EXPECT_TRUE(without.unknown.empty());
  ASSERT_EQ(without.failures.size(), 2u);
  EXPECT_EQ(without.failures[0].second, NotConstant::form);
  EXPECT_EQ(without.failures[1].second, NotConstant::form);
  Recorder name_only;
  EXPECT_FALSE(mbgc::ir::constant_value(*parsed("2 * pi"), name_only.rules(false)));
  EXPECT_EQ(name_only.unknown, (std::vector<std::string>{"pi"}));  // a name like any other

  Recorder with;
  auto v = mbgc::ir::constant_value(*e, with.rules(true));
  ASSERT_TRUE(v);
  EXPECT_DOUBLE_EQ(*v, std::tan(30 * std::numbers::pi / 180) + 2.0);
  EXPECT_TRUE(with.failures.empty() && with.unknown.empty());
}

TEST(Constant, ListsAndIndicesAreNotConstants) {
  for (const char* text : {"[1, 2]", "[1, 2][1]", "max(1, 2)"}) {
    Recorder rec;
    EXPECT_FALSE(mbgc::ir::constant_value(*parsed(text), rec.rules(true))) << text;
    ASSERT_EQ(rec.failures.size(), 1u) << text;
    EXPECT_EQ(rec.failures[0].second, NotConstant::form) << text;
  }
}

TEST(Constant, NothingDeeperThanTheLimit) {
  Recorder rec;
  ConstantRules rules = rec.rules();
  auto e = parsed("((((1))))+2");  // the parser drops parentheses: depth 1
  rules.max_depth = 0;
  EXPECT_FALSE(mbgc::ir::constant_value(*e, rules));
  rules.max_depth = 1;
  EXPECT_EQ(mbgc::ir::constant_value(*e, rules), 3.0);
  EXPECT_TRUE(rec.failures.empty());
}

}  // namespace
