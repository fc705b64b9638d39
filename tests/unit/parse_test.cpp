// Unit tests for pass 1 (parse/): statement kinds, expression precedence and
// associativity, junction and bond syntax, the multibody statements (body,
// ground, joint, gravity, constraints, for loops) and name interpolation,
// source locations, comments, printing round trips, and error reporting and recovery.
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
    case Kind::String: return "\"" + e.name + "\"";
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

// ---- the multibody layer -------------------------------------------------------------------

TEST(Parse, BodyAttributesAndPoints) {
  auto c = parse(
      "body crank {\n"
      "  mass = 2; inertia = diag(1, 2, 3)\n"
      "  com = [0.5, 0, 0], point a = [0, 0, 0]\n"
      "  point tip = [L, 0, 0]\n"
      "}\n"
      "body empty { }\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto bodies = all_of<ir::AstBody>(c->ast);
  ASSERT_EQ(bodies.size(), 2u);
  const ir::AstBody& b = *bodies[0];
  EXPECT_EQ(b.name, "crank");
  EXPECT_EQ(b.kind_loc.line, 1);
  EXPECT_EQ(b.kind_loc.col, 1);
  EXPECT_EQ(b.loc.col, 6);
  EXPECT_EQ(b.loc.length, 5);
  ASSERT_EQ(b.attrs.size(), 3u);
  EXPECT_EQ(b.attrs[0].key, "mass");
  EXPECT_EQ(b.attrs[1].key, "inertia");
  EXPECT_EQ(tree(*b.attrs[1].value), "diag(1, 2, 3)");
  EXPECT_EQ(b.attrs[2].key, "com");
  ASSERT_EQ(b.points.size(), 2u);
  EXPECT_EQ(b.points[0].name, "a");
  EXPECT_EQ(b.points[1].name, "tip");
  EXPECT_EQ(tree(*b.points[1].value), "[L, 0, 0]");
  EXPECT_EQ(b.points[1].loc.line, 4);
  EXPECT_EQ(b.points[1].loc.col, 9);
  EXPECT_EQ(bodies[1]->name, "empty");
  EXPECT_TRUE(bodies[1]->attrs.empty());
  EXPECT_TRUE(bodies[1]->points.empty());
}

TEST(Parse, GroundIsABodyNamedGround) {
  auto c = parse("model m\n  ground { point pivot = [0, 0, 0]; point top = [0, 1, 0]; mass = 1 }\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto bodies = all_of<ir::AstBody>(c->ast);
  ASSERT_EQ(bodies.size(), 1u);
  EXPECT_EQ(bodies[0]->name, "ground");
  EXPECT_EQ(bodies[0]->kind_loc.line, 2);
  EXPECT_EQ(bodies[0]->kind_loc.col, 3);
  EXPECT_EQ(bodies[0]->loc.col, 3);
  ASSERT_EQ(bodies[0]->points.size(), 2u);
  EXPECT_EQ(bodies[0]->points[1].name, "top");
  ASSERT_EQ(bodies[0]->attrs.size(), 1u);  // accepted here, rejected by elaborate
  EXPECT_EQ(bodies[0]->attrs[0].key, "mass");
}

TEST(Parse, JointTypeEndpointsAndSettings) {
  auto c = parse(
      "joint j1 revolute(ground.pivot, crank.a) { axis = [0, 0, 1]; q0 = 0.3 }\n"
      "joint weld fixed(ground, crank)\n"
      "joint j3 anything_goes(a.b, c)\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto js = all_of<ir::AstJoint>(c->ast);
  ASSERT_EQ(js.size(), 3u);
  const ir::AstJoint& j = *js[0];
  EXPECT_EQ(j.name, "j1");
  EXPECT_EQ(j.kind_loc.col, 1);
  EXPECT_EQ(j.loc.col, 7);
  EXPECT_EQ(j.type, "revolute");
  EXPECT_EQ(j.type_loc.col, 10);
  EXPECT_EQ(j.type_loc.length, 8);
  EXPECT_EQ(j.a.path, "ground.pivot");
  EXPECT_EQ(j.a.loc.col, 19);
  EXPECT_EQ(j.a.loc.length, 12);
  EXPECT_EQ(j.b.path, "crank.a");
  ASSERT_EQ(j.attrs.size(), 2u);
  EXPECT_EQ(j.attrs[0].key, "axis");
  EXPECT_EQ(j.attrs[1].key, "q0");
  EXPECT_EQ(js[1]->type, "fixed");
  EXPECT_EQ(js[1]->a.path, "ground");
  EXPECT_EQ(js[1]->b.path, "crank");
  EXPECT_TRUE(js[1]->attrs.empty());
  EXPECT_EQ(js[2]->type, "anything_goes");  // elaborate checks the type
}

TEST(Parse, GravityAndConstraintsSettings) {
  auto c = parse("gravity = [0, -g, 0]\nconstraints = lagrange\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto ss = all_of<ir::AstSetting>(c->ast);
  ASSERT_EQ(ss.size(), 2u);
  EXPECT_EQ(ss[0]->key, "gravity");
  EXPECT_EQ(ss[0]->loc.line, 1);
  EXPECT_EQ(ss[0]->loc.col, 1);
  EXPECT_EQ(ss[0]->loc.length, 7);
  EXPECT_EQ(tree(*ss[0]->value), "[0, (-g), 0]");
  EXPECT_EQ(ss[1]->key, "constraints");
  ASSERT_TRUE(ss[1]->value);
  EXPECT_EQ(ss[1]->value->kind, Kind::Name);
  EXPECT_EQ(ss[1]->value->name, "lagrange");
  EXPECT_EQ(ss[1]->value->loc.line, 2);
  EXPECT_EQ(ss[1]->value->loc.col, 15);
}

TEST(Parse, ConstraintorIsAnElementKind) {
  EXPECT_TRUE(mbgc::parse::element_kinds().count("CN"));
  auto c = parse("CN closure { g = q1 - q2; stiffness = 1e6 }\nCN c2 = 1\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto els = all_of<ir::AstElement>(c->ast);
  ASSERT_EQ(els.size(), 2u);
  EXPECT_EQ(els[0]->kind, "CN");
  EXPECT_EQ(els[0]->name, "closure");
  ASSERT_EQ(els[0]->attrs.size(), 2u);
  EXPECT_EQ(tree(*els[0]->attrs[0].value), "(q1 - q2)");
  EXPECT_EQ(els[1]->kind, "CN");
  ASSERT_TRUE(els[1]->value);
}

TEST(Parse, ForLoopBoundsAndBody) {
  auto c = parse(
      "for i in 1..N {\n"
      "  R r = 1; C k = 2\n"
      "  for j in 2 .. N - 1 { bond a -> b }\n"
      "}\n"
      "for k in -1..2*M { }\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(c->ast.stmts.size(), 2u);
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  EXPECT_EQ(f.var, "i");
  EXPECT_EQ(f.loc.line, 1);
  EXPECT_EQ(f.loc.col, 1);
  EXPECT_EQ(tree(*f.from), "1");
  EXPECT_EQ(tree(*f.to), "N");
  ASSERT_EQ(f.body.size(), 3u);
  EXPECT_TRUE(std::holds_alternative<ir::AstElement>(f.body[0]));
  EXPECT_TRUE(std::holds_alternative<ir::AstElement>(f.body[1]));
  const auto& inner = *std::get<std::shared_ptr<ir::AstFor>>(f.body[2]);
  EXPECT_EQ(inner.var, "j");
  EXPECT_EQ(inner.loc.line, 3);
  EXPECT_EQ(tree(*inner.from), "2");
  EXPECT_EQ(tree(*inner.to), "(N - 1)");
  ASSERT_EQ(inner.body.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<ir::AstBond>(inner.body[0]));
  const auto& g = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[1]);
  EXPECT_EQ(tree(*g.from), "(-1)");
  EXPECT_EQ(tree(*g.to), "(2 * M)");
  EXPECT_TRUE(g.body.empty());
}

TEST(Parse, ForLoopInsideAComponent) {
  auto c = parse("component chain(port a) {\n  for i in 1..3 { R r{i} = i }\n}\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& comp = *std::get<std::shared_ptr<ir::AstComponent>>(c->ast.stmts[0]);
  ASSERT_EQ(comp.body.size(), 1u);
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(comp.body[0]);
  ASSERT_EQ(f.body.size(), 1u);
  EXPECT_EQ(std::get<ir::AstElement>(f.body[0]).name, "r{i}");
}

TEST(Parse, RangeOperatorAndNumbers) {
  // `1..N` is 1 .. N; `1.5..2.5` two numbers; `1.5` alone still a number.
  auto c = parse("for i in 1..N {}\nfor j in 1.5..2.5 {}\nfor k in .5 ..3 {}\nparam p = 1.5\nparam q = 2.\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  EXPECT_EQ(f.from->kind, Kind::Number);
  EXPECT_EQ(f.from->number, 1.0);
  EXPECT_EQ(f.to->kind, Kind::Name);
  EXPECT_EQ(f.to->loc.col, 13);
  const auto& g = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[1]);
  EXPECT_DOUBLE_EQ(g.from->number, 1.5);
  EXPECT_DOUBLE_EQ(g.to->number, 2.5);
  const auto& h = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[2]);
  EXPECT_DOUBLE_EQ(h.from->number, 0.5);
  EXPECT_DOUBLE_EQ(h.to->number, 3.0);
  auto ps = all_of<ir::AstParam>(c->ast);
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_DOUBLE_EQ(ps[0]->value->number, 1.5);
  EXPECT_DOUBLE_EQ(ps[1]->value->number, 2.0);
}

TEST(Parse, MultibodyKeywordsStayUsableAsNames) {
  // Bond-graph models name elements body or gravity; only `body name`,
  // `gravity =`, `ground {`, ... start the new statements.
  auto c = parse(
      "I body = m\n"
      "Se gravity = [0, -9.81]\n"
      "1 v : gravity -> body\n"
      "R r = 1\n"
      "0 w : -> joint, ground, for\n"
      "param x = 2 *\n"
      "  body.f\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto js = all_of<ir::AstJunction>(c->ast);
  ASSERT_EQ(js.size(), 2u);
  ASSERT_EQ(js[0]->inputs.size(), 1u);
  EXPECT_EQ(js[0]->inputs[0].path, "gravity");
  ASSERT_EQ(js[0]->outputs.size(), 1u);  // `R r` on the next line is still a statement
  EXPECT_EQ(js[0]->outputs[0].path, "body");
  ASSERT_EQ(js[1]->outputs.size(), 3u);
  EXPECT_EQ(js[1]->outputs[2].path, "for");
  EXPECT_EQ(all_of<ir::AstElement>(c->ast).size(), 3u);
  auto ps = all_of<ir::AstParam>(c->ast);
  ASSERT_EQ(ps.size(), 1u);
  EXPECT_EQ(tree(*ps[0]->value), "(2 * body.f)");
}

// ---- name interpolation inside for loops ----------------------------------------------------

TEST(ParseInterpolation, NamesEverywhereInsideALoop) {
  auto c = parse(
      "for i in 1..N {\n"
      "  body link{i} { mass = m; point tip{i} = [i, 0, 0] }\n"
      "  joint j{i} revolute(link{i-1}.tip, link{i}) { q0 = q{i} }\n"
      "  R r{i} = k{i} * 2\n"
      "  1 n{i} : a{i}, b.p{i} -> c{i+1}.p1\n"
      "  bond b{i}: x{i} -> y{i}\n"
      "  signal s{i} = sin(j{i}.angle)\n"
      "  output q{i} = j{i}.angle\n"
      "  param k{i} = 2 * i\n"
      "  instance u{i} = comp(port = n{i})\n"
      "}\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  ASSERT_EQ(f.body.size(), 9u);
  const auto& body = std::get<ir::AstBody>(f.body[0]);
  EXPECT_EQ(body.name, "link{i}");
  EXPECT_EQ(body.loc.col, 8);
  EXPECT_EQ(body.loc.length, 7);  // the span covers the interpolation
  ASSERT_EQ(body.points.size(), 1u);
  EXPECT_EQ(body.points[0].name, "tip{i}");
  const auto& joint = std::get<ir::AstJoint>(f.body[1]);
  EXPECT_EQ(joint.name, "j{i}");
  EXPECT_EQ(joint.a.path, "link{i-1}.tip");
  EXPECT_EQ(joint.a.loc.length, 13);
  EXPECT_EQ(joint.b.path, "link{i}");
  EXPECT_EQ(joint.attrs[0].value->name, "q{i}");
  const auto& r = std::get<ir::AstElement>(f.body[2]);
  EXPECT_EQ(r.name, "r{i}");
  EXPECT_EQ(tree(*r.value), "(k{i} * 2)");
  const auto& n = std::get<ir::AstJunction>(f.body[3]);
  EXPECT_EQ(n.name, "n{i}");
  ASSERT_EQ(n.inputs.size(), 2u);
  EXPECT_EQ(n.inputs[0].path, "a{i}");
  EXPECT_EQ(n.inputs[1].path, "b.p{i}");
  ASSERT_EQ(n.outputs.size(), 1u);
  EXPECT_EQ(n.outputs[0].path, "c{i+1}.p1");
  const auto& bond = std::get<ir::AstBond>(f.body[4]);
  EXPECT_EQ(bond.name, "b{i}");
  EXPECT_EQ(bond.from.path, "x{i}");
  EXPECT_EQ(bond.to.path, "y{i}");
  const auto& sig = std::get<ir::AstSignal>(f.body[5]);
  EXPECT_EQ(sig.name, "s{i}");
  EXPECT_EQ(tree(*sig.value), "sin(j{i}.angle)");
  const auto& out = std::get<ir::AstOutput>(f.body[6]);
  EXPECT_EQ(out.name, "q{i}");
  ASSERT_EQ(out.value->kind, Kind::Name);
  EXPECT_EQ(out.value->name, "j{i}.angle");
  EXPECT_EQ(std::get<ir::AstParam>(f.body[7]).name, "k{i}");
  const auto& inst = std::get<ir::AstInstance>(f.body[8]);
  EXPECT_EQ(inst.name, "u{i}");
  EXPECT_EQ(inst.args[0].value->name, "n{i}");
}

TEST(ParseInterpolation, NestedLoopsWhitespaceAndRepeatedInterpolations) {
  auto c = parse(
      "for i in 1..N {\n"
      "  for j in 1..M {\n"
      "    C k{ i }_{j - 1} = 1\n"
      "    0 n{i}{j} : k{i}_{j-1} -> m{ (i - 1) * M + j }\n"
      "    output e{i}{j} = n{i}{j}.e + a{b{i}}\n"
      "  }\n"
      "}\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& outer = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  const auto& inner = *std::get<std::shared_ptr<ir::AstFor>>(outer.body[0]);
  ASSERT_EQ(inner.body.size(), 3u);
  EXPECT_EQ(std::get<ir::AstElement>(inner.body[0]).name, "k{i}_{j-1}");  // whitespace removed
  const auto& n = std::get<ir::AstJunction>(inner.body[1]);
  EXPECT_EQ(n.name, "n{i}{j}");
  EXPECT_EQ(n.inputs[0].path, "k{i}_{j-1}");
  EXPECT_EQ(n.outputs[0].path, "m{(i-1)*M+j}");
  const auto& out = std::get<ir::AstOutput>(inner.body[2]);
  EXPECT_EQ(out.name, "e{i}{j}");
  EXPECT_EQ(tree(*out.value), "(n{i}{j}.e + a{b{i}})");
}

TEST(ParseInterpolation, BraceAfterWhitespaceStillOpensABlock) {
  auto c = parse("for i in 1..N {\n  R fr{i} { e = c{i} * f }\n  body b{i} {mass = 1}\n}\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  const auto& r = std::get<ir::AstElement>(f.body[0]);
  EXPECT_EQ(r.name, "fr{i}");
  ASSERT_EQ(r.attrs.size(), 1u);
  EXPECT_EQ(tree(*r.attrs[0].value), "(c{i} * f)");
  EXPECT_EQ(std::get<ir::AstBody>(f.body[1]).attrs.size(), 1u);
}

TEST(ParseInterpolation, OutsideALoopABraceAfterANameIsABlock) {
  auto c = parse("R fr{ e = f }\nR s{}\nbody b{ point p = [0, 0, 0] }\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto els = all_of<ir::AstElement>(c->ast);
  ASSERT_EQ(els.size(), 2u);
  EXPECT_EQ(els[0]->name, "fr");
  EXPECT_EQ(els[0]->attrs.size(), 1u);
  EXPECT_EQ(all_of<ir::AstBody>(c->ast)[0]->points.size(), 1u);
}

TEST(ParseInterpolation, LoopsOfPointsInsideGroundAndBodyBlocks) {
  auto c = parse(
      "ground { point a = [0, 0, 0]; for i in 1..N { point O{i} = [i, 0, 0] } point b = [1, 1, 0] }\n"
      "for i in 1..N {\n"
      "  body plate{i} {\n"
      "    mass = 1\n"
      "    for k in 1..2 {\n"
      "      point e{k} = [k, 0, 0]\n"
      "      for l in 1..2 { point c{k}_{l} = [k, l, 0] }\n"
      "    }\n"
      "    point p{i} = [0, 0, 0]\n"
      "  }\n"
      "}\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& ground = std::get<ir::AstBody>(c->ast.stmts[0]);
  ASSERT_EQ(ground.points.size(), 2u);
  ASSERT_EQ(ground.loops.size(), 1u);
  EXPECT_EQ(ground.loops[0]->position, 1u);  // between a and b
  EXPECT_EQ(ground.loops[0]->var, "i");
  ASSERT_EQ(ground.loops[0]->points.size(), 1u);
  EXPECT_EQ(ground.loops[0]->points[0].name, "O{i}");  // a loop inside ground interpolates
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[1]);
  const auto& plate = std::get<ir::AstBody>(f.body[0]);
  ASSERT_EQ(plate.attrs.size(), 1u);
  ASSERT_EQ(plate.points.size(), 1u);
  EXPECT_EQ(plate.points[0].name, "p{i}");
  ASSERT_EQ(plate.loops.size(), 1u);
  EXPECT_EQ(plate.loops[0]->position, 0u);
  const auto& k = *plate.loops[0];
  ASSERT_EQ(k.points.size(), 1u);
  ASSERT_EQ(k.loops.size(), 1u);
  EXPECT_EQ(k.loops[0]->position, 1u);
  EXPECT_EQ(k.loops[0]->points[0].name, "c{k}_{l}");
  const std::string printed = ir::print_ast(c->ast);
  EXPECT_EQ(printed,
            "ground { point a = [0, 0, 0]; for i in 1..N { point O{i} = [i, 0, 0] }; point b = [1, 1, 0] }\n"
            "for i in 1..N {\n"
            "  body plate{i} { mass = 1; for k in 1..2 { point e{k} = [k, 0, 0]; for l in 1..2 { point c{k}_{l} = [k, l, "
            "0] } }; point p{i} = [0, 0, 0] }\n"
            "}\n");
  auto again = parse(printed);
  ASSERT_TRUE(again->ok()) << again->messages() << printed;
  EXPECT_EQ(ir::print_ast(again->ast), printed);
}

// ---- printing ------------------------------------------------------------------------------

TEST(Parse, MultibodyRoundTripThroughPrintAst) {
  const std::string text =
      "model chain\n"
      "param N = 3\n"
      "gravity = [0, -9.81, 0]\n"
      "constraints = lagrange\n"
      "ground { point pivot = [0, 0, 0] }\n"
      "for i in 1..N {\n"
      "  body link{i} { mass = 1; point tip = [1, 0, 0] }\n"
      "  for j in 1..i - 1 {\n"
      "    joint j{i}_{j} spherical(link{ i - 1 }.tip, link{i}) { q0 = 0.1 * j }\n"
      "  }\n"
      "  output q{i} = j{i}.angle\n"
      "}\n"
      "CN c { g = q }\n";
  auto c = parse(text);
  ASSERT_TRUE(c->ok()) << c->messages();
  const std::string printed = ir::print_ast(c->ast);
  EXPECT_EQ(printed,
            "model chain\n"
            "param N = 3\n"
            "gravity = [0, (-9.81), 0]\n"
            "constraints = lagrange\n"
            "ground { point pivot = [0, 0, 0] }\n"
            "for i in 1..N {\n"
            "  body link{i} { mass = 1; point tip = [1, 0, 0] }\n"
            "  for j in 1..(i - 1) {\n"
            "    joint j{i}_{j} spherical(link{i-1}.tip, link{i}) { q0 = (0.1 * j) }\n"
            "  }\n"
            "  output q{i} = j{i}.angle\n"
            "}\n"
            "CN c { g = q }\n");
  auto again = parse(printed);
  ASSERT_TRUE(again->ok()) << again->messages() << printed;
  EXPECT_EQ(ir::print_ast(again->ast), printed);
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

std::vector<std::string> error_messages(const Compiled& c) {
  std::vector<std::string> out;
  for (const Reported& r : errors(c)) out.push_back(r.message);
  return out;
}

TEST(ParseErrors, JointNeedsTwoParenthesisedEndpoints) {
  auto c = parse("joint j1 revolute\nR r = 1\njoint j2 revolute(ground.pivot)\njoint j3 revolute(a, b, c)\nC k = 1\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 3u) << c->messages();
  EXPECT_EQ(e[0].message, "expected `(` after the joint's type `revolute`, found `R`");
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[1].message, "expected `,` between the joint's two endpoints, found `)`");
  EXPECT_EQ(e[1].line, 3);
  EXPECT_EQ(e[1].col, 31);
  EXPECT_EQ(e[2].message, "expected `)` after the joint's endpoints, found `,`");
  EXPECT_EQ(c->diags.all()[0].hint, "write joint name revolute(body_a.point, body_b.point)");
  EXPECT_EQ(all_of<ir::AstElement>(c->ast).size(), 2u);  // recovery keeps the statements between
}

TEST(ParseErrors, ForLoopHeader) {
  auto c = parse(
      "for i 1..3 { R a{i} = 1 }\n"
      "for i in 1 3 { R b{i} = 1 }\n"
      "for in 1..3 { }\n"
      "for i in 1..3\n"
      "R ok = 1\n");
  EXPECT_EQ(error_messages(*c), (std::vector<std::string>{
                                    "expected `in` after the loop variable, found number `1`",
                                    "expected `..` between the loop's bounds, found number `3`",
                                    "expected `in` after the loop variable, found number `1`",
                                    "expected `{` to open the loop's body, found `R`",
                                }))
      << c->messages();
  EXPECT_EQ(c->diags.all()[0].hint, "write for i in 1..N { ... }");
  auto els = all_of<ir::AstElement>(c->ast);
  ASSERT_EQ(els.size(), 1u);  // the failed loops' bodies are skipped whole
  EXPECT_EQ(els[0]->name, "ok");
}

TEST(ParseErrors, StatementsThatCannotBeRepeatedInALoop) {
  auto c = parse(
      "for i in 1..3 {\n"
      "  model inner\n"
      "  import \"x.mbg\"\n"
      "  component k(port a) { R r = 1 }\n"
      "  simulate { t_end = 1 }\n"
      "  R r{i} = 1\n"
      "}\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 4u) << c->messages();
  EXPECT_EQ(e[0].message, "`model` cannot appear inside a for loop");
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 3);
  EXPECT_EQ(e[1].message, "`import` cannot appear inside a for loop");
  EXPECT_EQ(e[2].message, "`component` cannot appear inside a for loop");
  EXPECT_EQ(e[3].message, "`simulate` cannot appear inside a for loop");
  ASSERT_EQ(c->ast.stmts.size(), 1u);
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  ASSERT_EQ(f.body.size(), 1u);
  EXPECT_EQ(std::get<ir::AstElement>(f.body[0]).name, "r{i}");
}

TEST(ParseErrors, ErrorsInsideALoopRecoverInsideIt) {
  auto c = parse(
      "for i in 1..3 {\n"
      "  R r{i} = *\n"
      "  body b{i} { mass = }\n"
      "  C c{i} = 1\n"
      "}\n"
      "R after = 1\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 2u) << c->messages();
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[1].line, 3);
  ASSERT_EQ(c->ast.stmts.size(), 2u);
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  ASSERT_EQ(f.body.size(), 1u);
  EXPECT_EQ(std::get<ir::AstElement>(f.body[0]).name, "c{i}");
  EXPECT_EQ(std::get<ir::AstElement>(c->ast.stmts[1]).name, "after");
}

TEST(ParseErrors, UnbalancedInterpolation) {
  auto c = parse(
      "for i in 1..3 {\n"
      "  body link{i { mass = 1 }\n"
      "  output q{i = 1\n"
      "  R fr{ e = f }\n"
      "  R ok{i} = 1\n"
      "}\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 3u) << c->messages();  // one per line: recovery stays inside the loop
  EXPECT_EQ(e[0].message, "expected `}` to close the interpolation in `link{i`, found `{`");
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 15);
  EXPECT_EQ(e[1].message, "expected `}` to close the interpolation in `q{i`, found `=`");
  EXPECT_EQ(e[2].message, "expected `}` to close the interpolation in `fr{e`, found `=`");
  EXPECT_EQ(c->diags.all()[2].hint,
            "an interpolated name is written name{expression}, e.g. link{i-1}; to open a block instead, put a space "
            "before `{`");
  const auto& f = *std::get<std::shared_ptr<ir::AstFor>>(c->ast.stmts[0]);
  ASSERT_EQ(f.body.size(), 1u);
  EXPECT_EQ(std::get<ir::AstElement>(f.body[0]).name, "ok{i}");
}

TEST(ParseErrors, EmptyInterpolationAndInterpolationOutsideALoop) {
  auto c = parse("for i in 1..3 {\n  R r{} = 1\n}\noutput q{1} = 2\nR ok = 1\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 2u) << c->messages();
  EXPECT_EQ(e[0].message, "empty interpolation in `r{}`");
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(e[0].col, 6);
  EXPECT_EQ(e[1].message, "a name can interpolate `q{...}` only inside a for loop");
  EXPECT_EQ(e[1].line, 4);
  EXPECT_EQ(e[1].col, 9);
  EXPECT_EQ(all_of<ir::AstElement>(c->ast).size(), 1u);
}

TEST(ParseErrors, PointOutsideABody) {
  auto c = parse("point p = [0, 0, 0]\nR r = 1\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].message, "`point` belongs inside a body or ground block");
  EXPECT_EQ(e[0].col, 1);
  EXPECT_EQ(all_of<ir::AstElement>(c->ast).size(), 1u);
}

TEST(ParseErrors, BodyBlockErrors) {
  auto c = parse(
      "body ground { mass = 1 }\n"
      "body a { mass = 1\n"
      "joint j revolute(a, b)\n"
      "ground { point = 1 }\n"
      "body c { point p [0, 0, 0] }\n");
  EXPECT_EQ(error_messages(*c), (std::vector<std::string>{
                                    "`ground` is the fixed frame, not a body",
                                    "missing `}` at the end of body `a`",
                                    "expected `=` after the point's name, found `[`",
                                }))
      << c->messages();
  // `point = 1` is an attribute named point (elaborate rejects it); the joint survives.
  EXPECT_EQ(all_of<ir::AstJoint>(c->ast).size(), 1u);
  auto bodies = all_of<ir::AstBody>(c->ast);
  ASSERT_EQ(bodies.size(), 1u);
  EXPECT_EQ(bodies[0]->attrs[0].key, "point");
}

TEST(ParseErrors, SettingsNeedTheirValue) {
  auto c = parse("constraints = 3\ngravity [0, 0]\nR r = 1\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();  // `gravity [` is not a statement's shape: skipped in recovery
  EXPECT_EQ(e[0].message, "expected a name (the constraint method), found number `3`");
  EXPECT_EQ(c->diags.all()[0].hint, "write constraints = lagrange or constraints = penalty");
  c = parse("gravity\nR r = 1\n");
  e = errors(*c);
  ASSERT_EQ(e.size(), 1u) << c->messages();
  EXPECT_EQ(e[0].message, "expected `=` after `gravity`, found `R`");
  EXPECT_EQ(e[0].line, 2);
  EXPECT_EQ(all_of<ir::AstElement>(c->ast).size(), 1u);
}

TEST(ParseErrors, UnclosedLoopsAreEachReported) {
  auto c = parse("for i in 1..3 {\n  for j in 1..3 {\n    R r{i}{j} = 1\n");
  EXPECT_EQ(error_messages(*c), (std::vector<std::string>{
                                    "missing `}` at the end of the for loop over `j`",
                                    "missing `}` at the end of the for loop over `i`",
                                }))
      << c->messages();
}

TEST(ParseErrors, DeeplyNestedLoopsAreAnErrorNotACrash) {
  std::string text;
  for (int k = 0; k < 2000; ++k) text += "for i in 1..2 {\n";
  auto c = parse(text);
  ASSERT_TRUE(c->diags.has_errors());
  EXPECT_EQ(c->diags.all()[0].message, "for loops nested more than 64 deep");
}

TEST(ParseErrors, DeeplyNestedExpressionIsAnErrorNotACrash) {
  std::string deep(500, '(');
  auto c = parse("param a = " + deep + "1\n");
  ASSERT_TRUE(c->diags.has_errors());
  EXPECT_EQ(c->diags.all()[0].message, "expression nested too deeply");
}

}  // namespace

TEST(ParseErrors, ALoopInsideABlockRepeatsPointsOnly) {
  auto c = parse(
      "body b { for k in 1..2 { mass = 1 } }\n"
      "ground { for i in 1..2 { point g{i} = [i, 0, 0]\n"
      "joint j revolute(ground, b)\n");
  auto e = errors(*c);
  ASSERT_EQ(e.size(), 2u) << c->messages();
  EXPECT_EQ(e[0].message, "a for loop inside body `b` repeats points only, found the setting `mass`");
  EXPECT_EQ(e[0].line, 1);
  EXPECT_EQ(e[0].col, 26);
  EXPECT_EQ(e[1].message, "a for loop inside `ground` repeats points only, found the statement `joint j`");
  EXPECT_EQ(e[1].line, 3);
  // recovery resumes at the statement: the joint is kept
  EXPECT_EQ(all_of<ir::AstJoint>(c->ast).size(), 1u);
}

// ---- units in braces ----------------------------------------------------------------

TEST(ParseUnits, ALiteralsUnitBringsItsValueToSIAndKeepsWhatWasTyped) {
  auto e = param_expr("30 {deg}");
  ASSERT_TRUE(e && e->unit);
  EXPECT_DOUBLE_EQ(e->number, 30 * 3.14159265358979323846 / 180);
  EXPECT_EQ(e->written, 30);
  EXPECT_EQ(e->unit->unit.text, "deg");
  EXPECT_EQ(e->unit->loc.col, 15);  // `param p = 30 {deg}`: the text inside the braces
  EXPECT_EQ(e->unit->loc.length, 3);
  EXPECT_DOUBLE_EQ(param_expr("3000 {rpm}")->number, 3000 * 2 * 3.14159265358979323846 / 60);
  EXPECT_DOUBLE_EQ(param_expr("36 {km/h}")->number, 10);
  EXPECT_DOUBLE_EQ(param_expr("2 {bar} * 3")->args[0]->number, 2e5);
  EXPECT_DOUBLE_EQ(param_expr("-5 {mm}")->args[0]->number, 5e-3);
  EXPECT_EQ(param_expr("3e4 {N/m}")->number, 3e4);
}

TEST(ParseUnits, ADeclarationsUnitFollowsItsValue) {
  auto c = parse("param k = m*g/x0 {N/m}\nsignal v = 2*x {m/s}\noutput w = j.rate {rad/s}\n"
                 "param m = 2 {kg}\nparam g = 9.81\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto params = all_of<ir::AstParam>(c->ast);
  ASSERT_EQ(params.size(), 3u);
  ASSERT_TRUE(params[0]->unit);
  EXPECT_EQ(params[0]->unit->unit.text, "N/m");
  EXPECT_EQ(tree(*params[0]->value), "((m * g) / x0)");
  EXPECT_FALSE(params[1]->unit);  // the literal's: `2 {kg}`
  EXPECT_TRUE(params[1]->value->unit);
  EXPECT_FALSE(params[2]->unit);
  EXPECT_EQ(all_of<ir::AstSignal>(c->ast)[0]->unit->unit.text, "m/s");
  EXPECT_EQ(all_of<ir::AstOutput>(c->ast)[0]->unit->unit.text, "rad/s");
}

TEST(ParseUnits, BracesThatAreNotAUnitAreWhatTheyWereBefore) {
  // a settings block holds `=`; a loop's bounds are followed by its body
  auto c = parse("C c = 0.1 { q0 = 1 {mm} }\nR r = 10 {Ohm} { }\nfor i in 1..3 { param a{i} = i }\n"
                 "I m = 2 {kg}\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  auto elements = all_of<ir::AstElement>(c->ast);
  ASSERT_EQ(elements.size(), 3u);
  EXPECT_FALSE(elements[0]->value->unit);
  ASSERT_EQ(elements[0]->attrs.size(), 1u);
  EXPECT_DOUBLE_EQ(elements[0]->attrs[0].value->number, 1e-3);
  EXPECT_EQ(elements[1]->value->unit->unit.text, "Ohm");
  EXPECT_EQ(elements[2]->value->unit->unit.text, "kg");
  EXPECT_EQ(all_of<std::shared_ptr<ir::AstFor>>(c->ast).size(), 1u);
}
