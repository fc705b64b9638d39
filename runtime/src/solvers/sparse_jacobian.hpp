// sparse_jacobian: IDA's Newton matrix dF/dy + c_j dF/dy' by finite
// differences on the pattern the compiler gives (Model::residual_sparsity),
// in compressed sparse columns for KLU. Columns that share no row are
// perturbed together (Curtis, Powell and Reid: a greedy colouring of the
// columns), so one residual evaluation gives a whole group of columns; for a
// chain of bodies the number of groups does not grow with the chain.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

namespace mbgrt::detail {

class SparseJacobian {
 public:
  /// column_starts (n + 1 entries) and rows as Model::residual_sparsity gives
  /// them; the diagonal is added where it is missing.
  SparseJacobian(std::vector<long> column_starts, std::vector<long> rows);

  std::size_t size() const { return starts_.size() - 1; }
  std::size_t nonzeros() const { return rows_.size(); }
  std::size_t groups() const { return groups_.size(); }
  /// The columns differenced together, group by group.
  const std::vector<std::vector<std::size_t>>& column_groups() const { return groups_; }
  const std::vector<long>& column_starts() const { return starts_; }
  const std::vector<long>& rows() const { return rows_; }
  /// Residual evaluations fill() has made (one per group per call).
  long evaluations() const { return evaluations_; }

  /// r(y, yp, out): the residual; returns 0 on success.
  using Residual = std::function<int(const double* y, const double* yp, double* r)>;

  /// values[k] for the k-th stored entry (the order of rows()), IDA's way:
  /// column j moved by inc_j = max(sqrt(eps) max(|y_j|, |h y'_j|), 1 / w_j)
  /// in y_j and c_j inc_j in y'_j, r0 the residual at (y, yp), w the error
  /// weights, h the current step. y and yp are restored. Non-zero: the
  /// residual's failure.
  int fill(const Residual& residual, double cj, double h, double* y, double* yp, const double* r0, const double* w,
           double* values);

 private:
  std::vector<long> starts_, rows_;
  std::vector<std::vector<std::size_t>> groups_;  // columns differenced together
  long evaluations_ = 0;
  std::vector<double> r_, inc_, y0_, yp0_;  // scratch: residual, steps, values before the steps
};

}  // namespace mbgrt::detail
