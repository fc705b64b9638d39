// Unit tests for pass 4 (causality/scap): SCAP on textbook graphs — integral
// and derivative causality, propagation through junctions, TF and GY, the
// forced causality of non-square two-ports, resistor choices, the report
// lists and the conflict errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;

std::unique_ptr<Compiled> causality(const std::string& text) { return run(text, Stage::Causality); }

/// Name of the node that computes the effort on bond `number`.
std::string effort_setter(const Compiled& c, int number) {
  const ir::BondGraph& g = c.causal.graph;
  int b = bond_index(g, number);
  if (b < 0) return "<no bond>";
  int s = g.bonds[static_cast<std::size_t>(b)].effort_setter;
  return s < 0 ? "<open>" : g.nodes[static_cast<std::size_t>(s)].name;
}

std::vector<std::string> setters(const Compiled& c) {
  std::vector<std::string> out;
  for (const ir::Bond& b : c.causal.graph.bonds) out.push_back(effort_setter(c, b.number));
  return out;
}

std::vector<int> bond_numbers(const Compiled& c, const std::vector<int>& indices) {
  std::vector<int> out;
  for (int b : indices) out.push_back(c.causal.graph.bonds[static_cast<std::size_t>(b)].number);
  return out;
}

bool log_has(const Compiled& c, const std::string& line) {
  const auto& s = c.causal.report.steps;
  return std::find(s.begin(), s.end(), line) != s.end();
}

const ir::Diagnostic& first_error(const Compiled& c) {
  static const ir::Diagnostic none{};
  for (const ir::Diagnostic& d : c.diags.all())
    if (d.severity == ir::Severity::Error) return d;
  ADD_FAILURE() << "no error reported";
  return none;
}

// ---- storage: integral and derivative causality ------------------------------------------------

TEST(Causality, SeriesRlcHasIntegralCausalityEverywhere) {
  auto c = causality("Se src = 5\nR r = 2\nI l = 0.5\nC c = 0.1\n1 loop : src -> r, l, c\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  // The I sets the loop's flow; every other element gets the flow and computes an effort.
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"src", "r", "loop", "c"}));
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.integral), (std::vector<std::string>{"l", "c"}));
  EXPECT_TRUE(c->causal.report.derivative.empty());
  EXPECT_TRUE(c->causal.report.chosen.empty());
  EXPECT_TRUE(log_has(*c, "bond 3 (loop -> l): effort from `loop` — I `l`: integral causality"));
}

TEST(Causality, TwoInertiasOnOneOneJunctionGiveDerivativeCausality) {
  auto c = causality("Se force = 2\nI mass1 = 1\nI mass2 = 3\n1 v : force -> mass1, mass2\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.integral), (std::vector<std::string>{"mass1"}));
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.derivative), (std::vector<std::string>{"mass2"}));
  // mass2 receives the junction's flow: the junction computes the effort it is given.
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"force", "v", "mass2"}));
  EXPECT_TRUE(log_has(*c, "I `mass2`: derivative causality (forced by the graph)"));
}

TEST(Causality, TwoCapacitorsOnOneZeroJunctionGiveDerivativeCausality) {
  auto c = causality("Sf src = 2\nC c1 = 0.5\nC c2 = 1.5\n0 n : src -> c1, c2\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.integral), (std::vector<std::string>{"c1"}));
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.derivative), (std::vector<std::string>{"c2"}));
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"n", "c1", "n"}));
  EXPECT_TRUE(log_has(*c, "C `c2`: derivative causality (forced by the graph)"));
}

TEST(Causality, FlowSourceForcesAnInertiaIntoDerivativeCausality) {
  auto c = causality("Sf drive = 1\nI m = 2\n1 v : drive -> m\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_TRUE(c->causal.report.integral.empty());
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.derivative), (std::vector<std::string>{"m"}));
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"v", "m"}));
}

TEST(Causality, EffortSourceOnACapacitorForcesDerivativeCausality) {
  auto c = causality("Se v = 1\nC c = 2\nR r = 1\n0 n : v -> c, r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.derivative), (std::vector<std::string>{"c"}));
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"v", "n", "n"}));
}

// ---- two-ports -------------------------------------------------------------------------------

TEST(Causality, TransformerPassesCausalityAndGyratorTurnsIt) {
  auto c = causality(
      "Sf pump = 3\nTF lever = 2\nGY g = 0.5\nI m = 1\nR r = 4\n"
      "1 a : pump -> lever.p1\n"
      "bond lever.p2 -> j\n"
      "0 j : -> g.p1\n"
      "bond g.p2 -> k\n"
      "1 k : -> m, r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  // flow in at p1 of the TF -> flow out at p2 (the TF sets e1, the 0-junction sets e2);
  // flow in at p1 of the GY -> effort out at p2 (the GY sets both efforts).
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"a", "lever", "j", "g", "g", "k", "r"}));
  EXPECT_TRUE(log_has(*c, "bond 3 (lever -> j): effort from `j` — TF `lever` passes causality through"));
  EXPECT_TRUE(log_has(*c, "bond 5 (g -> k): effort from `g` — GY `g` passes causality through"));
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.integral), (std::vector<std::string>{"m"}));
}

TEST(Causality, DcMotorGyratorSetsBothEfforts) {
  auto c = causality(
      "Se supply = 60\nR ra = 0.4\nI la = 0.05\nGY emf = 0.678\nI rotor = 0.57\nR fr = 0.2\n"
      "1 armature : supply -> ra, la, emf\n1 shaft : emf -> rotor, fr\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"supply", "ra", "armature", "emf", "emf", "shaft", "fr"}));
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.integral), (std::vector<std::string>{"la", "rotor"}));
}

TEST(Causality, GearCoupledInertiasGiveDerivativeCausalityThroughTheTransformer) {
  auto c = causality("Se f = 1\nI a = 1\nTF g = 2\nI b = 3\n1 j1 : f -> a, g\n1 j2 : g -> b\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.integral), (std::vector<std::string>{"a"}));
  EXPECT_EQ(names_of_nodes(c->causal.graph, c->causal.report.derivative), (std::vector<std::string>{"b"}));
}

TEST(Causality, NonSquareTransformerHasForcedCausality) {
  auto c = causality(
      "Sf src = [1, 2, 3]\nTF t = [[1, 0, 2], [0, 1, 1]]\nR r = diag(2, 3)\n1 a : src -> t\n1 b : t -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"a", "t", "b", "r"}));
  EXPECT_TRUE(log_has(*c, "bond 2 (a -> t): effort from `t` — forced: non-square TF `t` computes e1 = T^T e2"));
}

TEST(Causality, NonSquareTransformerAgainstAnEffortSourceIsAConflict) {
  auto c = causality(
      "Se src = [1, 2, 3]\nTF t = [[1, 0, 2], [0, 1, 1]]\nR r = diag(2, 3)\n1 a : src -> t\n1 b : t -> r\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "causal conflict at 1-junction `a`: no bond sets its flow");
}

// ---- resistors and arbitrary choices --------------------------------------------------------------

TEST(Causality, OpenResistorIsAChoiceAndClosesAnAlgebraicLoop) {
  auto c = causality(
      "Se src = 10\nR r1 = 1\nR r2 = 2\nR r3 = 3\nC cap = 0.5\n"
      "1 s : src -> r1, n\n0 n : -> r2, m\n1 m : -> r3, cap\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(bond_numbers(*c, c->causal.report.chosen), (std::vector<int>{2}));
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"src", "r1", "s", "n", "n", "m", "cap"}));
  EXPECT_TRUE(log_has(*c, "bond 2 (s -> r1): effort from `r1` — R `r1`: resistance causality (a choice)"));
}

TEST(Causality, ConductanceLawIsChosenInConductanceForm) {
  // As above, but r1's law is written f = phi(e): the choice gives r1 the effort.
  auto c = causality(
      "Se src = 10\nR r1 { f = e / 2 }\nR r2 = 2\nR r3 = 3\nC cap = 0.5\n"
      "1 s : src -> r1, n\n0 n : -> r2, m\n1 m : -> r3, cap\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(effort_setter(*c, 2), "s");
  EXPECT_TRUE(log_has(*c, "bond 2 (s -> r1): effort from `s` — R `r1`: conductance causality (a choice)"));
  // With r1 conducting, r2 is still open and is the second choice.
  EXPECT_EQ(bond_numbers(*c, c->causal.report.chosen), (std::vector<int>{2, 4}));
  EXPECT_EQ(setters(*c), (std::vector<std::string>{"src", "s", "n", "r2", "n", "m", "cap"}));
}

TEST(Causality, ForcedNonlinearResistorIsNotAChoice) {
  auto c = causality("Se src = 1\nC cap = 1\nR g { e = f^3 }\nR h = 2\n1 s : src -> g, n\n0 n : -> cap, h\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  // The capacitor fixes n's effort, so s must give g its effort: g is forced
  // against its law's form (reduce makes that implicit), and nothing was chosen.
  EXPECT_EQ(effort_setter(*c, 2), "s");
  EXPECT_TRUE(c->causal.report.chosen.empty());
}

TEST(Causality, JunctionOnlyLoopIsDecidedArbitrarily) {
  // Two junctions joined twice: after the sources, one of the two parallel bonds is open.
  auto c = causality("Se src = 1\nR r = 1\n1 a : src -> x, y\n0 x\n0 y\n1 b : x, y -> r\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  for (const ir::Bond& b : c->causal.graph.bonds) EXPECT_GE(b.effort_setter, 0) << "bond " << b.number;
  // r is chosen first (step 3), then bond 2 (step 4) settles the junction loop.
  EXPECT_EQ(bond_numbers(*c, c->causal.report.chosen), (std::vector<int>{6, 2}));
  EXPECT_TRUE(log_has(*c, "bond 2 (a -> x): effort from `a` — bond 2: effort from `a` (a choice)"));
}

// ---- conflicts -------------------------------------------------------------------------------------

TEST(CausalityErrors, TwoEffortSourcesOnAZeroJunction) {
  auto c = causality("model m\nSe battery = 12\nSe charger = 14\nR load = 5\n0 bus : battery, charger -> load\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "causal conflict at 0-junction `bus`: bonds 1 and 2 both impose effort on it");
  EXPECT_EQ(d.loc.line, 5);
  EXPECT_EQ(d.loc.col, 3);
  ASSERT_EQ(d.notes.size(), 2u);
  EXPECT_EQ(d.notes[0].second, "bond 1 from `battery`");
  EXPECT_EQ(d.notes[1].second, "bond 2 from `charger`");
  EXPECT_EQ(d.notes[1].first.col, 18);
}

TEST(CausalityErrors, TwoFlowSourcesOnAOneJunction) {
  auto c = causality("Sf pump = 2\nSf fan = 3\nSf aux = 1\nR pipe = 1\n1 j : pump, fan, aux -> pipe\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "causal conflict at 1-junction `j`: bonds 1 and 2 and 3 all impose flow on it");
}

TEST(CausalityErrors, FlowSourcesOnBothSidesOfATransformer) {
  auto c = causality("Sf a = 1\nSf b = 2\nTF t = 2\n1 j1 : a -> t\n1 j2 : b ->\nbond t -> j2\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message.rfind("causal conflict on bond 4 at TF `t`:", 0), 0u) << d.message;
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_EQ(d.notes[0].second, "bond 4 is declared here");
}

TEST(CausalityErrors, NobodySetsTheEffortOfAZeroJunction) {
  auto c = causality("Sf a = 1\nSf b = 2\n0 n : a, b ->\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "causal conflict at 0-junction `n`: no bond sets its effort");
}

}  // namespace
