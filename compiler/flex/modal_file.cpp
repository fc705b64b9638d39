// flex/modal_file.cpp — the `.mbm` reader (format: docs/modal_format.md).
#include "flex/modal_file.hpp"

#include "ir/find_file.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <set>
#include <sstream>

namespace mbgc::flex {
namespace {

constexpr int kMaxModes = 64;
const char* kFormatHint = "see docs/modal_format.md for the records of a modal-data file";

struct Token {
  std::string text;
  ir::SourceLoc loc;
};

std::vector<Token> tokenize(const std::string& text, int file) {
  std::vector<Token> out;
  int line = 1, col = 1;
  std::size_t i = 0;
  auto advance = [&] {
    if (text[i] == '\n') ++line, col = 1;
    else ++col;
    ++i;
  };
  while (i < text.size()) {
    char c = text[i];
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') advance();
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      advance();
    } else {
      Token t;
      t.loc = ir::SourceLoc{file, line, col, 1};
      while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])) && text[i] != '#') {
        t.text += text[i];
        advance();
      }
      t.loc.length = static_cast<int>(t.text.size());
      out.push_back(std::move(t));
    }
  }
  return out;
}

class Reader {
 public:
  Reader(std::vector<Token> tokens, int file, ir::Diagnostics& diags) : tokens_(std::move(tokens)), file_(file), diags_(diags) {}

  std::optional<ModalData> run(ModalData data) {
    data_ = std::move(data);
    if (!header()) return std::nullopt;
    while (pos_ < tokens_.size() && ok_) record();
    if (ok_) complete();
    if (!ok_) return std::nullopt;
    return std::move(data_);
  }

 private:
  bool fail(const ir::SourceLoc& at, std::string message, std::string hint = kFormatHint) {
    if (ok_) diags_.error(at, std::move(message), std::move(hint));
    ok_ = false;
    return false;
  }
  ir::SourceLoc end_loc() const { return tokens_.empty() ? ir::SourceLoc{file_, 1, 1, 1} : tokens_.back().loc; }

  std::optional<double> number(const char* what) {
    if (pos_ >= tokens_.size()) {
      fail(end_loc(), fmt::format("the file ends inside {}", what), "a record is its name and then all of its numbers");
      return std::nullopt;
    }
    const Token& t = tokens_[pos_];
    char* end = nullptr;
    double v = std::strtod(t.text.c_str(), &end);
    if (end != t.text.c_str() + t.text.size() || t.text.empty()) {
      fail(t.loc, fmt::format("expected a number in {}, found `{}`", what, t.text),
           "a record is its name and then all of its numbers; is one missing?");
      return std::nullopt;
    }
    if (!std::isfinite(v)) {
      fail(t.loc, fmt::format("`{}` in {} is not a finite number", t.text, what));
      return std::nullopt;
    }
    ++pos_;
    return v;
  }
  /// rows x cols numbers, row by row.
  std::optional<Matrix> matrix(int rows, int cols, const std::string& what) {
    Matrix m(static_cast<std::size_t>(rows), std::vector<double>(static_cast<std::size_t>(cols)));
    for (auto& row : m)
      for (double& x : row) {
        auto v = number(what.c_str());
        if (!v) return std::nullopt;
        x = *v;
      }
    return m;
  }
  std::optional<int> index(const char* what, const Token& record) {
    const std::size_t at = pos_;
    auto v = number(what);
    if (!v) return std::nullopt;
    if (*v < 1 || *v > data_.count || *v != std::floor(*v)) {
      fail(tokens_[at].loc, fmt::format("{} of `{}` is {}, not a mode number 1..{}", what, record.text, tokens_[at].text, data_.count));
      return std::nullopt;
    }
    return static_cast<int>(*v);
  }
  std::optional<std::string> name(const Token& record) {
    if (pos_ >= tokens_.size()) {
      fail(end_loc(), fmt::format("the file ends before the point name of `{}`", record.text));
      return std::nullopt;
    }
    const Token& t = tokens_[pos_];
    bool ident = !t.text.empty() && (std::isalpha(static_cast<unsigned char>(t.text[0])) || t.text[0] == '_');
    for (char c : t.text) ident = ident && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
    if (!ident) {
      fail(t.loc, fmt::format("`{}` is not a point name", t.text), "point names are letters, digits and _, starting with a letter");
      return std::nullopt;
    }
    ++pos_;
    return t.text;
  }

  bool header() {
    if (tokens_.empty() || tokens_[0].text != "mbgc_modal_body")
      return fail(tokens_.empty() ? ir::SourceLoc{file_, 1, 1, 1} : tokens_[0].loc,
                  "a modal-data file starts with `mbgc_modal_body 1`", "is this the right file? " + std::string(kFormatHint));
    ++pos_;
    const std::size_t at = pos_;
    auto version = number("the format version");
    if (!version) return false;
    if (*version != 1) return fail(tokens_[at].loc, fmt::format("format version {} is not known (this mbgc reads version 1)", tokens_[at].text));
    if (pos_ >= tokens_.size() || tokens_[pos_].text != "modes")
      return fail(pos_ < tokens_.size() ? tokens_[pos_].loc : end_loc(), "the second record must be `modes n`",
                  "the number of modes comes first: the sizes of the other records follow from it");
    ++pos_;
    const std::size_t nat = pos_;
    auto n = number("`modes`");
    if (!n) return false;
    if (*n < 1 || *n > kMaxModes || *n != std::floor(*n))
      return fail(tokens_[nat].loc, fmt::format("`modes` is {}, not a whole number 1..{}", tokens_[nat].text, kMaxModes));
    data_.count = static_cast<int>(*n);
    data_.moment_kg_m.assign(static_cast<std::size_t>(data_.count), {});
    data_.product_kg.assign(static_cast<std::size_t>(data_.count), std::vector<Matrix>(static_cast<std::size_t>(data_.count)));
    return true;
  }

  /// Each record once: false (and an error) for a repeat.
  bool first_time(const Token& record, const std::string& key) {
    if (auto [it, fresh] = seen_.emplace(key, record.loc); !fresh)
      return fail(record.loc, fmt::format("`{}` is given twice", key), fmt::format("the first is at line {}", it->second.line));
    return true;
  }

  void record() {
    const Token& r = tokens_[pos_++];
    const int n = data_.count;
    const std::string& k = r.text;
    if (k == "mass") {
      if (!first_time(r, k)) return;
      const std::size_t at = pos_;
      if (auto v = number("`mass`")) {
        data_.mass_kg = *v;
        if (*v <= 0) fail(tokens_[at].loc, fmt::format("the mass is {} kg: it must be positive", tokens_[at].text));
      }
    } else if (k == "first_moment") {
      if (!first_time(r, k)) return;
      if (auto m = matrix(1, 3, "`first_moment`")) data_.first_moment_kg_m = {(*m)[0][0], (*m)[0][1], (*m)[0][2]};
    } else if (k == "inertia") {
      if (!first_time(r, k)) return;
      if (auto m = matrix(3, 3, "`inertia`")) data_.inertia_kg_m2 = symmetric(*m, r, "inertia");
    } else if (k == "mean") {
      if (!first_time(r, k)) return;
      if (auto m = matrix(3, n, fmt::format("`mean` (3 x {})", n))) data_.mean_kg = *m;
    } else if (k == "stiffness") {
      if (!first_time(r, k)) return;
      if (auto m = matrix(n, n, fmt::format("`stiffness` ({} x {})", n, n))) data_.stiffness = symmetric(*m, r, "stiffness");
    } else if (k == "moment") {
      auto i = index("the mode", r);
      if (!i || !first_time(r, fmt::format("moment {}", *i))) return;
      if (auto m = matrix(3, 3, fmt::format("`moment {}`", *i))) data_.moment_kg_m[static_cast<std::size_t>(*i - 1)] = *m;
    } else if (k == "product") {
      auto i = index("the first mode", r);
      if (!i) return;
      const std::size_t at = pos_;
      auto j = index("the second mode", r);
      if (!j) return;
      if (*j < *i) {
        fail(tokens_[at].loc, fmt::format("`product {} {}`: give the pair with k <= l (`product {} {}`, the transpose)", *i, *j, *j, *i));
        return;
      }
      if (!first_time(r, fmt::format("product {} {}", *i, *j))) return;
      if (auto m = matrix(3, 3, fmt::format("`product {} {}`", *i, *j))) {
        auto& B = data_.product_kg;
        if (*i == *j) {  // int Phi_k Phi_k^T dm is symmetric
          B[static_cast<std::size_t>(*i - 1)][static_cast<std::size_t>(*i - 1)] = symmetric(*m, r, fmt::format("product {} {}", *i, *i).c_str());
          return;
        }
        B[static_cast<std::size_t>(*i - 1)][static_cast<std::size_t>(*j - 1)] = *m;
        Matrix t(3, std::vector<double>(3));
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) t[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] = (*m)[static_cast<std::size_t>(b)][static_cast<std::size_t>(a)];
        B[static_cast<std::size_t>(*j - 1)][static_cast<std::size_t>(*i - 1)] = t;
      }
    } else if (k == "point" || k == "shape" || k == "slope") {
      auto p = name(r);
      if (!p || !first_time(r, k + " " + *p)) return;
      ModalPoint& pt = data_.points[*p];
      if (k == "point") {
        if (auto m = matrix(1, 3, fmt::format("`point {}`", *p))) pt.position = {(*m)[0][0], (*m)[0][1], (*m)[0][2]};
      } else if (auto m = matrix(3, n, fmt::format("`{} {}` (3 x {})", k, *p, n))) {
        (k == "shape" ? pt.shape : pt.slope) = *m;
      }
    } else if (k == "mbgc_modal_body" || k == "modes") {
      fail(r.loc, fmt::format("`{}` may appear once, at the start of the file", k));
    } else {
      static const std::vector<std::string> records = {"mass",   "first_moment", "inertia", "mean",  "stiffness",
                                                       "moment", "product",      "point",   "shape", "slope"};
      std::string near = ir::closest_name(k, records);
      fail(r.loc, fmt::format("`{}` is not a record of a modal-data file", k),
           near.empty() ? std::string(kFormatHint) : fmt::format("did you mean `{}`?", near));
    }
  }

  /// A matrix that must be symmetric: checked to 1e-9 of its largest entry, then symmetrised.
  Matrix symmetric(Matrix m, const Token& r, const char* what) {
    double largest = 0;
    for (const auto& row : m)
      for (double x : row) largest = std::max(largest, std::abs(x));
    for (std::size_t a = 0; a < m.size(); ++a)
      for (std::size_t b = a + 1; b < m.size(); ++b) {
        if (std::abs(m[a][b] - m[b][a]) > 1e-9 * largest)
          fail(r.loc, fmt::format("`{}` is not symmetric: entry ({}, {}) is {:g}, entry ({}, {}) is {:g}", what, a + 1, b + 1, m[a][b], b + 1, a + 1, m[b][a]),
               "a mass or stiffness matrix is symmetric; check the order of the numbers (row by row)");
        m[a][b] = m[b][a] = 0.5 * (m[a][b] + m[b][a]);
      }
    return m;
  }

  void complete() {
    std::vector<std::string> missing;
    for (const char* k : {"mass", "first_moment", "inertia", "mean", "stiffness"})
      if (!seen_.count(k)) missing.push_back(fmt::format("`{}`", k));
    for (int i = 1; i <= data_.count; ++i) {
      if (!seen_.count(fmt::format("moment {}", i))) missing.push_back(fmt::format("`moment {}`", i));
      for (int j = i; j <= data_.count; ++j)
        if (!seen_.count(fmt::format("product {} {}", i, j))) missing.push_back(fmt::format("`product {} {}`", i, j));
    }
    for (const auto& [p, pt] : data_.points)
      for (const char* k : {"point", "shape", "slope"})
        if (!seen_.count(fmt::format("{} {}", k, p))) missing.push_back(fmt::format("`{} {}`", k, p));
    if (!missing.empty()) {
      std::string list;
      for (std::size_t i = 0; i < missing.size() && i < 6; ++i) list += (i ? ", " : "") + missing[i];
      if (missing.size() > 6) list += fmt::format(" and {} more", missing.size() - 6);
      fail(tokens_[0].loc, fmt::format("the modal-data file lacks {}", list),
           "every record is required (zeros are fine); a point needs point, shape and slope");
      return;
    }
    for (int i = 0; i < data_.count; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const Matrix& B = data_.product_kg[k][k];
      double modal_mass = B[0][0] + B[1][1] + B[2][2];
      if (!(modal_mass > 0) || !(data_.stiffness[k][k] > 0)) {
        fail(seen_.at(modal_mass > 0 ? "stiffness" : fmt::format("product {} {}", i + 1, i + 1)),
             fmt::format("mode {} has modal mass {:g} kg and modal stiffness {:g} N/m: both must be positive", i + 1,
                         modal_mass, data_.stiffness[k][k]),
             "rigid-body modes belong to the floating frame, not to the file's modes");
        return;
      }
    }
  }

  std::vector<Token> tokens_;
  int file_;
  ir::Diagnostics& diags_;
  std::size_t pos_ = 0;
  bool ok_ = true;
  ModalData data_;
  std::map<std::string, ir::SourceLoc> seen_;
};

/// ax(X) = [X23 - X32, X31 - X13, X12 - X21]: int a x b dm from X = int a b^T dm.
std::array<double, 3> ax(const Matrix& X) { return {X[1][2] - X[2][1], X[2][0] - X[0][2], X[0][1] - X[1][0]}; }
double trace(const Matrix& X) { return X[0][0] + X[1][1] + X[2][2]; }
Matrix zeros(std::size_t rows, std::size_t cols) { return Matrix(rows, std::vector<double>(cols, 0.0)); }

}  // namespace

ModalMassTerms modal_mass_terms(const ModalData& d) {
  const auto n = static_cast<std::size_t>(d.count);
  ModalMassTerms t;
  t.modal_mass = zeros(n, n);
  for (std::size_t i = 0; i < 3; ++i) {
    t.coupling[i] = zeros(1, n), t.coupling_eta[i] = zeros(n, n);
    for (std::size_t j = 0; j < 3; ++j) t.J1[i][j] = zeros(1, n), t.J2[i][j] = zeros(n, n);
  }
  for (std::size_t k = 0; k < n; ++k) {
    // |r|^2 I - r r^T with r = r0 + Phi eta: linear terms 2 (r0 . Phi_k) I - r0 Phi_k^T - Phi_k r0^T
    const Matrix& A = d.moment_kg_m[k];
    const auto a = ax(A);
    for (std::size_t i = 0; i < 3; ++i) {
      t.coupling[i][0][k] = a[i];
      for (std::size_t j = 0; j < 3; ++j) t.J1[i][j][0][k] = (i == j ? 2 * trace(A) : 0.0) - A[i][j] - A[j][i];
    }
    for (std::size_t l = 0; l < n; ++l) {
      const Matrix& Bkl = d.product_kg[k][l];
      t.modal_mass[k][l] = trace(Bkl);
      const auto b = ax(Bkl);
      for (std::size_t i = 0; i < 3; ++i) {
        t.coupling_eta[i][k][l] = b[i];
        // quadratic terms sum_kl eta_k eta_l (tr B_kl delta_ij - B_kl,ij), written symmetric in k, l
        for (std::size_t j = 0; j < 3; ++j)
          t.J2[i][j][k][l] = (i == j ? trace(Bkl) : 0.0) - 0.5 * (Bkl[i][j] + d.product_kg[l][k][i][j]);
      }
    }
  }
  return t;
}

std::optional<ModalData> read_modal_file(const std::string& name, const ir::SourceLoc& named_at,
                                         const std::vector<std::string>& search_dirs, ir::SourceManager& sources,
                                         ir::Diagnostics& diags) {
  auto id = ir::read_named_file(name, named_at, search_dirs, sources, diags, "modal-data file");
  if (!id) return std::nullopt;
  return read_modal_source(sources, *id, diags);
}

std::optional<ModalData> read_modal_source(const ir::SourceManager& sources, int file_id, ir::Diagnostics& diags) {
  ModalData data;
  data.path = sources.file(file_id).display_path;
  return Reader(tokenize(sources.file(file_id).text, file_id), file_id, diags).run(std::move(data));
}

}  // namespace mbgc::flex
