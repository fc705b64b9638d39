// The grammar in grammar/mbg.ebnf and the parser must agree: every example
// and golden model parses without a diagnostic, and the EBNF's keywords and
// element kinds are exactly the parser's.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "ir/diagnostics.hpp"
#include "parse/parse.hpp"

namespace fs = std::filesystem;

namespace {

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> models() {
  std::vector<fs::path> out;
  for (const char* dir : {"examples", "tests/golden/good"})
    for (const auto& e : fs::recursive_directory_iterator(fs::path(MBGC_SOURCE_DIR) / dir))
      if (e.path().extension() == ".mbg") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

/// The quoted terminals of one EBNF rule, e.g. element kind = "Se" | "Sf" ...
std::set<std::string> terminals_of_rule(const std::string& ebnf, const std::string& rule) {
  std::smatch m;
  std::regex def("\\n" + rule + "\\s*=([^;]*);");
  EXPECT_TRUE(std::regex_search(ebnf, m, def)) << "rule `" << rule << "` not found in mbg.ebnf";
  std::set<std::string> out;
  std::string body = m[1];
  std::regex quoted("\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(body.begin(), body.end(), quoted); it != std::sregex_iterator(); ++it)
    out.insert((*it)[1]);
  return out;
}

}  // namespace

TEST(Grammar, EveryExampleAndGoodModelParses) {
  auto files = models();
  ASSERT_GE(files.size(), 10u);
  for (const fs::path& p : files) {
    mbgc::ir::SourceManager sources;
    mbgc::ir::Diagnostics diags(sources);
    int id = sources.add(p.string(), read(p));
    mbgc::parse::parse_source(sources, id, diags);
    std::ostringstream rendered;
    diags.render(rendered);
    EXPECT_FALSE(diags.has_errors()) << p << "\n" << rendered.str();
  }
}

TEST(Grammar, ElementKindsMatchTheParser) {
  std::string ebnf = read(fs::path(MBGC_SOURCE_DIR) / "grammar" / "mbg.ebnf");
  EXPECT_EQ(terminals_of_rule(ebnf, "element kind"), mbgc::parse::element_kinds());
}

TEST(Grammar, StatementKeywordsMatchTheParser) {
  std::string ebnf = read(fs::path(MBGC_SOURCE_DIR) / "grammar" / "mbg.ebnf");
  // Keywords are the first terminal of each statement rule.
  std::set<std::string> keywords;
  for (const char* rule : {"model decl", "import", "parameter", "signal", "output", "bond", "simulate", "component",
                           "instance", "body", "ground", "joint", "force element", "contact", "tyre", "gravity", "constraints", "for loop",
                           "scene"}) {
    std::smatch m;
    std::regex first(std::string("\\n") + rule + "\\s*=\\s*\"([^\"]+)\"");
    ASSERT_TRUE(std::regex_search(ebnf, m, first)) << rule;
    keywords.insert(m[1]);
  }
  EXPECT_EQ(keywords, mbgc::parse::statement_keywords());
}

TEST(Grammar, ContextualWordsAreNotStatementKeywords) {
  // `point` (inside a body block) and `in` (in a for loop's header) are
  // terminals of the grammar but start no statement, so they stay usable as names.
  std::string ebnf = read(fs::path(MBGC_SOURCE_DIR) / "grammar" / "mbg.ebnf");
  EXPECT_TRUE(terminals_of_rule(ebnf, "body entry").count("point"));
  EXPECT_TRUE(terminals_of_rule(ebnf, "for loop").count("in"));
  EXPECT_TRUE(terminals_of_rule(ebnf, "for loop").count(".."));
  EXPECT_FALSE(mbgc::parse::statement_keywords().count("point"));
  EXPECT_FALSE(mbgc::parse::statement_keywords().count("in"));
}

TEST(Grammar, MultibodyStatementsParse) {
  // One of each multibody form, as the grammar's comments show them.
  const char* text =
      "model chain\n"
      "param N = 3\n"
      "gravity = [0, -9.81, 0]\n"
      "constraints = lagrange\n"
      "ground { point pivot = [0, 0, 0] }\n"
      "for i in 1..N {\n"
      "  body link{i} { mass = 1; inertia = diag(1, 1, 1); com = [0.5, 0, 0]; point base = [0, 0, 0]; point tip = [1, 0, 0] }\n"
      "  output q{i} = j{i}.angle\n"
      "}\n"
      "joint j1 revolute(ground.pivot, link1.base) { axis = [0, 0, 1]; q0 = 0.3 }\n"
      "for i in 2..N { joint j{i} revolute(link{i-1}.tip, link{i}.base) }\n"
      "CN closure { g = 0 }\n";
  mbgc::ir::SourceManager sources;
  mbgc::ir::Diagnostics diags(sources);
  int id = sources.add("chain.mbg", text);
  mbgc::ir::AstProgram p = mbgc::parse::parse_source(sources, id, diags);
  std::ostringstream rendered;
  diags.render(rendered);
  EXPECT_FALSE(diags.has_errors()) << rendered.str();
  EXPECT_EQ(p.stmts.size(), 9u);
}
