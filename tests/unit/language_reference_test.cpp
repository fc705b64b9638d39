// docs/language.md is the language reference: every name the compiler knows
// must appear in it in backticks, so that a new built-in, keyword, setting,
// joint kind or quantity cannot land undocumented. The lists come from the
// compiler's own tables; the quantities, which have no table, from the
// multibody layer's sources (every quantity it defines and every tyre
// signal), so a new one is found there too. Every setting's default value,
// declared in its table, must be the one the reference's row for it states.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "ir/element_settings.hpp"
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

/// What the reference's table rows for setting `name` under the heading that
/// starts with `section` (up to the next heading of level 2 or 3) say of its
/// default, one entry per row: the `default` column's cell, the `required`
/// column's "no (X)", or "(default X)" in any cell, without backticks;
/// empty where the row states none.
std::vector<std::string> documented_defaults(const std::string& section, const std::string& name) {
  std::ifstream in(fs::path(MBGC_SOURCE_DIR) / "docs" / "language.md");
  std::vector<std::string> out;
  auto cells = [](const std::string& row) {
    std::vector<std::string> c;
    std::stringstream s(row.substr(1));
    for (std::string cell; std::getline(s, cell, '|');) c.push_back(std::regex_replace(cell, std::regex("^ +| +$"), ""));
    return c;
  };
  auto plain = [](std::string t) {
    t = std::regex_replace(t, std::regex("`"), "");
    return std::regex_replace(t, std::regex("\xE2\x88\x92"), "-");  // U+2212, the minus sign
  };
  const std::regex default_column("^no \\((.*)\\)$"), in_text("\\(default ([^;)]*)");
  bool inside = false;
  std::vector<std::string> header, previous;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) == 0 || line.rfind("### ", 0) == 0) inside = line.rfind(section, 0) == 0;
    if (!inside || line.rfind("|", 0) != 0) {
      previous.clear();
      continue;
    }
    std::vector<std::string> row = cells(line);
    if (line.rfind("|---", 0) == 0) header = previous;
    previous = row;
    if (row.empty() || header.empty() || line.rfind("|---", 0) == 0) continue;
    bool names = false;
    const std::regex code("`([^`]+)`");
    for (auto it = std::sregex_iterator(row[0].begin(), row[0].end(), code); it != std::sregex_iterator(); ++it)
      names |= (*it)[1] == name;
    if (!names) continue;
    std::string stated;
    std::smatch m;
    const auto column = [&](const char* title) {
      const auto at = std::find(header.begin(), header.end(), title);
      return at == header.end() || static_cast<std::size_t>(at - header.begin()) >= row.size() ? std::string()
                                                                                                 : row[at - header.begin()];
    };
    if (std::string cell = column("default"); !cell.empty()) stated = cell;
    else if (cell = column("required"); std::regex_match(cell, m, default_column)) stated = m[1];
    else if (std::regex_search(line, m, in_text)) stated = m[1];
    out.push_back(plain(stated));
  }
  return out;
}

/// Whether the reference's `stated` default is `value` (as the table writes
/// it): the same text, or the same numbers (2.0e5 and 200000).
bool same_default(const std::string& stated, const std::string& value) {
  namespace mb = mbgc::multibody::detail;
  if (stated == value) return true;
  const std::vector<double> a = mb::defaults_to(stated.c_str()).numbers(), b = mb::defaults_to(value.c_str()).numbers();
  return !a.empty() && a == b;
}

/// Every row of `name` under `section` states `value` as its default, and there is one.
void expect_default_documented(const std::string& section, const std::string& name, const std::string& value) {
  const std::vector<std::string> stated = documented_defaults(section, name);
  EXPECT_FALSE(stated.empty()) << "no row of `" << name << "` in docs/language.md's section " << section;
  for (const std::string& s : stated)
    EXPECT_TRUE(same_default(s, value)) << "docs/language.md " << section << ": `" << name << "` defaults to "
                                        << (s.empty() ? "(nothing stated)" : s) << ", its table to " << value;
}

/// Every setting of `table` declares a default (a value or what stands
/// instead), and the reference states each default value under `section`.
void expect_defaults_documented(const std::vector<const mbgc::multibody::detail::Setting*>& table, const std::string& section) {
  ASSERT_FALSE(table.empty()) << section;
  for (const auto* s : table) {
    EXPECT_TRUE(s->by_default.value || s->by_default.otherwise) << "setting `" << s->name << "` declares no default";
    if (s->by_default.value) expect_default_documented(section, s->name, s->by_default.value);
  }
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
    for (const mb::Setting* s : k->required())  // and a required one has no default value
      EXPECT_EQ(s->by_default.value, nullptr) << kind << " requires `" << s->name << "`, which has a default";
  }
}

TEST(LanguageReference, EveryBodyContactAndTyreSetting) {
  namespace mb = mbgc::multibody::detail;
  expect_documented(mb::setting_names(mb::body_setting::kAll), "body setting");
  expect_documented(mb::contact_setting_names(), "contact setting");
  expect_documented(mb::tyre_setting_names(), "tyre setting");
}

TEST(LanguageReference, EverySettingsDefault) {
  namespace mb = mbgc::multibody::detail;
  expect_defaults_documented(mb::body_setting::kAll, "### 6.1");
  expect_defaults_documented(mb::beam_setting::kAll, "### 6.2");
  expect_defaults_documented(mb::modal_setting::kAll, "### 6.3");
  expect_defaults_documented(mb::joint_setting::kCommon, "### 7.2");
  std::vector<const mb::Setting*> own;  // the kinds' own
  for (const mb::Setting* s : mb::joint_setting::kAll)
    if (std::find(mb::joint_setting::kCommon.begin(), mb::joint_setting::kCommon.end(), s) == mb::joint_setting::kCommon.end())
      own.push_back(s);
  expect_defaults_documented(own, "### 7.3");
  expect_defaults_documented(mb::force_setting::kAll, "### 8.1");
  expect_defaults_documented(mb::contact_setting::kAll, "### 8.2");
  expect_defaults_documented(mb::tyre_setting::kAll, "### 8.3");
  std::size_t coefficients = 0;
  for (const std::string& name : mb::tyre_setting_names())
    if (auto v = mb::tyre_coefficient_default(name)) {
      ++coefficients;
      expect_default_documented("### 8.3", name, fmt::format("{}", *v));
    }
  EXPECT_GT(coefficients, 40u) << "the Magic Formula's coefficients were not found";
  std::size_t cn = 0;
  for (const mbgc::ir::ElementSetting& s : mbgc::ir::element_settings(mbgc::ir::NodeKind::CN))
    if (s.default_value) {
      ++cn;
      expect_default_documented("### 5.2", s.key, fmt::format("{}", *s.default_value));
    }
  EXPECT_EQ(cn, 2u) << "a CN's exponent and stabilisation have defaults";
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
