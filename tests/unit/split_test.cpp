// split_test.cpp — codegen/split: a long method cut into parts.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "codegen/split.hpp"

namespace {

using mbgc::codegen::CppFunction;
using mbgc::codegen::CppStmt;
using mbgc::codegen::split_method;

CppFunction method(std::vector<CppStmt> body) {
  return {"DERIVATIVE", "void derivative(double t, const double* x, double* xdot) override", std::move(body)};
}

std::vector<std::string> texts(const CppFunction& f) {
  std::vector<std::string> out;
  for (const CppStmt& s : f.body) out.push_back(s.code());
  return out;
}

TEST(SplitMethod, AShortMethodStaysWhole) {
  EXPECT_FALSE(split_method(method({CppStmt::line("(void)t;"), CppStmt::assign("xdot[0]", "x[0]")}), 5));
}

TEST(SplitMethod, CutsAtCommentsAndMakesWhatLaterPartsReadMembers) {
  const CppFunction f = method({
      CppStmt::line("(void)t;"),
      CppStmt::comment("model.mbg:1:1  first"),
      CppStmt::read("a", "x", 0),      // a read of x: each part that reads it reads x
      CppStmt::local("b", "2.0 * a"),   // read in its own part only
      CppStmt::local("c", "a + b"),     // read by part 2
      CppStmt::comment("model.mbg:2:1  second"),
      CppStmt::local("d", "std::cos(c) * 1e-08"),
      CppStmt::assign("xdot[0]", "d + a"),
  });
  const auto split = split_method(f, 5);
  ASSERT_TRUE(split);
  ASSERT_EQ(split->parts.size(), 2u);
  EXPECT_EQ(texts(split->method), (std::vector<std::string>{"derivative_part1(t, x, xdot);", "derivative_part2(t, x, xdot);"}));
  EXPECT_EQ(split->method.signature, f.signature);
  EXPECT_EQ(split->parts[0].signature, "void derivative_part1(double t, const double* x, double* xdot)");
  // every part names its parameters once and reads x itself; the locals
  // part 2 reads are members, in the order they are defined; `b`, `cos` and
  // the number's `e` are not
  EXPECT_EQ(texts(split->parts[0]),
            (std::vector<std::string>{"(void)t;", "(void)x;", "(void)xdot;", "const double a = x[0];", "model.mbg:1:1  first",
                                      "const double b = 2.0 * a;", "c = a + b;"}));
  EXPECT_EQ(texts(split->parts[1]),
            (std::vector<std::string>{"(void)t;", "(void)x;", "(void)xdot;", "const double a = x[0];", "model.mbg:2:1  second",
                                      "const double d = std::cos(c) * 1e-08;", "xdot[0] = d + a;"}));
  EXPECT_EQ(split->members, (std::vector<std::string>{"c"}));
}

TEST(SplitMethod, EachPartReadsTheUnknownsItUsesUnderTheirComment) {
  const CppFunction f = method({
      CppStmt::line("(void)t;"),
      CppStmt::comment("states"),
      CppStmt::read("a", "x", 0),
      CppStmt::read("b", "x", 1),
      CppStmt::read("c", "x", 2),
      CppStmt::comment("model.mbg:1:1  first"),
      CppStmt::local("d", "a * c"),
      CppStmt::assign("xdot[0]", "d"),
      CppStmt::comment("model.mbg:2:1  second"),
      CppStmt::assign("xdot[1]", "b + d"),
      CppStmt::assign("xdot[2]", "b"),
  });
  // the reads do not count towards a part's lines: 6 statements left, in two parts
  const auto split = split_method(f, 4);
  ASSERT_TRUE(split);
  ASSERT_EQ(split->parts.size(), 2u);
  EXPECT_EQ(texts(split->parts[0]), (std::vector<std::string>{"(void)t;", "(void)x;", "(void)xdot;", "states", "const double a = x[0];",
                                                              "const double c = x[2];", "model.mbg:1:1  first", "d = a * c;",
                                                              "xdot[0] = d;"}));
  EXPECT_EQ(texts(split->parts[1]), (std::vector<std::string>{"(void)t;", "(void)x;", "(void)xdot;", "states", "const double b = x[1];",
                                                              "model.mbg:2:1  second", "xdot[1] = b + d;", "xdot[2] = b;"}));
  EXPECT_EQ(split->members, (std::vector<std::string>{"d"}));
}

TEST(SplitMethod, NeverCutsBetweenALinearBlocksArraysAndTheirReaders) {
  std::vector<CppStmt> body{CppStmt::comment("one"), CppStmt::read("a", "x", 0),
                            CppStmt::line("double blk1_a[1] = {"), CppStmt::line("    a,"), CppStmt::line("};"),
                            CppStmt::line("double blk1_x[1] = {1.0};"), CppStmt::comment("inside the block's span"),
                            CppStmt::line("mbgrt::solve_linear(1, blk1_a, blk1_x);"),
                            CppStmt::local("u", "blk1_x[0]"), CppStmt::comment("after it"),
                            CppStmt::assign("xdot[0]", "u")};
  const auto split = split_method(method(body), 4);
  ASSERT_TRUE(split);
  ASSERT_EQ(split->parts.size(), 2u);
  EXPECT_EQ(split->parts[1].body[3].text, "after it");
  EXPECT_EQ(split->members, (std::vector<std::string>{"u"}));
}

TEST(SplitMethod, AConstMethodIsNotCut) {
  CppFunction f{"", "double energy(const double* x) const", {}};
  for (int i = 0; i < 10; ++i) {
    f.body.push_back(CppStmt::comment("c"));
    f.body.push_back(CppStmt::read("a" + std::to_string(i), "x", 0));
  }
  EXPECT_FALSE(split_method(f, 4));
}

}  // namespace
