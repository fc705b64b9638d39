// Unit tests for pass 3 (graph/build_graph): bonds on element ports, multibond
// dimension inference (junctions, declared [n], TF/GY matrices), variable
// naming and kinds, sign conventions for reversed bonds, laws, initial values,
// signals, outputs and the structural errors.
#include <gtest/gtest.h>

#include <string>
#include <unordered_set>
#include <vector>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;

std::unique_ptr<Compiled> graph(const std::string& text) { return run(text, Stage::Graph); }

const ir::GraphNode& nd(const Compiled& c, const std::string& name) {
  int n = node_id(c.graph, name);
  if (n < 0) throw std::out_of_range("no node " + name);
  return c.graph.nodes[static_cast<std::size_t>(n)];
}

std::vector<int> bond_dims(const ir::BondGraph& g) {
  std::vector<int> out;
  for (const ir::Bond& b : g.bonds) out.push_back(b.dim);
  return out;
}

const ir::Output& output(const Compiled& c, const std::string& name) {
  for (const ir::Output& o : c.graph.outputs)
    if (o.name == name) return o;
  throw std::out_of_range("no output " + name);
}

const ir::Diagnostic& first_error(const Compiled& c) {
  static const ir::Diagnostic none{};
  for (const ir::Diagnostic& d : c.diags.all())
    if (d.severity == ir::Severity::Error) return d;
  ADD_FAILURE() << "no error reported";
  return none;
}

/// Value of expression e with every variable set from `vars` (by name) and parameters evaluated.
double value_of(const Compiled& c, const ir::Expr& e, const std::map<std::string, double>& vars) {
  Env env;
  env.params = param_values(c.graph);
  for (const auto& [name, v] : vars) env.vars[var_id(c.graph, name)] = v;
  return eval(e, env);
}

// ---- dimensions --------------------------------------------------------------------------

TEST(GraphDims, ElementShapePropagatesThroughJunctions) {
  auto c = graph(
      "Se gravity = [0, -9.81]\n"
      "I mass = diag(2, 2)\n"
      "C spring = diag(0.1, 0.1)\n"
      "R damper = 1\n"
      "1 v : gravity -> mass, w\n"
      "0 w : -> spring, damper\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(bond_dims(c->graph), (std::vector<int>{2, 2, 2, 2, 2}));
  EXPECT_EQ(nd(*c, "damper").dim, 2);  // a scalar R on a 2-bond: R * identity
  EXPECT_EQ(nd(*c, "w").dim, 2);
  EXPECT_EQ(nd(*c, "spring").state_vars.size(), 2u);
}

TEST(GraphDims, DeclaredJunctionDimensionReachesScalarElements) {
  auto c = graph("Sf a = 1\nR r = 2\n1 j [3] : a -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(bond_dims(c->graph), (std::vector<int>{3, 3}));
  EXPECT_EQ(nd(*c, "r").dim, 3);
  EXPECT_GE(var_id(c->graph, "r.f[3]"), 0);
}

TEST(GraphDims, DeclaredBondDimensionConflictIsAnError) {
  auto c = graph("Se f = [1, 2, 3]\nR r = 1\n1 j : f ->\nbond x: j -> r [2]\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message.rfind("multibond dimension mismatch:", 0), 0u) << d.message;
}

TEST(GraphDims, NonSquareTransformerMatrixSetsBothSides) {
  // T is 2 x 3: f2 = T f1, so port p1 carries 3 components and p2 carries 2.
  auto c = graph(
      "Sf src = 1\n"
      "TF t = [[1, 0, 2], [0, 1, 1]]\n"
      "R r = 2\n"
      "1 a : src -> t\n"
      "1 b : t -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(nd(*c, "t").dim, 3);
  EXPECT_EQ(nd(*c, "t").dim2, 2);
  EXPECT_EQ(bond_dims(c->graph), (std::vector<int>{3, 3, 2, 2}));
  EXPECT_EQ(nd(*c, "r").dim, 2);
  EXPECT_EQ(nd(*c, "src").dim, 3);
}

TEST(GraphDims, NonSquareGyratorMatrixSetsBothSides) {
  auto c = graph(
      "Se src = 1\n"
      "GY g = [[1, 2, 3, 4]]\n"
      "R r = 2\n"
      "bond src -> g.p1\n"
      "bond g.p2 -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(nd(*c, "g").dim, 4);
  EXPECT_EQ(nd(*c, "g").dim2, 1);
  EXPECT_EQ(bond_dims(c->graph), (std::vector<int>{4, 1}));
}

TEST(GraphDims, ScalarTransformerKeepsTheDimensionOnBothPorts) {
  auto c = graph(
      "Se src = [1, 2]\n"
      "TF t = 2\n"
      "R r = 3\n"
      "1 a : src -> t\n"
      "1 b : t -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(bond_dims(c->graph), (std::vector<int>{2, 2, 2, 2}));
  EXPECT_EQ(nd(*c, "t").dim, 2);
  EXPECT_EQ(nd(*c, "t").dim2, 2);
}

TEST(GraphDims, TransformerSideConflictIsAnError) {
  auto c = graph(
      "Se src = [1, 2]\n"
      "TF t = [[1, 0, 2], [0, 1, 1]]\n"
      "R r = 2\n"
      "1 a : src -> t\n"
      "1 b : t -> r\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "multibond dimension mismatch: bond 2 at junction `a` needs dimension 3");
}

TEST(GraphDims, JunctionMismatchNamesTheBondAndTheCause) {
  auto c = graph("model dimension_mismatch\nSe force = [1, 2]\nI body = diag(1, 2, 3)\n1 v : force -> body\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "multibond dimension mismatch: bond 2 at junction `v` needs dimension 3");
  EXPECT_EQ(d.loc.line, 4);
  EXPECT_EQ(d.loc.col, 16);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_EQ(d.notes[0].second, "`force` is a 2-vector here");
  EXPECT_EQ(d.notes[0].first.line, 2);
  EXPECT_EQ(d.notes[0].first.col, 4);
}

TEST(GraphDims, NonSquareStorageMatrixIsAnError) {
  auto c = graph("Se f = [1, 2]\nI m = [[1, 2, 3], [4, 5, 6]]\n1 v : f -> m\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "I `m` needs a scalar or a square matrix, not a 2x3 matrix");
}

// ---- variables ------------------------------------------------------------------------------

TEST(GraphVars, BondVariablesAreNamedAfterTheElementTheyFeed) {
  auto c = graph(
      "Se supply = 10\nR r = 1\nI l = 1\nGY emf = 2\nI rotor = 1\n"
      "1 armature : supply -> r, l, emf\n"
      "1 shaft : emf -> link\n"
      "0 link\n"
      "bond named: link -> rotor\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  std::vector<std::string> names;
  for (const ir::Variable& v : c->graph.vars) names.push_back(v.name);
  EXPECT_EQ(names, (std::vector<std::string>{"supply.e", "supply.f", "r.e", "r.f", "l.e", "l.f", "emf.e1",
                                             "emf.f1", "emf.e2", "emf.f2", "b6.e", "b6.f", "named.e", "named.f",
                                             "l.p", "rotor.p"}));
}

TEST(GraphVars, MultibondComponentsAreIndexed) {
  auto c = graph("Se g = [0, -9.81]\nI mass = diag(2, 2)\n1 v : g -> mass\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::Bond& b = c->graph.bonds[1];
  ASSERT_EQ(b.effort_vars.size(), 2u);
  EXPECT_EQ(c->graph.vars[static_cast<std::size_t>(b.effort_vars[1])].name, "mass.e[2]");
  EXPECT_EQ(c->graph.vars[static_cast<std::size_t>(b.flow_vars[0])].name, "mass.f[1]");
  const ir::GraphNode& m = nd(*c, "mass");
  ASSERT_EQ(m.state_vars.size(), 2u);
  EXPECT_EQ(c->graph.vars[static_cast<std::size_t>(m.state_vars[1])].name, "mass.p[2]");
}

TEST(GraphVars, KindsAndOwners) {
  auto c = graph("Se src = 1\nC cap = 2\n0 n : src -> cap\nsignal s = 2 * t\noutput o = s\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const auto& vars = c->graph.vars;
  int e = var_id(c->graph, "cap.e"), f = var_id(c->graph, "cap.f");
  int q = var_id(c->graph, "cap.q"), s = var_id(c->graph, "s");
  ASSERT_TRUE(e >= 0 && f >= 0 && q >= 0 && s >= 0);
  EXPECT_EQ(vars[static_cast<std::size_t>(e)].kind, ir::VarKind::Effort);
  EXPECT_EQ(vars[static_cast<std::size_t>(f)].kind, ir::VarKind::Flow);
  EXPECT_EQ(vars[static_cast<std::size_t>(q)].kind, ir::VarKind::State);
  EXPECT_EQ(vars[static_cast<std::size_t>(s)].kind, ir::VarKind::Signal);
  EXPECT_EQ(vars[static_cast<std::size_t>(e)].of, 1);  // bond index of n -> cap
  EXPECT_EQ(vars[static_cast<std::size_t>(f)].of, 1);
  ASSERT_EQ(c->graph.signals.size(), 1u);
  EXPECT_EQ(c->graph.signals[0].var, s);
  EXPECT_EQ(str(c->graph.signals[0].value, c->graph), "2*t");
  EXPECT_EQ(str(output(*c, "o").value, c->graph), "s");
}

TEST(GraphVars, BondsAreNumberedInDeclarationOrder) {
  auto c = graph("Se src = 1\nR r = 1\n1 j : src -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(c->graph.bonds.size(), 2u);
  EXPECT_EQ(c->graph.bonds[0].number, 1);
  EXPECT_EQ(c->graph.bonds[1].number, 2);
  EXPECT_EQ(c->graph.bonds[0].name, "b1");
  EXPECT_EQ(c->graph.bonds[0].from, node_id(c->graph, "src"));
  EXPECT_EQ(c->graph.bonds[0].to, node_id(c->graph, "j"));
  EXPECT_EQ(nd(*c, "j").bonds, (std::vector<int>{0, 1}));
}

// ---- sign conventions ---------------------------------------------------------------------

TEST(GraphSigns, PassiveElementFlowIsPowerIn) {
  auto c = graph(
      "Se src = 10\nR a = 2\nR b { e = 3 * f }\n"
      "1 j : src -> a\n"
      "bond b -> j\n"  // reversed: power flows out of b
      "output fa = a.f\noutput fb = b.f\noutput eb = b.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  int fa = var_id(c->graph, "a.f"), fb = var_id(c->graph, "b.f"), eb = var_id(c->graph, "b.e");
  const ir::Expr& out_fa = output(*c, "fa").value;
  const ir::Expr& out_fb = output(*c, "fb").value;
  ASSERT_EQ(out_fa->op, ir::Op::Var);
  EXPECT_EQ(out_fa->id, fa);
  ASSERT_EQ(out_fb->op, ir::Op::Neg);
  ASSERT_EQ(out_fb->args[0]->op, ir::Op::Var);
  EXPECT_EQ(out_fb->args[0]->id, fb);
  ASSERT_EQ(output(*c, "eb").value->op, ir::Op::Var);  // efforts keep their sign
  EXPECT_EQ(output(*c, "eb").value->id, eb);
  // Inside the law, f is the element's (power-in) flow too: e = 3 * (-b.f).
  EXPECT_EQ(value_of(*c, nd(*c, "b").law_rhs[0], {{"b.f", 1.0}}), -3.0);
}

TEST(GraphSigns, SourceFlowIsPowerOut) {
  auto c = graph("Sf out = 2\nSf in = 3\nR r = 1\n1 j : out -> r\nbond j -> in\n"
                 "output fo = out.f\noutput fi = in.f\n");
  // Two flow sources on one 1-junction is a causality problem, not a graph one.
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(output(*c, "fo").value->op, ir::Op::Var);
  ASSERT_EQ(output(*c, "fi").value->op, ir::Op::Neg);
  EXPECT_EQ(output(*c, "fi").value->args[0]->id, var_id(c->graph, "in.f"));
}

TEST(GraphSigns, TwoPortFlowsFollowThePortDirection) {
  auto c = graph(
      "Se src = 1\nTF t = 2\nR r = 1\n"
      "0 a : src ->\n"
      "1 b : -> r\n"
      "bond t.p1 -> a\n"  // p1 reversed: power leaves t at p1
      "bond t.p2 -> b\n"  // p2 as usual: power leaves t at p2
      "output f1 = t.f1\noutput f2 = t.f2\noutput e1 = t.e1\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(output(*c, "f1").value->op, ir::Op::Neg);
  EXPECT_EQ(output(*c, "f1").value->args[0]->id, var_id(c->graph, "t.f1"));
  ASSERT_EQ(output(*c, "f2").value->op, ir::Op::Var);
  EXPECT_EQ(output(*c, "f2").value->id, var_id(c->graph, "t.f2"));
  ASSERT_EQ(output(*c, "e1").value->op, ir::Op::Var);
}

TEST(GraphSigns, JunctionQuantitiesAreTheCommonVariable) {
  auto c = graph("Se src = 1\nR r = 1\nR q = 1\n0 n : src -> r, s\n1 s : -> q\noutput en = n.e\noutput fs = s.f\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(str(output(*c, "en").value, c->graph), "src.e");  // n's first bond
  EXPECT_EQ(str(output(*c, "fs").value, c->graph), "b3.f");
  auto bad = graph("Se src = 1\nR r = 1\n1 s : src -> r\noutput es = s.e\n");
  ASSERT_EQ(bad->diags.error_count(), 1) << bad->messages();
  EXPECT_EQ(first_error(*bad).message, "1-junction `s` has no quantity `e`");
}

// ---- laws and initial values ----------------------------------------------------------------

TEST(GraphLaws, LawFormsAndTheirVariables) {
  auto c = graph(
      "Se g = 1\n"
      "I m { f = p / 2 }\n"
      "R drag { e = 0.1 * f * abs(f) }\n"
      "R cond { f = e^3 }\n"
      "C c { e = 100 * q + 10 * q^3 }\n"
      "R lin = 4\n"
      "1 j : g -> m, drag, cond, c, lin\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(nd(*c, "m").law, ir::LawForm::FlowOfState);
  EXPECT_EQ(nd(*c, "drag").law, ir::LawForm::EffortOfFlow);
  EXPECT_EQ(nd(*c, "cond").law, ir::LawForm::FlowOfEffort);
  EXPECT_EQ(nd(*c, "c").law, ir::LawForm::EffortOfState);
  EXPECT_EQ(nd(*c, "lin").law, ir::LawForm::Linear);
  EXPECT_EQ(nd(*c, "g").law, ir::LawForm::Source);
  EXPECT_EQ(str(nd(*c, "m").law_rhs[0], c->graph), "m.p/2");
  EXPECT_EQ(str(nd(*c, "cond").law_rhs[0], c->graph), "cond.e^3");
  EXPECT_EQ(value_of(*c, nd(*c, "drag").law_rhs[0], {{"drag.f", -2.0}}), -0.4);
  EXPECT_EQ(value_of(*c, nd(*c, "c").law_rhs[0], {{"c.q", 2.0}}), 280.0);
  EXPECT_EQ(str(nd(*c, "lin").value.items[0], c->graph), "4");
}

TEST(GraphLaws, InitialStateFromInitialFlowOrEffort) {
  auto c = graph(
      "param m = 2\n"
      "Se g = [0, 1]\n"
      "I mass = diag(m, 3) { f0 = [1, 5] }\n"
      "1 v : g -> mass\n"
      "Sf s = 1\n"
      "C cap = 0.5 { e0 = 4 }\n"
      "I l = 7 { p0 = 3 }\n"
      "0 n : s -> cap, k\n"
      "1 k : -> l\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::Value& im = nd(*c, "mass").initial;
  ASSERT_EQ(im.items.size(), 2u);
  EXPECT_EQ(value_of(*c, im.items[0], {}), 2.0);   // p0 = I f0 = [m*1, 3*5]
  EXPECT_EQ(value_of(*c, im.items[1], {}), 15.0);
  EXPECT_EQ(value_of(*c, nd(*c, "cap").initial.items[0], {}), 2.0);  // q0 = C e0
  EXPECT_EQ(value_of(*c, nd(*c, "l").initial.items[0], {}), 3.0);
}

struct LawError {
  const char* model;
  const char* message;
};

class GraphLawErrors : public ::testing::TestWithParam<LawError> {};

TEST_P(GraphLawErrors, Reported) {
  auto c = graph(GetParam().model);
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, GetParam().message);
}

INSTANTIATE_TEST_SUITE_P(
    Graph, GraphLawErrors,
    ::testing::Values(
        LawError{"Se s = 1\nC c { e = 2 * f }\n0 n : s -> c\n", "the law of `c` must be a function of its state"},
        LawError{"Se s = 1\nR r { e = 2 * e }\n1 j : s -> r\n", "the law `e = ...` of `r` refers to `e` itself"},
        LawError{"Se s = 1\nR r = 1 { e = f }\n1 j : s -> r\n", "R `r` has two constitutive laws"},
        LawError{"Se s = 1\nR r\n1 j : s -> r\n", "R `r` has no value or law"},
        LawError{"Se s = 1\nR r = 2 { law = 3 }\n1 j : s -> r\n", "R `r` has no setting `law`"},
        LawError{"Se src = 1\nI m = 1\nTF lever = cos(m.p)\nR load = 1\n1 a : src -> m, lever\n1 b : lever -> load\n",
                 "the value of TF `lever` must be constant (parameters only)"},
        LawError{"Se s = 1\nI m = 1 + t\n1 j : s -> m\n", "the value of I `m` must be constant (parameters only)"},
        LawError{"Sf s = 1\nC c { e = q; e0 = 1 }\n0 n : s -> c\n", "`e0` needs a linear element"},
        LawError{"Se s = 1\nI m = 2 { f0 = [1, 2] }\n1 j : s -> m\n",
                 "initial value is a 2-vector, but `m` has dimension 1"},
        LawError{"Se s = 1\nR r = 1\n1 j : s -> r\noutput o = r.p\n", "R `r` has no quantity `p`"},
        LawError{"Se s = 1\nR load = 2\n1 j : s -> load\noutput i = lod.f\n", "unknown name `lod.f`"}));

TEST(GraphLaws, ModulatedTransformerMayDependOnTimeAndSignals) {
  auto c = graph("Se g = 1\nI m = 1\nC k = 1\nsignal theta = t * 0.5\nMTF arm = cos(theta)\n"
                 "1 j : g -> m, arm\n0 n : arm -> k\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(str(nd(*c, "arm").value.items[0], c->graph), "cos(theta)");
}

// ---- structure errors --------------------------------------------------------------------------

TEST(GraphErrors, UnconnectedElement) {
  auto c = graph("model m\nSe src = 1\nR load = 2\nC cap = 1\n1 j : src -> load\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "C `cap` is not connected to anything");
  EXPECT_EQ(d.loc.line, 4);
  EXPECT_EQ(d.loc.col, 3);
}

TEST(GraphErrors, OnePortWithTwoBonds) {
  auto c = graph("model m\nSe src = 1\nR load = 2\n1 a : src -> load\n1 b : -> load\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "R `load` already has a bond");
  EXPECT_EQ(d.loc.line, 5);
  EXPECT_EQ(d.loc.col, 10);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_EQ(d.notes[0].first.line, 4);
}

TEST(GraphErrors, TwoPortPortNotConnectedAndJunctionWithoutBonds) {
  auto c = graph("Se src = 1\nTF t = 2\n1 a : src -> t\n0 lonely\n");
  ASSERT_EQ(c->diags.error_count(), 2) << c->messages();
  std::vector<std::string> msgs;
  for (const ir::Diagnostic& d : c->diags.all()) msgs.push_back(d.message);
  EXPECT_EQ(msgs, (std::vector<std::string>{"port p2 of TF `t` is not connected", "0-junction `lonely` has no bonds"}));
}

// ---- outputs ----------------------------------------------------------------------------------

TEST(GraphOutputs, VectorOutputsAreExpandedPerComponent) {
  auto c = graph("Se g = [0, -9.81]\nI mass = diag(2, 2)\n1 v : g -> mass\noutput vel = mass.f\noutput e2 = mass.e[2]\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  std::vector<std::string> names;
  for (const ir::Output& o : c->graph.outputs) names.push_back(o.name);
  EXPECT_EQ(names, (std::vector<std::string>{"vel[1]", "vel[2]", "e2"}));
  EXPECT_EQ(str(c->graph.outputs[1].value, c->graph), "mass.f[2]");
  EXPECT_EQ(str(c->graph.outputs[2].value, c->graph), "mass.e[2]");
}

TEST(GraphOutputs, ComponentScopesResolveLocalNamesFirst) {
  auto c = graph(
      "component rc(port a, param R = 1) {\n  R r = R\n  1 j : a -> r\n  output i = r.f\n}\n"
      "Se src = 1\n0 n : src ->\ninstance u = rc(a = n, R = 4)\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(c->graph.outputs.size(), 1u);
  EXPECT_EQ(c->graph.outputs[0].name, "u.i");
  EXPECT_EQ(str(c->graph.outputs[0].value, c->graph), "u.r.f");
  EXPECT_EQ(str(nd(*c, "u.r").value.items[0], c->graph), "u.R");
}

}  // namespace
