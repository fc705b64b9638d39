// Unit tests for pass 1 (parse/): statement kinds, expression precedence and
// associativity, junction and bond syntax, source locations, comments, and
// error reporting and recovery.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;
using ir::AstExpr;
using Kind = ir::AstExpr::Kind;

std::unique_ptr<Compiled> parse(const std::string& text) { return run(text, Stage::Parse); }

template <class T>
std::vector<const T*> all_of(const ir::AstProgram& p) {
  std::vector<const T*> out;
  for (const ir::AstStmt& s : p.stmts)
    if (auto* x = std::get_if<T>(&s)) out.push_back(x);
  return out;
}

/// The expression of `param <name> = ...` in a one-parameter model.
ir::AstExprPtr param_expr(const std::string& expr_text) {
  auto c = parse("param p = " + expr_text + "\n");
  EXPECT_TRUE(c->ok()) << c->messages();
  auto params = all_of<ir::AstParam>(c->ast);
  if (params.size() != 1) {
    ADD_FAILURE() << "expected one param, got " << params.size();
    return nullptr;
  }
  return params[0]->value;
}

/// Fully parenthesised form of an AST expression: names, numbers, (a op b), (-a), f(...).
std::string tree(const AstExpr& e) {
  switch (e.kind) {
    case Kind::Number: {
      std::string s = std::to_string(e.number);
      s.erase(s.find_last_not_of('0') + 1);
      if (s.back() == '.') s.pop_back();
      return s;
    }
    case Kind::Name: return e.name;
    case Kind::Unary: return std::string("(") + e.op + tree(*e.args[0]) + ")";
    case Kind::Binary: return "(" + tree(*e.args[0]) + " " + e.op + " " + tree(*e.args[1]) + ")";
    case Kind::Call:
    case Kind::List:
    case Kind::Index: {
      std::string s = e.kind == Kind::Call ? e.name + "(" : e.kind == Kind::List ? "[" : tree(*e.args[0]) + "[";
      for (std::size_t i = e.kind == Kind::Index ? 1 : 0; i < e.args.size(); ++i)
        s += (i > (e.kind == Kind::Index ? 1u : 0u) ? ", " : "") + tree(*e.args[i]);
      return s + (e.kind == Kind::Call ? ")" : "]");
    }
  }
  return "?";
}

std::string tree_of(const std::string& expr_text) {
  auto e = param_expr(expr_text);
  return e ? tree(*e) : "<none>";
}

// ---- statements -------------------------------------------------------------------------

TEST(Parse, StatementKindsInSourceOrder) {
  auto c = parse(
      "model m\n"
      "import \"lib/x.mbg\"\n"
      "param k = 2\n"
      "signal s = t\n"
      "output o = s\n"
      "R r = k\n"
      "1 j : -> r\n"
      "bond j -> r\n"
      "simulate { t_end = 1 }\n"
      "component c(port a) { R q = 1 }\n"
      "instance u = c(a = j)\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& s = c->ast.stmts;
  ASSERT_EQ(s.size(), 11u);
  EXPECT_TRUE(std::holds_alternative<ir::AstModel>(s[0]));
  EXPECT_TRUE(std::holds_alternative<ir::AstImport>(s[1]));
  EXPECT_TRUE(std::holds_alternative<ir::AstParam>(s[2]));
  EXPECT_TRUE(std::holds_alternative<ir::AstSignal>(s[3]));
  EXPECT_TRUE(std::holds_alternative<ir::AstOutput>(s[4]));
  EXPECT_TRUE(std::holds_alternative<ir::AstElement>(s[5]));
  EXPECT_TRUE(std::holds_alternative<ir::AstJunction>(s[6]));
  EXPECT_TRUE(std::holds_alternative<ir::AstBond>(s[7]));
  EXPECT_TRUE(std::holds_alternative<ir::AstSimulate>(s[8]));
  EXPECT_TRUE(std::holds_alternative<std::shared_ptr<ir::AstComponent>>(s[9]));
  EXPECT_TRUE(std::holds_alternative<ir::AstInstance>(s[10]));
  EXPECT_EQ(std::get<ir::AstModel>(s[0]).name, "m");
  EXPECT_EQ(std::get<ir::AstImport>(s[1]).path, "lib/x.mbg");
}

TEST(Parse, SemicolonsAreOptionalBetweenStatements) {
  auto c = parse("param a = 1; param b = 2 param c = 3;;\nparam d = 4");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto params = all_of<ir::AstParam>(c->ast);
  ASSERT_EQ(params.size(), 4u);
  EXPECT_EQ(params[0]->name, "a");
  EXPECT_EQ(params[1]->name, "b");
  EXPECT_EQ(params[2]->name, "c");
  EXPECT_EQ(params[3]->name, "d");
  EXPECT_EQ(params[2]->value->number, 3.0);
}

TEST(Parse, ElementKindsValuesAndAttributes) {
  auto c = parse(
      "C k = 1 / k_s { q0 = 0.1; e0 = 2 }\n"
      "R fr { e = c * f^2 }\n"
      "MGY g = 2\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto els = all_of<ir::AstElement>(c->ast);
  ASSERT_EQ(els.size(), 3u);
  EXPECT_EQ(els[0]->kind, "C");
  EXPECT_EQ(els[0]->name, "k");
  ASSERT_TRUE(els[0]->value);
  EXPECT_EQ(tree(*els[0]->value), "(1 / k_s)");
  ASSERT_EQ(els[0]->attrs.size(), 2u);
  EXPECT_EQ(els[0]->attrs[0].key, "q0");
  EXPECT_EQ(els[0]->attrs[1].key, "e0");
  EXPECT_EQ(els[1]->kind, "R");
  EXPECT_FALSE(els[1]->value);
  ASSERT_EQ(els[1]->attrs.size(), 1u);
  EXPECT_EQ(els[1]->attrs[0].key, "e");
  EXPECT_EQ(tree(*els[1]->attrs[0].value), "(c * (f ^ 2))");
  EXPECT_EQ(els[2]->kind, "MGY");
}

TEST(Parse, JunctionBondListsInputsAndOutputs) {
  auto c = parse("1 loop [2] : a, emf.p2 -> c, m1.d\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto js = all_of<ir::AstJunction>(c->ast);
  ASSERT_EQ(js.size(), 1u);
  const ir::AstJunction& j = *js[0];
  EXPECT_EQ(j.type, '1');
  EXPECT_EQ(j.name, "loop");
  ASSERT_TRUE(j.dim.has_value());
  EXPECT_EQ(*j.dim, 2);
  ASSERT_EQ(j.inputs.size(), 2u);
  EXPECT_EQ(j.inputs[0].path, "a");
  EXPECT_EQ(j.inputs[1].path, "emf.p2");
  ASSERT_EQ(j.outputs.size(), 2u);
  EXPECT_EQ(j.outputs[0].path, "c");
  EXPECT_EQ(j.outputs[1].path, "m1.d");
  // Locations: the dotted endpoint's span covers "emf.p2".
  EXPECT_EQ(j.inputs[1].loc.line, 1);
  EXPECT_EQ(j.inputs[1].loc.col, 17);
  EXPECT_EQ(j.inputs[1].loc.length, 6);
  EXPECT_EQ(j.outputs[1].loc.col, 30);
}

TEST(Parse, JunctionWithOneSidedOrNoBondList) {
  auto c = parse(
      "0 n : -> r2, m\n"
      "1 s : src ->\n"
      "0 x1\n"
      "R r = 1\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto js = all_of<ir::AstJunction>(c->ast);
  ASSERT_EQ(js.size(), 3u);
  EXPECT_EQ(js[0]->type, '0');
  EXPECT_TRUE(js[0]->inputs.empty());
  ASSERT_EQ(js[0]->outputs.size(), 2u);
  EXPECT_EQ(js[0]->outputs[1].path, "m");
  ASSERT_EQ(js[1]->inputs.size(), 1u);
  EXPECT_EQ(js[1]->inputs[0].path, "src");
  EXPECT_TRUE(js[1]->outputs.empty());  // `R r` on the next line is a statement, not an output
  EXPECT_TRUE(js[2]->inputs.empty());
  EXPECT_TRUE(js[2]->outputs.empty());
  EXPECT_FALSE(js[2]->dim.has_value());
  EXPECT_EQ(all_of<ir::AstElement>(c->ast).size(), 1u);
}

TEST(Parse, BondStatementWithNameAndDimension) {
  auto c = parse("bond link: j1 -> lever.p1 [3]\nbond a -> b\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto bs = all_of<ir::AstBond>(c->ast);
  ASSERT_EQ(bs.size(), 2u);
  EXPECT_EQ(bs[0]->name, "link");
  EXPECT_EQ(bs[0]->from.path, "j1");
  EXPECT_EQ(bs[0]->to.path, "lever.p1");
  ASSERT_TRUE(bs[0]->dim.has_value());
  EXPECT_EQ(*bs[0]->dim, 3);
  EXPECT_EQ(bs[0]->loc.line, 1);
  EXPECT_EQ(bs[0]->loc.col, 1);
  EXPECT_EQ(bs[1]->name, "");
  EXPECT_FALSE(bs[1]->dim.has_value());
  EXPECT_EQ(bs[1]->loc.line, 2);
}

TEST(Parse, ComponentInterfaceAndBody) {
  auto c = parse(
      "component rc(port a, param R = 1, param Cc, port b) {\n"
      "  R r = R\n"
      "  C c = Cc\n"
      "  1 j : a -> r, c, b\n"
      "}\n"
      "instance u1 = rc(a = x1, b = x2, Cc = 2 * k)\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(c->ast.stmts.size(), 2u);
  const auto& comp = *std::get<std::shared_ptr<ir::AstComponent>>(c->ast.stmts[0]);
  EXPECT_EQ(comp.name, "rc");
  ASSERT_EQ(comp.ports.size(), 2u);
  EXPECT_EQ(comp.ports[0].path, "a");
  EXPECT_EQ(comp.ports[1].path, "b");
  ASSERT_EQ(comp.params.size(), 2u);
  EXPECT_EQ(comp.params[0].name, "R");
  ASSERT_TRUE(comp.params[0].value);
  EXPECT_EQ(comp.params[0].value->number, 1.0);
  EXPECT_EQ(comp.params[1].name, "Cc");
  EXPECT_FALSE(comp.params[1].value);
  ASSERT_EQ(comp.body.size(), 3u);
  EXPECT_TRUE(std::holds_alternative<ir::AstJunction>(comp.body[2]));
  const auto& in = std::get<ir::AstInstance>(c->ast.stmts[1]);
  EXPECT_EQ(in.name, "u1");
  EXPECT_EQ(in.component, "rc");
  ASSERT_EQ(in.args.size(), 3u);
  EXPECT_EQ(in.args[0].key, "a");
  EXPECT_EQ(in.args[0].value->kind, Kind::Name);
  EXPECT_EQ(in.args[0].value->name, "x1");
  EXPECT_EQ(in.args[2].key, "Cc");
  EXPECT_EQ(tree(*in.args[2].value), "(2 * k)");
}

TEST(Parse, SimulateSettings) {
  auto c = parse("simulate { t_end = 2; interval = 0.01, solver = cvode\n rtol = 1e-10 }\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto sims = all_of<ir::AstSimulate>(c->ast);
  ASSERT_EQ(sims.size(), 1u);
  ASSERT_EQ(sims[0]->settings.size(), 4u);
  EXPECT_EQ(sims[0]->settings[2].key, "solver");
  EXPECT_EQ(sims[0]->settings[2].value->name, "cvode");
  EXPECT_DOUBLE_EQ(sims[0]->settings[3].value->number, 1e-10);
}

// ---- expressions: precedence and associativity ----------------------------------------------

TEST(ParseExpr, SubtractionIsLeftAssociative) { EXPECT_EQ(tree_of("a - b - c"), "((a - b) - c)"); }

TEST(ParseExpr, DivisionAndProductAreLeftAssociative) {
  EXPECT_EQ(tree_of("a / b * c"), "((a / b) * c)");
  EXPECT_EQ(tree_of("a / b / c"), "((a / b) / c)");
}

TEST(ParseExpr, PowerIsRightAssociative) { EXPECT_EQ(tree_of("a^b^c"), "(a ^ (b ^ c))"); }

TEST(ParseExpr, UnaryMinusBindsLooserThanPower) {
  EXPECT_EQ(tree_of("-x^2"), "(-(x ^ 2))");
  EXPECT_EQ(tree_of("2 * -x"), "(2 * (-x))");
}

TEST(ParseExpr, NegativeExponent) { EXPECT_EQ(tree_of("a^-b^2"), "(a ^ (-(b ^ 2)))"); }

TEST(ParseExpr, ProductBindsTighterThanSum) {
  EXPECT_EQ(tree_of("1 + 2 * 3 - 4 / 5"), "((1 + (2 * 3)) - (4 / 5))");
}

TEST(ParseExpr, ParenthesesOverridePrecedence) {
  EXPECT_EQ(tree_of("(a + b) * c"), "((a + b) * c)");
  EXPECT_EQ(tree_of("(a^b)^c"), "((a ^ b) ^ c)");
}

TEST(ParseExpr, CallsDottedNamesIndicesAndLists) {
  EXPECT_EQ(tree_of("atan2(m1.loop.f, v[2]) + M[1, 2]"), "(atan2(m1.loop.f, v[2]) + M[1, 2])");
  EXPECT_EQ(tree_of("[[1, 2], [3, 4]]"), "[[1, 2], [3, 4]]");
  auto e = param_expr("diag(m, m)");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, Kind::Call);
  EXPECT_EQ(e->name, "diag");
  EXPECT_EQ(e->args.size(), 2u);
}

TEST(ParseExpr, NumberSpellings) {
  auto c = parse("param a = 6.5e-3\nparam b = .25\nparam c = 1E+2\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto ps = all_of<ir::AstParam>(c->ast);
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_DOUBLE_EQ(ps[0]->value->number, 6.5e-3);
  EXPECT_DOUBLE_EQ(ps[1]->value->number, 0.25);
  EXPECT_DOUBLE_EQ(ps[2]->value->number, 100.0);
}

TEST(ParseExpr, OperatorLocationIsTheOperatorToken) {
  auto e = param_expr("ab - cd");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->loc.line, 1);
  EXPECT_EQ(e->loc.col, 14);
  EXPECT_EQ(e->args[1]->loc.col, 16);
  EXPECT_EQ(e->args[1]->loc.length, 2);
}

// ---- lexical details ----------------------------------------------------------------------

TEST(Parse, CommentsAreSkippedAndLinesCounted) {
  auto c = parse(
      "// line comment\n"
      "# hash comment\n"
      "/* block\n"
      "   comment */ param a = 1 // trailing\n"
      "param b = 2\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto ps = all_of<ir::AstParam>(c->ast);
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps[0]->loc.line, 4);
  EXPECT_EQ(ps[0]->loc.col, 21);
  EXPECT_EQ(ps[1]->loc.line, 5);
  EXPECT_EQ(ps[1]->loc.col, 7);
}

TEST(Parse, ElementLocationsPointAtNameAndKind) {
  auto c = parse("model m\n  GY  emf = K_m\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto els = all_of<ir::AstElement>(c->ast);
  ASSERT_EQ(els.size(), 1u);
  EXPECT_EQ(els[0]->kind_loc.line, 2);
  EXPECT_EQ(els[0]->kind_loc.col, 3);
  EXPECT_EQ(els[0]->loc.col, 7);
  EXPECT_EQ(els[0]->loc.length, 3);
  EXPECT_EQ(els[0]->value->loc.col, 13);
}

// ---- errors -------------------------------------------------------------------------------

struct Reported {
  int line, col;
  std::string message;
};
std::vector<Reported> errors(const Compiled& c) {
  std::vector<Reported> out;
  for (const ir::Diagnostic& d : c.diags.all())
    if (d.severity == ir::Severity::Error) out.push_back({d.loc.line, d.loc.col, d.message});
  return out;
}

TEST(ParseErrors, TwoErrorsInOneFileAreBothReportedWithLineAndColumn) {
  auto c = parse(
      "model m\n"
      "param a = )\n"
      "Se s = ]\n"
      "R r = 1\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 2u) << c->messages();
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 11);
  EXPECT_EQ(e[0].message, "expected an expression, found `)`");
  EXPECT_EQ(e[1].line, 3);
  EXPECT_EQ(e[1].col, 8);
  EXPECT_EQ(e[1].message, "expected an expression, found `]`");
  // Recovery resumes at the next statement: the good statements survive.
  EXPECT_EQ(all_of<ir::AstModel>(c->ast).size(), 1u);
  auto els = all_of<ir::AstElement>(c->ast);
  ASSERT_EQ(els.size(), 1u);
  EXPECT_EQ(els[0]->name, "r");
}

TEST(ParseErrors, IncompleteExpressionBeforeNextStatement) {
  auto c = parse("model syntax_error\nparam k = 3 *\nR load = k\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].line, 3);
  EXPECT_EQ(e[0].col, 1);
  EXPECT_EQ(e[0].message, "expected an expression, found the start of a statement (`R load`)");
}

TEST(ParseErrors, ErrorsInsideAComponentRecoverInsideIt) {
  auto c = parse(
      "component k(port a) {\n"
      "  R r = *\n"
      "  C c = 1\n"
      "}\n"
      "param z = (\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 2u) << c->messages();
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 9);
  EXPECT_EQ(e[1].line, 6);  // end of file, after the last newline
  ASSERT_EQ(c->ast.stmts.size(), 1u);
  const auto& comp = *std::get<std::shared_ptr<ir::AstComponent>>(c->ast.stmts[0]);
  ASSERT_EQ(comp.body.size(), 1u);
  EXPECT_EQ(std::get<ir::AstElement>(comp.body[0]).name, "c");
}

TEST(ParseErrors, UnknownStatement) {
  auto c = parse("model m\nresistor load = 3\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 1);
  EXPECT_EQ(e[0].message, "unknown statement `resistor`");
}

TEST(ParseErrors, BadCharacterIsReportedOnceWithoutParseNoise) {
  auto c = parse("model bad\nparam k = 3 $ 4\nparam j = ) \n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 13);
  EXPECT_EQ(e[0].message, "unexpected character `$`");
  EXPECT_TRUE(c->ast.stmts.empty());
}

TEST(ParseErrors, MalformedNumber) {
  auto c = parse("param a = 1.2.3\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].col, 11);
  EXPECT_EQ(e[0].message, "malformed number `1.2.3`");
}

TEST(ParseErrors, UnterminatedCommentAndString) {
  auto c = parse("param a = 1\n/* never closed\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].message, "unterminated comment");
  c = parse("import \"lib.mbg\n");
  e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].message, "unterminated string");
}

TEST(ParseErrors, MultibondDimensionMustBePositiveInteger) {
  auto c = parse("bond a -> b [0]\nbond c -> d [2.5]\nbond e -> f [2]\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 2u) << c->messages();
  EXPECT_EQ(e[0].message, "multibond dimension must be a positive integer, not `0`");
  EXPECT_EQ(e[0].line, 1);
  EXPECT_EQ(e[0].col, 14);
  EXPECT_EQ(e[1].message, "multibond dimension must be a positive integer, not `2.5`");
  EXPECT_EQ(e[1].line, 2);
  auto bs = all_of<ir::AstBond>(c->ast);
  ASSERT_EQ(bs.size(), 1u);
  EXPECT_EQ(bs[0]->from.path, "e");
}

TEST(ParseErrors, ComponentInsideComponentIsRejected) {
  auto c = parse("component a(port p) {\n  component b(port q)\n  R r = 1\n}\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 3);
  EXPECT_EQ(e[0].message, "components cannot be declared inside a component");
  ASSERT_EQ(c->ast.stmts.size(), 1u);
  const auto& comp = *std::get<std::shared_ptr<ir::AstComponent>>(c->ast.stmts[0]);
  ASSERT_EQ(comp.body.size(), 1u);
  EXPECT_EQ(std::get<ir::AstElement>(comp.body[0]).name, "r");
}

TEST(ParseErrors, MissingArrowInBondGivesHint) {
  auto c = parse("bond a b\n");
  ASSERT_EQ(c->diags.all().size(), 1u) << c->messages();
  const ir::Diagnostic& d = c->diags.all()[0];
  EXPECT_EQ(d.message, "expected `->` between the bond's ends, found `b`");
  EXPECT_EQ(d.hint, "write bond from -> to (power flows from -> to)");
  EXPECT_EQ(d.loc.col, 8);
}

TEST(ParseErrors, DeeplyNestedExpressionIsAnErrorNotACrash) {
  std::string deep(500, '(');
  auto c = parse("param a = " + deep + "1\n");
  ASSERT_TRUE(c->diags.has_errors());
  EXPECT_EQ(c->diags.all()[0].message, "expression nested too deeply");
}

}  // namespace
