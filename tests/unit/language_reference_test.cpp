// docs/language.md is the language reference: every name the compiler knows
// must appear in it in backticks, so that a new built-in, keyword, setting,
// joint kind or quantity cannot land undocumented. The lists come from the
// compiler's own tables; the quantities, which have no table, from the
// multibody layer's sources (every quantity it defines and every tyre
// signal), so a new one is found there too.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "ir/graph.hpp"
#include "ir/value.hpp"
#include "multibody/expander.hpp"
#include "multibody/joint_kind.hpp"
#include "multibody/setting_names.hpp"
#include "parse/parse.hpp"

namespace fs = std::filesystem;

namespace {

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every `...` span of the reference, and each dotted or bracketed part of
/// one (`B.position` documents `position`; `x[1]` documents `x`).
std::set<std::string> documented() {
  std::ifstream in(fs::path(MBGC_SOURCE_DIR) / "docs" / "language.md");
  std::set<std::string> names;
  const std::regex code("`([^`]+)`"), word("[A-Za-z_][A-Za-z_0-9]*");
  bool fenced = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) {  // a fenced example: code, not a reference entry
      fenced = !fenced;
      continue;
    }
    if (fenced) continue;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), code); it != std::sregex_iterator(); ++it) {
      const std::string span = (*it)[1];
      names.insert(span);
      for (auto w = std::sregex_iterator(span.begin(), span.end(), word); w != std::sregex_iterator(); ++w)
        names.insert((*w)[0]);
    }
  }
  return names;
}

template <class Names>
void expect_documented(const Names& names, const char* what, bool may_be_empty = false) {
  static const std::set<std::string> doc = documented();
  ASSERT_GT(doc.size(), 100u) << "docs/language.md is missing or nearly empty";
  std::size_t count = 0;
  for (const auto& entry : names) {
    const std::string name = [&] {
      if constexpr (std::is_convertible_v<decltype(entry), std::string>) return std::string(entry);
      else return std::string(entry.first);
    }();
    ++count;
    EXPECT_TRUE(doc.count(name)) << what << " `" << name << "` is not in docs/language.md (write it in backticks)";
  }
  if (!may_be_empty) {
    EXPECT_GT(count, 0u) << "no " << what << " to check: the list is empty";
  }
}

/// The quantity names the multibody layer defines, in every source: through
/// a symbol's `quantity("NAME")` (define_quantities' `quantity("NAME", value)`)
/// and as `quantities_.define(x.NAME(), value)`, and the tyre's signals
/// (`sig("NAME", ...)`, `sig_vector(B, tn.NAME(), ...)`).
std::set<std::string> quantity_names() {
  std::set<std::string> names;
  const std::regex named(R"re(\bquantity\("([A-Za-z_][A-Za-z_0-9]*)"[,)])re");
  const std::regex member(R"re(quantities_\.define\([A-Za-z_0-9.()]*\.([A-Za-z_][A-Za-z_0-9]*)\(\),)re");
  const std::regex tyre_signal(R"re(\bsig\("([A-Za-z_][A-Za-z_0-9]*)")re");
  const std::regex tyre_vector(R"re(\bsig_vector\(B, *tn\.([A-Za-z_][A-Za-z_0-9]*)\(\))re");
  for (const auto& e : fs::directory_iterator(fs::path(MBGC_SOURCE_DIR) / "compiler" / "multibody")) {
    if (e.path().extension() != ".cpp") continue;
    const std::string text = read(e.path());
    for (const std::regex* r : {&named, &member, &tyre_signal, &tyre_vector})
      for (auto it = std::sregex_iterator(text.begin(), text.end(), *r); it != std::sregex_iterator(); ++it)
        names.insert((*it)[1]);
  }
  return names;
}

TEST(LanguageReference, EveryBuiltInFunction) { expect_documented(mbgc::ir::function_names(), "function"); }

TEST(LanguageReference, EveryStatementKeywordAndElementKind) {
  expect_documented(mbgc::parse::statement_keywords(), "keyword");
  expect_documented(mbgc::parse::element_kinds(), "element kind");
}

TEST(LanguageReference, EveryJointKindAndSetting) {
  namespace mb = mbgc::multibody::detail;
  expect_documented(mb::joint_kind_names(), "joint kind");
  expect_documented(mb::setting_names(mb::joint_setting::kAll), "joint setting");
  for (const std::string& kind : mb::joint_kind_names()) {
    const mb::JointKind* k = mb::find_joint_kind(kind);
    ASSERT_NE(k, nullptr) << kind;
    // fixed: none of its own
    expect_documented(mb::setting_names(k->settings()), (kind + " setting").c_str(), /*may_be_empty=*/true);
    for (const mb::Setting* s : k->settings())  // every kind's setting is one of the table's
      EXPECT_NE(std::find(mb::joint_setting::kAll.begin(), mb::joint_setting::kAll.end(), s),
                mb::joint_setting::kAll.end())
          << kind << ": " << s->name;
  }
}

TEST(LanguageReference, EveryBodyContactAndTyreSetting) {
  namespace mb = mbgc::multibody::detail;
  expect_documented(mb::setting_names(mb::body_setting::kAll), "body setting");
  expect_documented(mb::contact_setting_names(), "contact setting");
  expect_documented(mb::tyre_setting_names(), "tyre setting");
}

TEST(LanguageReference, EverySimulateSetting) {
  std::vector<std::string> names;
  for (const mbgc::ir::SimSetting& s : mbgc::ir::sim_settings()) names.emplace_back(s.name);
  expect_documented(names, "simulate setting");
}

TEST(LanguageReference, EveryQuantity) {
  const std::set<std::string> names = quantity_names();
  // the scrape must find the well-known ones, or it has stopped working
  for (const char* known : {"position", "angular_momentum", "displacement_rate", "Fz", "slip_angle"})
    EXPECT_TRUE(names.count(known)) << "the scrape of compiler/multibody did not find `" << known << "`";
  expect_documented(names, "quantity");
}

}  // namespace
