// fe/matrix_market.cpp
#include "matrix_market.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <vector>

#include "text_reader.hpp"

namespace mbgc::fe {
namespace {

const char* kHeaderHint =
    "the first line of a Matrix Market file is `%%MatrixMarket matrix coordinate real symmetric` "
    "(or `general`; `integer` also works)";

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

std::optional<SparseMatrix> read_matrix_market(const std::string& path, const char* what, long size,
                                               ir::SourceManager& sources, ir::Diagnostics& diags) {
  TextReader in(sources, diags);
  if (!in.open(path, '%')) return std::nullopt;

  // Header: %%MatrixMarket matrix coordinate real symmetric
  std::vector<std::string> header;
  if (in.raw_line()) {
    std::string_view line = in.line_text();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i > start) header.push_back(lower(line.substr(start, i - start)));
    }
  }
  if (header.size() != 5 || header[0] != "%%matrixmarket" || header[1] != "matrix") {
    diags.error(in.line_loc(), fmt::format("`{}` is not a Matrix Market file", path), kHeaderHint);
    return std::nullopt;
  }
  if (header[2] != "coordinate") {
    diags.error(in.line_loc(), fmt::format("the {} is stored as `{}`; mbgc-reduce reads sparse `coordinate` files", what, header[2]),
                "an FE model's matrices are sparse; write them in coordinate form");
    return std::nullopt;
  }
  if (header[3] != "real" && header[3] != "integer" && header[3] != "double") {
    diags.error(in.line_loc(), fmt::format("the {} holds `{}` numbers; a mass or stiffness matrix is real", what, header[3]), kHeaderHint);
    return std::nullopt;
  }
  const bool symmetric = header[4] == "symmetric";
  if (!symmetric && header[4] != "general") {
    diags.error(in.line_loc(), fmt::format("`{}` symmetry: a mass or stiffness matrix is `symmetric` (or written in full as `general`)", header[4]),
                kHeaderHint);
    return std::nullopt;
  }

  std::vector<Word> w;
  if (!in.next_line(w)) {
    diags.error(in.end_loc(), fmt::format("the {} file ends before its size line `rows columns entries`", what));
    return std::nullopt;
  }
  if (w.size() != 3) {
    diags.error(in.line_loc(), fmt::format("the size line has {} numbers, expected 3: rows, columns, entries", w.size()));
    return std::nullopt;
  }
  const auto rows = in.integer(w[0], "the row count", 1, 1'000'000'000);
  const auto cols = rows ? in.integer(w[1], "the column count", 1, 1'000'000'000) : std::nullopt;
  const auto entries = cols ? in.integer(w[2], "the entry count", 0, 2'000'000'000) : std::nullopt;
  if (!entries) return std::nullopt;
  if (*rows != *cols) {
    diags.error(w[1].loc, fmt::format("the {} is {} x {}; it must be square", what, *rows, *cols));
    return std::nullopt;
  }
  if (*rows != size) {
    diags.error(w[0].loc, fmt::format("the {} is {} x {}, but the nodes give {} DOFs", what, *rows, *rows, size),
                "one row and column per DOF: the node file's nodes times --dofs-per-node, in the node file's order");
    return std::nullopt;
  }

  std::vector<Eigen::Triplet<double, long>> triplets;
  std::vector<int> line_of;  // per triplet, for the asymmetry message
  triplets.reserve(static_cast<std::size_t>(std::min<long long>(*entries, 50'000'000)) * (symmetric ? 2 : 1));
  long long count = 0;
  while (in.next_line(w)) {
    if (count == *entries) {
      diags.error(w[0].loc, fmt::format("more entries than the {} the size line announced", *entries));
      return std::nullopt;
    }
    if (w.size() != 3) {
      diags.error(in.line_loc(), fmt::format("an entry is `row column value`; this line has {} words", w.size()));
      return std::nullopt;
    }
    const auto i = in.integer(w[0], "the row", 1, *rows);
    const auto j = i ? in.integer(w[1], "the column", 1, *cols) : std::nullopt;
    const auto v = j ? in.number(w[2], "the value") : std::nullopt;
    if (!v) return std::nullopt;
    if (symmetric && *j > *i) {
      diags.error(w[1].loc, fmt::format("entry ({}, {}) is above the diagonal of a `symmetric` file", *i, *j),
                  "a symmetric Matrix Market file holds the lower triangle (row >= column); or declare it `general`");
      return std::nullopt;
    }
    triplets.emplace_back(*i - 1, *j - 1, *v);
    line_of.push_back(in.line_number());
    if (symmetric && *i != *j) triplets.emplace_back(*j - 1, *i - 1, *v);
    ++count;
  }
  if (count != *entries) {
    diags.error(in.end_loc(), fmt::format("the {} file has {} entries, but its size line announced {}", what, count, *entries));
    return std::nullopt;
  }
  SparseMatrix m(size, size);
  m.setFromTriplets(triplets.begin(), triplets.end());
  m.makeCompressed();

  if (!symmetric) {
    double largest = 0;
    for (long k = 0; k < m.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(m, k); it; ++it) largest = std::max(largest, std::abs(it.value()));
    const SparseMatrix transposed = m.transpose();
    const SparseMatrix skew = m - transposed;
    double worst = 0;
    long wi = 0, wj = 0;
    for (long k = 0; k < skew.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(skew, k); it; ++it)
        if (std::abs(it.value()) > worst) worst = std::abs(it.value()), wi = it.row(), wj = it.col();
    if (worst > 1e-10 * largest) {
      // point at the line that wrote (wi, wj), or at (wj, wi) when only that one exists
      int line = 0;
      for (std::size_t t = 0; t < triplets.size() && !line; ++t)
        if ((triplets[t].row() == wi && triplets[t].col() == wj) || (triplets[t].row() == wj && triplets[t].col() == wi))
          line = line_of[t];
      diags.error({in.file(), std::max(line, 1), 1, 1},
                  fmt::format("the {} is not symmetric: entries ({}, {}) and ({}, {}) differ by {:.3g}, {:.3g} of its largest entry",
                              what, wi + 1, wj + 1, wj + 1, wi + 1, worst, worst / largest),
                  "a mass or stiffness matrix of a conservative structure is symmetric; check the export");
      return std::nullopt;
    }
    m = (0.5 * (m + transposed)).eval();  // rounding-level asymmetry removed
  }
  return m;
}

}  // namespace mbgc::fe
