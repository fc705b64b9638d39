// Unit tests for pass 2 (sema/resolve): parameter ordering and lowering,
// component flattening, instance parameters, port binding, simulate settings,
// imports (through parse::load_program on temporary files) and the errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unordered_set>
#include <vector>

#include <unistd.h>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;
namespace fs = std::filesystem;

std::unique_ptr<Compiled> resolve(const std::string& text) { return run(text, Stage::Resolve); }

std::vector<std::string> param_names(const ir::ResolvedModel& m) {
  std::vector<std::string> out;
  for (const ir::Parameter& p : m.params) out.push_back(p.name);
  return out;
}

/// Numeric value of parameter `name` (its expression evaluated over earlier ones).
double pvalue(const ir::ResolvedModel& m, const std::string& name) {
  auto values = param_values(m.params);
  for (std::size_t i = 0; i < m.params.size(); ++i)
    if (m.params[i].name == name) return values.at(static_cast<int>(i));
  ADD_FAILURE() << "no parameter `" << name << "`";
  return -1e300;
}

int node(const ir::ResolvedModel& m, const std::string& name) {
  auto it = m.node_index.find(name);
  return it == m.node_index.end() ? -1 : it->second;
}

std::string node_name(const ir::ResolvedModel& m, int n) {
  return n < 0 ? "<none>" : m.nodes[static_cast<std::size_t>(n)].name;
}

/// "from -> to" of every bond, with ":p1"/":p2" for two-port sides.
std::vector<std::string> bond_list(const ir::ResolvedModel& m) {
  std::vector<std::string> out;
  auto end = [&](const ir::ResolvedEnd& e) {
    return node_name(m, e.node) + (e.port ? ":p" + std::to_string(e.port) : "");
  };
  for (const ir::ResolvedBond& b : m.bonds) out.push_back(end(b.from) + " -> " + end(b.to));
  return out;
}

const ir::Diagnostic& first_error(const Compiled& c) {
  static const ir::Diagnostic none{};
  for (const ir::Diagnostic& d : c.diags.all())
    if (d.severity == ir::Severity::Error) return d;
  ADD_FAILURE() << "no error reported";
  return none;
}

// ---- parameters --------------------------------------------------------------------------

TEST(Resolve, ForwardReferencedParametersAreOrderedDependenciesFirst) {
  auto c = resolve("param a = b * 2\nparam b = c + 1\nparam c = 3\nparam d = a - c\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(param_names(c->resolved), (std::vector<std::string>{"c", "b", "a", "d"}));
  EXPECT_EQ(pvalue(c->resolved, "a"), 8.0);
  EXPECT_EQ(pvalue(c->resolved, "d"), 5.0);
  // Each parameter refers to the earlier ones by index, not by copy.
  const ir::Parameter& a = c->resolved.params[2];
  std::unordered_set<int> uses;
  ir::collect_params(a.value, uses);
  EXPECT_EQ(uses, (std::unordered_set<int>{1}));  // b
  EXPECT_FALSE(a.literal);
  EXPECT_TRUE(c->resolved.params[0].literal);
  EXPECT_EQ(c->resolved.params[0].literal_value, 3.0);
}

TEST(Resolve, ParameterCycleIsReportedOnceWithTheChain) {
  auto c = resolve("model m\nparam a = 2 * b\nparam b = c + 1\nparam c = a / 3\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "parameter cycle: a -> b -> c -> a");
  EXPECT_EQ(d.loc.line, 2);
  EXPECT_EQ(d.loc.col, 7);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_EQ(d.notes[0].first.line, 4);
  EXPECT_EQ(d.notes[0].first.col, 11);
}

TEST(Resolve, VectorAndMatrixParametersAreFlattenedToScalars) {
  auto c = resolve("param v = [1, 2]\nparam M = [[1, 2], [3, 4]]\nparam s = v[2] + M[2, 1]\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(param_names(c->resolved),
            (std::vector<std::string>{"v[1]", "v[2]", "M[1,1]", "M[1,2]", "M[2,1]", "M[2,2]", "s"}));
  EXPECT_EQ(pvalue(c->resolved, "s"), 5.0);
  const ir::Value& v = c->resolved.param_values.at(static_cast<std::size_t>(c->resolved.param_index.at("v")));
  EXPECT_EQ(v.rows, 2);
  EXPECT_EQ(v.cols, 1);
  EXPECT_EQ(v.items[1]->op, ir::Op::Param);
  EXPECT_EQ(v.items[1]->id, 1);
  const ir::Value& m = c->resolved.param_values.at(static_cast<std::size_t>(c->resolved.param_index.at("M")));
  EXPECT_EQ(m.rows, 2);
  EXPECT_EQ(m.cols, 2);
}

TEST(Resolve, ParameterDependingOnTimeIsAnError) {
  auto c = resolve("param a = 2 * t\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "parameter `a` depends on time");
}

TEST(Resolve, UnknownParameterSuggestsClosestName) {
  auto c = resolve("param R_a = 0.4\nparam k = R_b * 2\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "unknown parameter `R_b`");
  EXPECT_EQ(d.hint, "did you mean `R_a`?");
  EXPECT_EQ(d.loc.line, 2);
  EXPECT_EQ(d.loc.col, 11);
}

TEST(Resolve, ElementIsNotAParameter) {
  auto c = resolve("R load = 2\nparam k = load\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "`load` is not a parameter");
}

// ---- components -----------------------------------------------------------------------------

const char* kComponents =
    "model components\n"
    "component rc(port a, param R = 1, param Cc = 1) {\n"
    "  R r = R\n"
    "  C c = Cc\n"
    "  1 j : a -> r, c\n"
    "}\n"
    "Se src = 1\n"
    "0 bus : src -> x1, x2\n"
    "0 x1\n"
    "0 x2\n"
    "instance u1 = rc(a = x1, R = 2)\n"
    "instance u2 = rc(a = x2, Cc = 3)\n";

TEST(Resolve, ComponentInstancesAreFlattenedIntoDottedNames) {
  auto c = resolve(kComponents);
  ASSERT_TRUE(c->ok()) << c->messages();
  std::vector<std::string> names;
  for (const ir::ResolvedNode& n : c->resolved.nodes) names.push_back(n.name);
  EXPECT_EQ(names, (std::vector<std::string>{"src", "bus", "x1", "x2", "u1.r", "u1.c", "u1.j", "u2.r", "u2.c",
                                             "u2.j"}));
  EXPECT_EQ(c->resolved.nodes[static_cast<std::size_t>(node(c->resolved, "u1.r"))].kind, ir::NodeKind::R);
  EXPECT_EQ(c->resolved.nodes[static_cast<std::size_t>(node(c->resolved, "u2.j"))].kind, ir::NodeKind::One);
  ASSERT_EQ(c->resolved.scopes.size(), 3u);
  EXPECT_EQ(c->resolved.scopes[1].prefix, "u1.");
  EXPECT_EQ(c->resolved.scopes[1].component, "rc");
  // u2's C reads u2's parameter Cc, bound to it
  const ir::TermPtr& cc = c->resolved.nodes[static_cast<std::size_t>(node(c->resolved, "u2.c"))].element->value;
  ASSERT_EQ(cc->kind, ir::Term::Kind::Ref);
  EXPECT_EQ(cc->ref.kind, ir::Ref::Kind::Param);
  EXPECT_EQ(cc->ref.id, c->resolved.param_index.at("u2.Cc"));
  EXPECT_EQ(c->resolved.model_name, "components");
}

TEST(Resolve, InstanceArgumentsOverrideParameterDefaults) {
  auto c = resolve(kComponents);
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(pvalue(c->resolved, "u1.R"), 2.0);
  EXPECT_EQ(pvalue(c->resolved, "u1.Cc"), 1.0);
  EXPECT_EQ(pvalue(c->resolved, "u2.R"), 1.0);
  EXPECT_EQ(pvalue(c->resolved, "u2.Cc"), 3.0);
  EXPECT_EQ(c->resolved.params.size(), 4u);
}

TEST(Resolve, ArgumentsAreEvaluatedInTheCallerAndDefaultsInTheInstance) {
  auto c = resolve(
      "param R = 5\n"
      "component rc(port a, param R = 1, param Cc = 2 * R) {\n"
      "  R r = R\n"
      "  C c = Cc\n"
      "  1 j : a -> r, c\n"
      "}\n"
      "Sf src = 1\n"
      "0 x : src ->\n"
      "instance u1 = rc(a = x, R = R * 2)\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(pvalue(c->resolved, "R"), 5.0);
  EXPECT_EQ(pvalue(c->resolved, "u1.R"), 10.0);   // R * 2 with the caller's R
  EXPECT_EQ(pvalue(c->resolved, "u1.Cc"), 20.0);  // 2 * R with the instance's R
}

TEST(Resolve, PortsBindToTheCallersNodes) {
  auto c = resolve(kComponents);
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(bond_list(c->resolved),
            (std::vector<std::string>{"src -> bus", "bus -> x1", "bus -> x2", "x1 -> u1.j", "u1.j -> u1.r",
                                      "u1.j -> u1.c", "x2 -> u2.j", "u2.j -> u2.r", "u2.j -> u2.c"}));
}

TEST(Resolve, NestedInstancesPassPortsAndParametersThrough) {
  auto c = resolve(
      "component inner(port p, param k = 1) {\n"
      "  R r = k\n"
      "  1 j : p -> r\n"
      "}\n"
      "component outer(port q, param k = 3) {\n"
      "  instance i = inner(p = q, k = k + 1)\n"
      "}\n"
      "Se src = 1\n"
      "0 n : src ->\n"
      "instance o = outer(q = n)\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_GE(node(c->resolved, "o.i.r"), 0);
  EXPECT_GE(node(c->resolved, "o.i.j"), 0);
  EXPECT_EQ(pvalue(c->resolved, "o.k"), 3.0);
  EXPECT_EQ(pvalue(c->resolved, "o.i.k"), 4.0);
  EXPECT_EQ(bond_list(c->resolved), (std::vector<std::string>{"src -> n", "n -> o.i.j", "o.i.j -> o.i.r"}));
}

TEST(Resolve, TwoPortSidesAreBoundByPortName) {
  auto c = resolve(
      "Se src = 1\nTF lever = 2\nR load = 1\n"
      "1 a : src -> lever.p1\n"
      "1 b : -> load\n"
      "bond lever.p2 -> b\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(bond_list(c->resolved),
            (std::vector<std::string>{"src -> a", "a -> lever:p1", "b -> load", "lever:p2 -> b"}));
}

TEST(Resolve, BondEndpointsKeepTheirLocations) {
  auto c = resolve("Se src = 1\nR load = 2\n1 j : src -> load\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(c->resolved.bonds.size(), 2u);
  const ir::ResolvedBond& b = c->resolved.bonds[1];
  EXPECT_EQ(b.to.loc.line, 3);
  EXPECT_EQ(b.to.loc.col, 14);
  EXPECT_EQ(b.loc.col, 14);  // a junction's bond is located at its endpoint
}

// ---- errors in structure ------------------------------------------------------------------

TEST(ResolveErrors, UnconnectedPort) {
  auto c = resolve(
      "component rc(port a, port b, param R = 1) {\n  R r = R\n  1 j : a -> r, b\n}\n"
      "Se src = 1\n0 n : src ->\ninstance u = rc(a = n)\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "port `b` of component `rc` is not connected");
  EXPECT_EQ(d.loc.line, 7);
  EXPECT_EQ(d.loc.col, 10);
}

TEST(ResolveErrors, UnknownComponentSuggestsClosest) {
  auto c = resolve("component rc(port a) {\n  R r = 1\n  1 j : a -> r\n}\n0 n\ninstance u = rcc(a = n)\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "unknown component `rcc`");
  EXPECT_EQ(d.hint, "did you mean `rc`?");
  EXPECT_EQ(d.loc.line, 6);
  EXPECT_EQ(d.loc.col, 14);
}

TEST(ResolveErrors, UnknownInstanceArgument) {
  auto c = resolve("component rc(port a, param R = 1) {\n  R r = R\n  1 j : a -> r\n}\n0 n\n"
                   "instance u = rc(a = n, Rr = 2)\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "component `rc` has no port or parameter `Rr`");
  EXPECT_EQ(d.hint, "did you mean `R`?");
}

TEST(ResolveErrors, ParameterWithoutDefaultMustBeGiven) {
  auto c = resolve("component rc(port a, param R) {\n  R r = R\n  1 j : a -> r\n}\n0 n\ninstance u = rc(a = n)\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "parameter `R` of component `rc` has no default and is not given");
}

TEST(ResolveErrors, ComponentRecursion) {
  auto c = resolve("component loop(port a) {\n  instance inner = loop(a = a)\n}\nSe src = 1\n0 n : src ->\n"
                   "instance l = loop(a = n)\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "component `loop` instantiates itself");
  EXPECT_EQ(d.loc.line, 2);
  EXPECT_EQ(d.loc.col, 20);
}

TEST(ResolveErrors, BondToNowhereSuggestsClosest) {
  auto c = resolve("Se src = 1\nR load = 2\n1 j : src ->\nbond j -> lod\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "bond to nowhere: no element or junction named `lod`");
  EXPECT_EQ(d.hint, "did you mean `load`?");
  EXPECT_EQ(d.loc.line, 4);
  EXPECT_EQ(d.loc.col, 11);
}

TEST(ResolveErrors, DuplicateNameNotesTheFirstDeclaration) {
  auto c = resolve("model m\nSe src = 1\nR src = 2\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "`src` is already declared");
  EXPECT_EQ(d.loc.line, 3);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_EQ(d.notes[0].first.line, 2);
  EXPECT_EQ(d.notes[0].first.col, 4);
}

TEST(ResolveErrors, OnePortHasNoPorts) {
  auto c = resolve("Se src = 1\nR load = 2\n1 j : src -> load.p1\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "`load` has no port `p1`");
}

TEST(ResolveErrors, BondFromANodeToItself) {
  auto c = resolve("0 n\nbond n -> n\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "bond from `n` to itself");
}

// ---- simulate ------------------------------------------------------------------------------

TEST(Resolve, SimulateSettingsAreFoldedToNumbers) {
  auto c = resolve("param k = 2\nsimulate { t_end = 2 * k; interval = 0.01; solver = ida; rtol = 1e-6; atol = 1e-9; step = 1e-3 }\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::SimSettings& s = c->resolved.settings;
  ASSERT_TRUE(s.t_end && s.interval && s.rtol && s.atol && s.step && s.solver);
  EXPECT_EQ(*s.t_end, 4.0);
  EXPECT_EQ(*s.interval, 0.01);
  EXPECT_EQ(*s.solver, "ida");
  EXPECT_EQ(*s.rtol, 1e-6);
  EXPECT_EQ(*s.atol, 1e-9);
  EXPECT_EQ(*s.step, 1e-3);
}

TEST(ResolveErrors, BadSimulateSettings) {
  auto c = resolve("simulate { t_end = -1; solver = leapfrog; tolerance = 1e-6 }\n");
  ASSERT_EQ(c->diags.error_count(), 3) << c->messages();
  std::vector<std::string> msgs;
  for (const ir::Diagnostic& d : c->diags.all()) msgs.push_back(d.message);
  EXPECT_EQ(msgs, (std::vector<std::string>{"unknown solver", "unknown simulation setting `tolerance`",
                                            "`t_end` must be positive"}));
}

TEST(ResolveErrors, SimulateInsideComponent) {
  auto c = resolve("component k(port a) {\n  simulate { t_end = 1 }\n}\n0 n\ninstance u = k(a = n)\n");
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message, "`simulate` belongs at the top level, not inside a component");
}

TEST(Resolve, ModelNameDefaultsToModel) {
  auto c = resolve("param a = 1\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(c->resolved.model_name, "model");
}

// ---- imports (parse::load_program + resolve) -----------------------------------------------

class ResolveImports : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("mbgc_resolve_test_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& rel, const std::string& text) {
    fs::path p = dir_ / rel;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path dir_;
};

const char* kSpringDamper =
    "component spring_damper(port a, param k = 100, param c = 2) {\n"
    "  C spring = 1 / k\n"
    "  R damper = c\n"
    "  1 j : a -> spring, damper\n"
    "}\n";

TEST_F(ResolveImports, ImportedComponentIsUsable) {
  write("lib/spring_damper.mbg", kSpringDamper);
  std::string main = write("main.mbg",
                           "model imports\n"
                           "import \"lib/spring_damper.mbg\"\n"
                           "I mass = 0.5\n"
                           "1 v : -> mass, p\n"
                           "0 p\n"
                           "instance sd = spring_damper(a = p, k = 50)\n");
  auto c = run_file(main, Stage::Resolve);
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(c->sources.count(), 2);
  EXPECT_EQ(fs::path(c->sources.file(1).display_path).lexically_normal(),
            (dir_ / "lib" / "spring_damper.mbg").lexically_normal());
  for (const ir::AstStmt& s : c->ast.stmts) EXPECT_FALSE(std::holds_alternative<ir::AstImport>(s));
  EXPECT_GE(node(c->resolved, "sd.spring"), 0);
  EXPECT_GE(node(c->resolved, "sd.damper"), 0);
  EXPECT_EQ(pvalue(c->resolved, "sd.k"), 50.0);
  EXPECT_EQ(pvalue(c->resolved, "sd.c"), 2.0);
  // Nodes declared in the library keep the library file in their locations.
  EXPECT_EQ(c->resolved.nodes[static_cast<std::size_t>(node(c->resolved, "sd.spring"))].loc.file, 1);
}

TEST_F(ResolveImports, ImportPathsAreRelativeToTheImportingFile) {
  write("lib/common.mbg", kSpringDamper);
  write("lib/wrap.mbg", "import \"common.mbg\"\n");
  std::string main = write("main.mbg", "import \"lib/wrap.mbg\"\n0 p\ninstance sd = spring_damper(a = p)\n");
  auto c = run_file(main, Stage::Resolve);
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(c->sources.count(), 3);
  EXPECT_GE(node(c->resolved, "sd.spring"), 0);
}

TEST_F(ResolveImports, FileImportedTwiceIsReadOnce) {
  write("c.mbg", kSpringDamper);
  write("a.mbg", "import \"c.mbg\"\n");
  write("b.mbg", "import \"c.mbg\"\n");
  std::string main = write("main.mbg", "import \"a.mbg\"\nimport \"b.mbg\"\n0 p\ninstance sd = spring_damper(a = p)\n");
  auto c = run_file(main, Stage::Resolve);
  ASSERT_TRUE(c->ok()) << c->messages();  // no "component declared twice"
  EXPECT_EQ(c->sources.count(), 4);
  EXPECT_EQ(c->resolved.components.size(), 1u);
}

TEST_F(ResolveImports, ImportCycleIsAnError) {
  std::string a = write("a.mbg", "import \"b.mbg\"\nparam x = 1\n");
  write("b.mbg", "param y = 2\nimport \"a.mbg\"\n");
  auto c = run_file(a, Stage::Resolve);
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message.rfind("import cycle: `", 0), 0u) << d.message;
  EXPECT_NE(d.message.find("a.mbg` imports itself"), std::string::npos) << d.message;
  ASSERT_TRUE(d.loc.valid());
  EXPECT_EQ(fs::path(c->sources.file(d.loc.file).display_path).filename(), "b.mbg");
  EXPECT_EQ(d.loc.line, 2);
  EXPECT_EQ(d.loc.col, 8);
}

TEST_F(ResolveImports, FileImportingItselfIsACycle) {
  std::string a = write("self.mbg", "import \"self.mbg\"\n");
  auto c = run_file(a, Stage::Parse);
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  EXPECT_EQ(first_error(*c).message.rfind("import cycle", 0), 0u);
}

TEST_F(ResolveImports, MissingImportIsReportedAtTheImport) {
  std::string main = write("main.mbg", "model m\nimport \"no_such_file.mbg\"\n");
  auto c = run_file(main, Stage::Resolve);
  ASSERT_EQ(c->diags.error_count(), 1) << c->messages();
  const ir::Diagnostic& d = first_error(*c);
  EXPECT_EQ(d.message, "cannot read `" + (dir_ / "no_such_file.mbg").string() + "`");
  EXPECT_EQ(d.hint, "the path is relative to the importing file");
  EXPECT_EQ(d.loc.line, 2);
  EXPECT_EQ(d.loc.col, 8);
}

}  // namespace
