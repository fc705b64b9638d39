#include "solvers/sparse_jacobian.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mbgrt::detail {

SparseJacobian::SparseJacobian(std::vector<long> column_starts, std::vector<long> rows)
    : starts_(std::move(column_starts)), rows_(std::move(rows)) {
  if (starts_.empty() || starts_.front() != 0 || static_cast<std::size_t>(starts_.back()) != rows_.size())
    throw std::invalid_argument("residual_sparsity: column starts do not match the rows");
  const std::size_t n = size();
  for (std::size_t j = 0; j < n; ++j) {
    if (starts_[j + 1] < starts_[j]) throw std::invalid_argument("residual_sparsity: column starts decrease");
    for (long k = starts_[j]; k < starts_[j + 1]; ++k)
      if (rows_[static_cast<std::size_t>(k)] < 0 || static_cast<std::size_t>(rows_[static_cast<std::size_t>(k)]) >= n)
        throw std::invalid_argument("residual_sparsity: a row out of range");
  }
  // The diagonal is always stored: the runtime may replace a residual row by
  // its own unknown (a redundant constraint's multiplier held at 0).
  std::vector<long> starts{0}, with_diagonal;
  with_diagonal.reserve(rows_.size() + n);
  for (std::size_t j = 0; j < n; ++j) {
    std::vector<long> column(rows_.begin() + starts_[j], rows_.begin() + starts_[j + 1]);
    column.push_back(static_cast<long>(j));
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
    with_diagonal.insert(with_diagonal.end(), column.begin(), column.end());
    starts.push_back(static_cast<long>(with_diagonal.size()));
  }
  starts_.swap(starts);
  rows_.swap(with_diagonal);
  // Greedy colouring: each column joins the first group none of whose
  // columns has a row in common with it.
  std::vector<std::vector<std::size_t>> row_groups(n);  // groups that already touch each row
  std::vector<std::size_t> stamp;                      // stamp[g] == j + 1: group g is forbidden for column j
  for (std::size_t j = 0; j < n; ++j) {
    for (long k = starts_[j]; k < starts_[j + 1]; ++k)
      for (std::size_t g : row_groups[static_cast<std::size_t>(rows_[static_cast<std::size_t>(k)])]) stamp[g] = j + 1;
    std::size_t g = 0;
    while (g < groups_.size() && stamp[g] == j + 1) ++g;
    if (g == groups_.size()) {
      groups_.emplace_back();
      stamp.push_back(0);
    }
    groups_[g].push_back(j);
    for (long k = starts_[j]; k < starts_[j + 1]; ++k) row_groups[static_cast<std::size_t>(rows_[static_cast<std::size_t>(k)])].push_back(g);
  }
  r_.resize(n);
  inc_.resize(n);
  y0_.resize(n);
  yp0_.resize(n);
}

int SparseJacobian::fill(const Residual& residual, double cj, double h, double* y, double* yp, const double* r0,
                         const double* w, double* values) {
  const double srur = std::sqrt(std::numeric_limits<double>::epsilon());
  for (const std::vector<std::size_t>& group : groups_) {
    for (std::size_t j : group) {
      double inc = std::max(srur * std::max(std::abs(y[j]), std::abs(h * yp[j])), 1.0 / w[j]);
      if (h * yp[j] < 0.0) inc = -inc;
      y0_[j] = y[j];
      yp0_[j] = yp[j];
      y[j] += inc;
      inc_[j] = y[j] - y0_[j];  // the step actually taken, after rounding
      yp[j] += cj * inc_[j];
    }
    const int flag = residual(y, yp, r_.data());
    ++evaluations_;
    for (std::size_t j : group) {
      y[j] = y0_[j];
      yp[j] = yp0_[j];
    }
    if (flag != 0) return flag;
    for (std::size_t j : group)
      for (long k = starts_[j]; k < starts_[j + 1]; ++k) {
        const auto row = static_cast<std::size_t>(rows_[static_cast<std::size_t>(k)]);
        values[k] = (r_[row] - r0[row]) / inc_[j];
      }
  }
  return 0;
}

}  // namespace mbgrt::detail
