// Unit tests for pass 5 (equations/generate): one equation per unknown (every
// bond variable computed by exactly one equation), the state equations of
// integral and derivative causality, junction balances with signs, element
// laws in the direction causality gives them, and two-port equations.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;

std::unique_ptr<Compiled> equations(const std::string& text) { return run(text, Stage::Equations); }

/// The equation that computes variable `name`, printed "lhs = rhs" in model names.
std::string equation_for(const Compiled& c, const std::string& name) {
  const ir::BondGraph& g = c.equations.graph;
  int id = var_id(g, name);
  if (id < 0) return "<no variable " + name + ">";
  for (const ir::Equation& e : c.equations.equations)
    if (e.unknown == id) return str(e.lhs, g) + " = " + str(e.rhs, g);
  return "<no equation for " + name + ">";
}

const ir::Equation* find_equation(const Compiled& c, const std::string& name) {
  int id = var_id(c.equations.graph, name);
  for (const ir::Equation& e : c.equations.equations)
    if (e.unknown == id) return &e;
  return nullptr;
}

// ---- one equation per unknown, on a set of models -----------------------------------------------

struct Model {
  const char* name;
  const char* text;
};

std::ostream& operator<<(std::ostream& os, const Model& m) { return os << m.name; }

const Model kModels[] = {
    {"series_rlc", "Se src = 5\nR r = 2\nI l = 0.5\nC c = 0.1\n1 loop : src -> r, l, c\n"},
    {"dc_motor",
     "Se supply = step(0, 60)\nR ra = 0.4\nI la = 0.05\nGY emf = 0.678\nI rotor = 0.57\nR fr = 0.2\n"
     "1 armature : supply -> ra, la, emf\n1 shaft : emf -> rotor, fr\n"},
    {"algebraic_loop",
     "Se src = 10\nR r1 = 1\nR r2 = 2\nR r3 = 3\nC cap = 0.5\n1 s : src -> r1, n\n0 n : -> r2, m\n1 m : -> r3, cap\n"},
    {"two_inertias", "Se force = 2\nI mass1 = 1\nI mass2 = 3\n1 v : force -> mass1, mass2\n"},
    {"two_capacitors", "Sf src = 2\nC c1 = 0.5\nC c2 = 1.5\n0 n : src -> c1, c2\n"},
    {"multibond",
     "param m = 2\nSe gravity = [0, -9.81*m]\nI mass = diag(m, m) { f0 = [1, 0] }\nC spring = diag(0.1, 0.1)\n"
     "R damper = [[0.5, 0.1], [0.1, 0.5]]\n1 v : gravity -> mass, spring, damper\n"},
    {"non_square_tf", "Sf src = [1, 2, 3]\nTF t = [[1, 0, 2], [0, 1, 1]]\nR r = diag(2, 3)\n1 a : src -> t\n1 b : t -> r\n"},
    {"gear", "Se f = 1\nI a = 1\nTF g = 2\nI b = 3\n1 j1 : f -> a, g\n1 j2 : g -> b\n"},
    {"modulated",
     "Se grav = 9.81\nI m { f = p / 2 }\nR drag { e = 0.1 * f * abs(f) }\nsignal theta = t * 0.5\n"
     "MTF arm = cos(theta)\n1 j : grav -> m, drag, arm\n0 n : arm -> c\nC c { e = 100 * q + 10*q^3 }\n"},
    {"nonlinear_dae",
     "Se src = sine(1, 1)\nR diode { e = 0.1*f + f^3 }\nR leak = 10\nC cap = 0.01\n1 s : src -> diode, n\n"
     "0 n : -> leak, cap\n"},
    {"reversed_bonds", "Se src = 10\nR r = 2\nI l = 1\n1 j : src ->\nbond r -> j\nbond l -> j\n"},
};

class EquationsPerModel : public ::testing::TestWithParam<Model> {};

TEST_P(EquationsPerModel, EveryUnknownIsComputedByExactlyOneEquation) {
  auto c = equations(GetParam().text);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::EquationSystem& s = c->equations;
  // Expected unknowns: every bond effort and flow, every integrated state's
  // derivative, every signal, and the state of each derivative-causal storage.
  std::set<int> expected;
  for (const ir::Bond& b : s.graph.bonds) {
    expected.insert(b.effort_vars.begin(), b.effort_vars.end());
    expected.insert(b.flow_vars.begin(), b.flow_vars.end());
  }
  for (const ir::StateVar& st : s.states) expected.insert(st.der);
  for (const ir::Signal& sig : s.graph.signals) expected.insert(sig.var);
  for (int n : s.causality.derivative)
    for (int x : s.graph.nodes[static_cast<std::size_t>(n)].state_vars) expected.insert(x);
  std::map<int, int> count;
  for (const ir::Equation& e : s.equations) ++count[e.unknown];
  std::set<int> computed;
  for (const auto& [v, n] : count) {
    EXPECT_EQ(n, 1) << s.graph.vars[static_cast<std::size_t>(v)].name << " is computed " << n << " times";
    computed.insert(v);
  }
  EXPECT_EQ(computed, expected);
  EXPECT_EQ(s.equations.size(), expected.size());
}

TEST_P(EquationsPerModel, EachEquationMentionsItsUnknownAndNoOtherState) {
  auto c = equations(GetParam().text);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::EquationSystem& s = c->equations;
  for (const ir::Equation& e : s.equations) {
    std::unordered_set<int> vars;
    ir::collect_vars(e.lhs, vars);
    ir::collect_vars(e.rhs, vars);
    EXPECT_TRUE(vars.count(e.unknown)) << e.origin << ": " << str(e.lhs, s.graph) << " = " << str(e.rhs, s.graph);
    EXPECT_TRUE(e.loc.valid()) << e.origin;
    EXPECT_FALSE(e.origin.empty());
  }
}

TEST_P(EquationsPerModel, StatesMatchTheIntegralStorages) {
  auto c = equations(GetParam().text);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::EquationSystem& s = c->equations;
  std::size_t expected = 0;
  for (int n : s.causality.integral) expected += s.graph.nodes[static_cast<std::size_t>(n)].state_vars.size();
  EXPECT_EQ(s.states.size(), expected);
  for (const ir::StateVar& st : s.states) {
    EXPECT_EQ(s.graph.vars[static_cast<std::size_t>(st.var)].kind, ir::VarKind::State);
    EXPECT_EQ(s.graph.vars[static_cast<std::size_t>(st.der)].kind, ir::VarKind::Derivative);
    EXPECT_EQ(s.graph.vars[static_cast<std::size_t>(st.der)].of, st.var);
    EXPECT_EQ(s.graph.vars[static_cast<std::size_t>(st.der)].name,
              "der(" + s.graph.vars[static_cast<std::size_t>(st.var)].name + ")");
    ASSERT_TRUE(st.initial);
  }
}

INSTANTIATE_TEST_SUITE_P(Equations, EquationsPerModel, ::testing::ValuesIn(kModels),
                         [](const ::testing::TestParamInfo<Model>& i) { return std::string(i.param.name); });

// ---- equation content ---------------------------------------------------------------------------

TEST(Equations, SeriesRlcEquations) {
  auto c = equations("Se src = 5\nR r = 2\nI l = 0.5\nC c = 0.1\n1 loop : src -> r, l, c\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(c->equations.equations.size(), 10u);
  EXPECT_EQ(equation_for(*c, "src.e"), "src.e = 5");
  EXPECT_EQ(equation_for(*c, "r.e"), "r.e = 2*r.f");
  EXPECT_EQ(equation_for(*c, "der(l.p)"), "der(l.p) = l.e");
  EXPECT_EQ(equation_for(*c, "l.f"), "l.p = 0.5*l.f");
  EXPECT_EQ(equation_for(*c, "der(c.q)"), "der(c.q) = c.f");
  EXPECT_EQ(equation_for(*c, "c.e"), "c.q = 0.1*c.e");
  EXPECT_EQ(equation_for(*c, "r.f"), "r.f = l.f");
  EXPECT_EQ(equation_for(*c, "l.e"), "src.e = r.e + l.e + c.e");
  const ir::Equation* e = find_equation(*c, "l.e");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->origin, "1 loop: efforts in = efforts out");
  EXPECT_EQ(e->loc.line, 5);
  EXPECT_EQ(e->loc.col, 3);
  ASSERT_EQ(c->equations.states.size(), 2u);
  EXPECT_EQ(c->equations.states[0].node, node_id(c->equations.graph, "l"));
}

TEST(Equations, ZeroJunctionBalanceIsSolvedForTheStrongBondsFlow) {
  auto c = equations("Sf src = 2\nC c = 0.5\nR r = 4\n0 n : src -> c, r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(equation_for(*c, "c.f"), "src.f = c.f + r.f");
  EXPECT_EQ(equation_for(*c, "src.e"), "src.e = c.e");
  EXPECT_EQ(equation_for(*c, "r.e"), "r.e = c.e");
  EXPECT_EQ(equation_for(*c, "r.f"), "r.e = 4*r.f");  // conductance: R's law solved for f later
}

TEST(Equations, ReversedBondsChangeTheSigns) {
  auto c = equations("Se src = 10\nR r = 2\nI l = 1\n1 j : src ->\nbond r -> j\nbond l -> j\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  // Efforts into j: src, r and l (all three bonds point at j).
  EXPECT_EQ(equation_for(*c, "l.e"), "src.e + r.e + l.e = 0");
  // r's and l's own flows are the negated bond flows.
  EXPECT_EQ(equation_for(*c, "r.e"), "r.e = -2*r.f");
  EXPECT_EQ(equation_for(*c, "l.f"), "l.p = -l.f");
  EXPECT_EQ(equation_for(*c, "der(l.p)"), "der(l.p) = l.e");
}

TEST(Equations, DerivativeCausalityGivesDerEquations) {
  auto c = equations("Se force = 2\nI mass1 = 1\nI mass2 = 3\n1 v : force -> mass1, mass2\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::EquationSystem& s = c->equations;
  ASSERT_EQ(s.states.size(), 1u);
  EXPECT_EQ(s.graph.vars[static_cast<std::size_t>(s.states[0].var)].name, "mass1.p");
  int p2 = var_id(s.graph, "mass2.p");
  EXPECT_EQ(s.graph.vars[static_cast<std::size_t>(p2)].kind, ir::VarKind::Auxiliary);
  EXPECT_EQ(equation_for(*c, "mass2.p"), "mass2.p = 3*mass2.f");
  const ir::Equation* e = find_equation(*c, "mass2.e");
  ASSERT_TRUE(e);
  ASSERT_EQ(e->rhs->op, ir::Op::Der);
  EXPECT_EQ(e->rhs->args[0]->id, p2);
  EXPECT_EQ(e->origin, "I mass2: e = der(p) (derivative causality)");
  EXPECT_EQ(var_id(s.graph, "der(mass2.p)"), -1);  // no derivative variable for it
}

TEST(Equations, MultibondStorageRowsAndInitialState) {
  auto c = equations(
      "param m = 2\nSe gravity = [0, -9.81*m]\nI mass = [[m, 1], [0, m]] { f0 = [1, 2] }\n1 v : gravity -> mass\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(equation_for(*c, "mass.f[1]"), "mass.p[1] = m*mass.f[1] + mass.f[2]");
  EXPECT_EQ(equation_for(*c, "mass.f[2]"), "mass.p[2] = m*mass.f[2]");
  EXPECT_EQ(equation_for(*c, "der(mass.p[2])"), "der(mass.p[2]) = mass.e[2]");
  ASSERT_EQ(c->equations.states.size(), 2u);
  Env env;
  env.params = param_values(c->equations.graph);
  EXPECT_EQ(eval(c->equations.states[0].initial, env), 4.0);  // m*1 + 1*2
  EXPECT_EQ(eval(c->equations.states[1].initial, env), 4.0);  // m*2
}

TEST(Equations, NonSquareTransformerEquations) {
  auto c = equations("Sf src = [1, 2, 3]\nTF t = [[1, 0, 2], [0, 1, 1]]\nR r = diag(2, 3)\n1 a : src -> t\n1 b : t -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(equation_for(*c, "t.f2[1]"), "t.f2[1] = t.f1[1] + 2*t.f1[3]");
  EXPECT_EQ(equation_for(*c, "t.f2[2]"), "t.f2[2] = t.f1[2] + t.f1[3]");
  EXPECT_EQ(equation_for(*c, "t.e1[3]"), "t.e1[3] = 2*t.e2[1] + t.e2[2]");
  EXPECT_EQ(equation_for(*c, "t.e1[1]"), "t.e1[1] = t.e2[1]");
}

TEST(Equations, GyratorEquationsFollowItsCausality) {
  auto c = equations(
      "Se supply = 60\nR ra = 0.4\nI la = 0.05\nGY emf = 0.678\nI rotor = 0.57\nR fr = 0.2\n"
      "1 armature : supply -> ra, la, emf\n1 shaft : emf -> rotor, fr\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(equation_for(*c, "emf.e2"), "emf.e2 = 0.678*emf.f1");
  EXPECT_EQ(equation_for(*c, "emf.e1"), "emf.e1 = 0.678*emf.f2");
}

TEST(Equations, ModulatedTransformerAndSignal) {
  auto c = equations("Se g = 1\nI m = 1\nC k = 1\nsignal theta = t * 0.5\nMTF arm = cos(theta)\n"
                     "1 j : g -> m, arm\n0 n : arm -> k\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(equation_for(*c, "theta"), "theta = 0.5*t");
  EXPECT_EQ(equation_for(*c, "arm.f2"), "arm.f2 = cos(theta)*arm.f1");
  EXPECT_EQ(equation_for(*c, "arm.e1"), "arm.e1 = cos(theta)*arm.e2");
}

TEST(Equations, NonlinearLawsKeepTheirWrittenForm) {
  auto c = equations(
      "Se src = 1\nR diode { e = 0.1*f + f^3 }\nR leak = 10\nC cap = 0.01\n1 s : src -> diode, n\n0 n : -> leak, cap\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  // Causality gives the diode its effort; its law e = phi(f) is then implicit in f.
  EXPECT_EQ(equation_for(*c, "diode.f"), "diode.e = 0.1*diode.f + diode.f^3");
  EXPECT_EQ(find_equation(*c, "diode.f")->origin, "R diode: e = law(f), solved for f");
  EXPECT_EQ(equation_for(*c, "leak.f"), "leak.e = 10*leak.f");
}

TEST(Equations, NonlinearStorageInIntegralCausality) {
  auto c = equations("Sf s = 1\nC c { e = 100 * q + 10*q^3 }\nR r = 1\n0 n : s -> c, r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(equation_for(*c, "c.e"), "c.e = 100*c.q + 10*c.q^3");
  EXPECT_EQ(find_equation(*c, "c.e")->origin, "C c: e = law(q)");
}

TEST(EquationErrors, NonlinearStorageInDerivativeCausality) {
  auto c = equations("model m\nSf drive = sin(t)\nI wheel { f = p / 2 + p^3 }\n1 v : drive -> wheel\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = c->diags.all()[0];
  EXPECT_EQ(d.message, "I `wheel` is in derivative causality, but its nonlinear law cannot be inverted");
  EXPECT_EQ(d.loc.line, 3);
  EXPECT_EQ(d.loc.col, 3);
}

}  // namespace
