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
  for (const char* rule : {"model decl", "import", "parameter", "signal", "output", "bond", "simulate", "component", "instance"}) {
    std::smatch m;
    std::regex first(std::string("\\n") + rule + "\\s*=\\s*\"([^\"]+)\"");
    ASSERT_TRUE(std::regex_search(ebnf, m, first)) << rule;
    keywords.insert(m[1]);
  }
  EXPECT_EQ(keywords, mbgc::parse::statement_keywords());
}
