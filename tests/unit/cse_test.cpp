// cse_test.cpp — codegen/cse and codegen/render: a method's common
// subexpressions found over its typed statements, then every value printed once.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "codegen/cse.hpp"
#include "codegen/render.hpp"

namespace {

using mbgc::codegen::CppStmt;
using mbgc::codegen::ExprNames;
using mbgc::codegen::render;
using mbgc::codegen::share_subexpressions;
namespace ir = mbgc::ir;

const ir::Namer kNames{[](int id) { return "x" + std::to_string(id); }, [](int id) { return "p" + std::to_string(id); }};

/// The statements after the pass and the printer, as the file shows them.
std::vector<std::string> printed(std::vector<CppStmt> body, const ExprNames& known = {}, ir::CppOps* ops = nullptr) {
  int counter = 0;
  share_subexpressions(body, 0, known, counter);
  render(body, 0, known, kNames, ops);
  std::vector<std::string> out;
  for (const CppStmt& s : body) out.push_back(s.kind == CppStmt::Kind::Comment ? "// " + s.text : s.code());
  return out;
}

const ir::Expr x0 = ir::var(0), x1 = ir::var(1);
const ir::Expr s = ir::call(ir::Fn::Sin, {x0});  // read by both statements below

TEST(CommonSubexpressions, ARepeatedValueIsDefinedOnceBeforeItsFirstUse) {
  const std::vector<std::string> out = printed({
      CppStmt::comment("model.mbg:1:1  first"),
      CppStmt::assign("xdot[0]", ir::mul(s, x1)),
      CppStmt::assign("xdot[1]", ir::add(s, x1)),
  });
  const std::vector<std::string> expected = {
      "// model.mbg:1:1  first",
      "// (cseN: a subexpression several equations below share)",
      "const double cse1 = std::sin(x0);",
      "xdot[0] = cse1 * x1;",
      "xdot[1] = cse1 + x1;",
  };
  EXPECT_EQ(out, expected);
}

TEST(CommonSubexpressions, AnEquationWhoseWholeValueRecursNamesItItself) {
  CppStmt f = CppStmt::local("hub_f", ir::div(x0, x1));
  f.may_name = CppStmt::Naming::unnamed;
  const std::vector<std::string> out = printed({std::move(f), CppStmt::assign("xdot[0]", ir::mul(ir::div(x0, x1), s)),
                                                CppStmt::assign("xdot[1]", ir::div(x0, x1))});
  const std::vector<std::string> expected = {
      "const double hub_f = x0 / x1;",
      "xdot[0] = hub_f * std::sin(x0);",
      "xdot[1] = hub_f;",
  };
  EXPECT_EQ(out, expected);
}

TEST(CommonSubexpressions, ADerivedConstantTakesOverFromAnEarlierTemporary) {
  // Its value is shared before it is assigned: `always` makes later statements read the member.
  const ir::Expr k = ir::mul(ir::param(0), ir::param(1));
  CppStmt member = CppStmt::assign("derived1_", k);
  member.may_name = CppStmt::Naming::always;
  CppStmt local = CppStmt::assign("derived1_", k);
  local.may_name = CppStmt::Naming::unnamed;
  const std::vector<CppStmt> before = {CppStmt::assign("a", ir::add(k, ir::param(2))), CppStmt::assign("b", ir::sub(k, ir::param(2)))};
  std::vector<CppStmt> with_member = before, with_local = before;
  with_member.insert(with_member.begin() + 1, member);
  with_local.insert(with_local.begin() + 1, local);
  EXPECT_EQ(printed(with_member).back(), "b = derived1_ - p2;");
  EXPECT_EQ(printed(with_local).back(), "b = cse1 - p2;");
}

TEST(CommonSubexpressions, KnownNamesAreReadNotSharedAgain) {
  ExprNames known;
  known.emplace(s, "in[0]");
  const std::vector<std::string> out =
      printed({CppStmt::assign("out[0]", ir::mul(s, x1)), CppStmt::assign("out[1]", ir::add(s, x1))}, known);
  const std::vector<std::string> expected = {"out[0] = in[0] * x1;", "out[1] = in[0] + x1;"};
  EXPECT_EQ(out, expected);
}

TEST(CommonSubexpressions, ALinearBlocksArraysStayTogether) {
  // What the right-hand side shares is defined before the matrix, not between the two arrays.
  CppStmt b = CppStmt::array_of("blk1_x", {ir::add(s, x1), ir::sub(s, x1)});
  b.with_previous = true;
  const std::vector<std::string> out = printed({CppStmt::array_of("blk1_a", {x0, x1, x1, x0}, 2), std::move(b)});
  const std::vector<std::string> expected = {
      "// (cseN: a subexpression several equations below share)",
      "const double cse1 = std::sin(x0);",
      "double blk1_a[4] = {",
      "    x0, x1,",
      "    x1, x0,",
      "};",
      "double blk1_x[2] = {cse1 + x1, cse1 - x1};",
  };
  EXPECT_EQ(out, expected);
}

TEST(CommonSubexpressions, OperationsAreCountedOnceAsPrinted) {
  ir::CppOps ops;
  printed({CppStmt::assign("xdot[0]", ir::mul(s, x1)), CppStmt::assign("xdot[1]", ir::add(s, x1))}, {}, &ops);
  EXPECT_EQ(ops.call, 1u);  // sin, in cse1's definition only
  EXPECT_EQ(ops.mul, 1u);
  EXPECT_EQ(ops.add, 1u);
}

TEST(CommonSubexpressions, AStatementWrittenBeforeItsValuesArePrintedIsACodegenBug) {
  const CppStmt st = CppStmt::assign("xdot[0]", x0);
  EXPECT_THROW((void)st.code(), std::logic_error);
  EXPECT_EQ(printed({CppStmt::param("p_m", 3, ir::mul(ir::constant(2.0), ir::param(1)), "  // m.mbg:1:1")}).front(),
            "p_m = param(3, 2.0 * p1);  // m.mbg:1:1");
}

}  // namespace
