// newton_detail.hpp — the small numerical pieces the constraint code's
// Newton iterations share (assembly, consistent rates): finite differences,
// the minimum-norm step, residual sizes. Internal to the runtime.
#pragma once

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "constraints.hpp"

namespace mbgrt::detail::newton {

using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using Index = Eigen::Index;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Central differences: a step of cbrt(eps) balances truncation against
/// rounding (relative error about 1e-11 for smooth functions).
inline double fd_step(double v) {
  static const double cbrt_eps = std::cbrt(std::numeric_limits<double>::epsilon());
  return cbrt_eps * std::max(1.0, std::abs(v));
}

/// A column of the Newton matrix whose pivot is below this fraction of the
/// largest (after row equilibration) is treated as dependent: well above the
/// ~1e-10 relative error of a central-difference Jacobian.
constexpr double kRankThreshold = 1e-8;

inline Index ix(std::size_t i) { return static_cast<Index>(i); }
inline std::size_t sz(Index i) { return static_cast<std::size_t>(i); }

/// Jacobian of rows [row0, row0 + rows) of f with respect to v[cols], by
/// central differences around v: the Newton matrices of the velocity phase
/// and of the initial values (numbers, not structure: which unknowns and rows
/// are which is the model's layout).
struct Linearization {
  Mat J;
  bool finite = true;
};

template <class Fn>
Linearization linearize(Fn&& f, Vec v, Index out_size, Index row0, Index rows, const std::vector<Index>& cols) {
  Linearization L;
  const auto m = ix(cols.size());
  L.J = Mat::Zero(rows, m);
  Vec fp(out_size), fm(out_size);
  for (Index c = 0; c < m; ++c) {
    const Index j = cols[sz(c)];
    const double v0 = v[j], h = fd_step(v0);
    v[j] = v0 + h;
    const double up = v[j];
    bool ok = f(v, fp);
    v[j] = v0 - h;
    const double down = v[j];
    ok = f(v, fm) && ok;
    v[j] = v0;
    if (!ok) {
      L.finite = false;
      return L;
    }
    L.J.col(c) = (fp.segment(row0, rows) - fm.segment(row0, rows)) / (up - down);
  }
  return L;
}

/// G = dg/dx at (t, y) over the states `cols` (the model's symbolic
/// constraint_jacobian), as a dense P x cols.size() matrix.
struct SymbolicG {
  Model& model;
  const ConstraintShape& shape;
  double t;
  std::vector<double> values = std::vector<double>(shape.g_columns.size());
  std::vector<Index> column_of = std::vector<Index>(shape.ns, -1);

  bool operator()(const Vec& y, const std::vector<Index>& cols, Mat& J) {
    std::fill(column_of.begin(), column_of.end(), Index{-1});
    for (std::size_t k = 0; k < cols.size(); ++k) column_of[sz(cols[k])] = ix(k);
    model.constraint_jacobian(t, y.data(), values.data());
    J = Mat::Zero(ix(shape.np), ix(cols.size()));
    for (std::size_t r = 0; r < shape.np; ++r)
      for (long e = shape.g_row_starts[r]; e < shape.g_row_starts[r + 1]; ++e) {
        const double v = values[static_cast<std::size_t>(e)];
        if (!std::isfinite(v)) return false;
        if (const Index c = column_of[static_cast<std::size_t>(shape.g_columns[static_cast<std::size_t>(e)])]; c >= 0)
          J(ix(r), c) = v;
      }
    return true;
  }
};

/// Minimum-norm least-squares solution s of J s = -r. Rows are equilibrated
/// first (which leaves the solution of a consistent system unchanged), so a
/// row in small units does not look like a dependent one. `rank`, if asked
/// for, is that of J with its columns equilibrated too, so that it does not
/// depend on units either (a 0.005 kg m^2 base beside a 200 kg payload made
/// its columns look dependent). The step itself stays least-norm in the
/// unknowns as they are: scaling its columns would pick another solution
/// wherever the system is nearly singular.
inline Vec min_norm_step(const Mat& J, const Vec& r, Index* rank = nullptr) {
  Vec w(J.rows());
  for (Index i = 0; i < J.rows(); ++i) {
    const double big = J.cols() > 0 ? J.row(i).cwiseAbs().maxCoeff() : 0.0;
    w[i] = big > 0.0 ? 1.0 / big : 1.0;
  }
  const Mat A = w.asDiagonal() * J;
  const Vec b = -(w.asDiagonal() * r);
  Eigen::CompleteOrthogonalDecomposition<Mat> cod;
  cod.setThreshold(kRankThreshold);
  cod.compute(A);
  if (rank) {
    Vec u(A.cols());
    for (Index j = 0; j < A.cols(); ++j) {
      const double big = A.rows() > 0 ? A.col(j).cwiseAbs().maxCoeff() : 0.0;
      u[j] = big > 0.0 ? 1.0 / big : 1.0;
    }
    Eigen::CompleteOrthogonalDecomposition<Mat> scaled;
    scaled.setThreshold(kRankThreshold);
    scaled.compute(A * u.asDiagonal());
    *rank = scaled.rank();
  }
  return cod.solve(b);
}

/// max_i sum_j |J_ij| |v[cols_j]|: the size of the terms each row balances.
inline double term_scale(const Mat& J, const Vec& v, const std::vector<Index>& cols) {
  double scale = 0.0;
  for (Index i = 0; i < J.rows(); ++i) {
    double s = 0.0;
    for (Index c = 0; c < J.cols(); ++c) s += std::abs(J(i, c)) * std::abs(v[cols[sz(c)]]);
    scale = std::max(scale, s);
  }
  return scale;
}

inline double max_abs(const Vec& v, Index* where = nullptr) {
  double best = 0.0;
  Index at = 0;
  for (Index i = 0; i < v.size(); ++i) {
    const double a = std::isfinite(v[i]) ? std::abs(v[i]) : kInf;
    if (a > best) {
      best = a;
      at = i;
    }
  }
  if (where) *where = at;
  return best;
}

inline std::string g2(double v) { return fmt::format("{:.2g}", v); }

}  // namespace mbgrt::detail::newton
