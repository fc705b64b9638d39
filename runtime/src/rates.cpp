// rates.cpp — consistent rates of a constrained DAE (constraints.hpp): y' of
// the states and the algebraic unknowns at an assembled state, for the start,
// a restart after an event and each stage of a step across a change point.
//
// The Newton matrix is differenced and factored densely up to
// kSparseRatesFromUnknowns unknowns: a complete orthogonal decomposition
// reveals its rank by pivoting on size and gives the minimum-norm answer
// where rows are dependent (the flexible double pendulum passes close to a
// singular configuration that a sparse QR, which orders columns to limit
// fill rather than by size, did not recognise, and its answer sent IDA on
// another path). From that size on, the dense solve's cube dominates (a
// step across a change point makes four a step: a row of 4 four-bars, 247
// unknowns, ran 10 s in 40 s dense, 7.5 s sparse), so the matrix is
// differenced on the residual's sparsity pattern (Model::residual_sparsity),
// columns that share no row together (the colouring of
// solvers/sparse_jacobian), and solved by a sparse LU (a sparse QR where the
// LU finds it singular): the cost grows with the model's non-zeros (a row of
// 40 four-bars has 2,263 unknowns).
#include <fmt/format.h>

#include <Eigen/OrderingMethods>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <Eigen/SparseQR>
#include <optional>

#include "constraints.hpp"
#include "newton_detail.hpp"
#include "report.hpp"
#include "solvers/sparse_jacobian.hpp"

namespace mbgrt::detail {
namespace {

using namespace newton;
using Sparse = Eigen::SparseMatrix<double>;
using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// The model's residual pattern with its columns coloured, from `from`
/// unknowns on; none below, or if the model gives none.
std::optional<SparseJacobian> sparse_pattern(const Model& model, std::size_t n, std::size_t from) {
  if (n < from) return std::nullopt;
  std::vector<long> starts, rows;
  if (!model.residual_sparsity(starts, rows) || starts.size() != n + 1) return std::nullopt;
  return SparseJacobian(std::move(starts), std::move(rows));
}

/// Central differences of f around v on the pattern, a group of columns at a
/// time: values[k] is the derivative of the k-th stored entry (the pattern's
/// order), for the columns below `end` (the others are left as they are).
template <class Fn>
bool grouped_differences(Fn&& f, Vec v, const SparseJacobian& pattern, std::size_t end, std::vector<double>& values) {
  const auto& starts = pattern.column_starts();
  const auto& rows = pattern.rows();
  Vec fp(v.size()), fm(v.size());
  std::vector<double> v0(pattern.size()), up(pattern.size()), down(pattern.size());
  for (const std::vector<std::size_t>& group : pattern.column_groups()) {
    std::vector<std::size_t> cols;
    for (std::size_t j : group)
      if (j < end) cols.push_back(j);
    if (cols.empty()) continue;
    for (std::size_t j : cols) {
      v0[j] = v[ix(j)];
      v[ix(j)] = v0[j] + fd_step(v0[j]);
      up[j] = v[ix(j)];
    }
    bool ok = f(v, fp);
    for (std::size_t j : cols) {
      v[ix(j)] = v0[j] - (up[j] - v0[j]);
      down[j] = v[ix(j)];
    }
    ok = f(v, fm) && ok;
    for (std::size_t j : cols) v[ix(j)] = v0[j];
    if (!ok) return false;
    for (std::size_t j : cols)
      for (long k = starts[j]; k < starts[j + 1]; ++k) {
        const auto row = ix(static_cast<std::size_t>(rows[static_cast<std::size_t>(k)]));
        values[static_cast<std::size_t>(k)] = (fp[row] - fm[row]) / (up[j] - down[j]);
      }
  }
  return true;
}

/// max_i sum_j |M_ij| |v_j|: the size of the terms each row balances.
double term_scale(const Sparse& M, const Vec& v) {
  Vec row_sums = Vec::Zero(M.rows());
  for (Index j = 0; j < M.outerSize(); ++j)
    for (Sparse::InnerIterator e(M, j); e; ++e) row_sums[e.row()] += std::abs(e.value()) * std::abs(v[j]);
  return row_sums.size() > 0 ? row_sums.maxCoeff() : 0.0;
}

/// A solution s of M s = -r, least-squares where the rows contradict each
/// other. Rows and columns are equilibrated (so neither units nor a row's
/// size look like dependence). A sparse LU with partial pivoting solves a
/// regular matrix (near a change point too: its answer is then large along
/// the dependent rows' multipliers only, whose force stays finite); where
/// it finds the matrix singular, a sparse QR treats a column keeping less
/// than kRankThreshold of its norm as dependent and leaves its unknown at 0
/// (a basic solution, not the minimum-norm one of the dense path: the two
/// differ along the dependent rows' multipliers, which the states' rates do
/// not depend on). The QR alone was 50 times slower at 2,263 unknowns.
Vec sparse_step(const Sparse& M, const Vec& r, Index* rank) {
  Vec w = Vec::Zero(M.rows()), u(M.cols());
  for (Index j = 0; j < M.outerSize(); ++j)
    for (Sparse::InnerIterator e(M, j); e; ++e) w[e.row()] = std::max(w[e.row()], std::abs(e.value()));
  for (Index i = 0; i < w.size(); ++i) w[i] = w[i] > 0.0 ? 1.0 / w[i] : 1.0;
  Sparse A = w.asDiagonal() * M;
  for (Index j = 0; j < A.outerSize(); ++j) {
    double big = 0.0;
    for (Sparse::InnerIterator e(A, j); e; ++e) big = std::max(big, std::abs(e.value()));
    u[j] = big > 0.0 ? 1.0 / big : 1.0;
  }
  A = A * u.asDiagonal();
  A.makeCompressed();
  const Vec b = -(w.asDiagonal() * r);
  Eigen::SparseLU<Sparse, Eigen::COLAMDOrdering<int>> lu;
  lu.compute(A);
  if (lu.info() == Eigen::Success) {
    Vec x = lu.solve(b);
    if (lu.info() == Eigen::Success && x.allFinite()) {
      *rank = A.cols();
      return u.asDiagonal() * x;
    }
  }
  Eigen::SparseQR<Sparse, Eigen::COLAMDOrdering<int>> qr;
  qr.setPivotThreshold(kRankThreshold);
  qr.compute(A);
  *rank = qr.info() == Eigen::Success ? qr.rank() : 0;
  if (qr.info() != Eigen::Success) return Vec::Zero(M.cols());
  return u.asDiagonal() * Vec(qr.solve(b));
}

}  // namespace

InitialValuesReport consistent_initial_values(Model& model, const ConstraintShape& s, double t,
                                              double* y_io, double* yp_io, const RatesOptions& options) {
  InitialValuesReport rep;
  const Index n = ix(s.n), ns = ix(s.ns);
  rep.unknowns = s.n;
  Vec Y = Eigen::Map<const Vec>(y_io, n), YP = Eigen::Map<const Vec>(yp_io, n);
  Vec Yw = Y, YPw = YP;

  // z = [y'_states; y_algebraic]
  Vec z(n);
  z.head(ns) = YP.head(ns);
  z.tail(n - ns) = Y.tail(n - ns);
  auto residual_at_z = [&](const Vec& zz, Vec& r) {
    YPw.head(ns) = zz.head(ns);
    Yw.tail(n - ns) = zz.tail(n - ns);
    constrained_residual(model, s, t, Yw.data(), YPw.data(), r.data());
    return r.allFinite();
  };
  auto fail_row = [&](Index row, const char* what) {
    rep.error = fmt::format(
        "consistent initial values: the residual of {} is {} at the assembled initial values (t = {} s)",
        residual_row_name(model, s, sz(row)), what, format_time(t));
  };

  Vec r0(n);
  if (!residual_at_z(z, r0)) {
    Index bad = 0;
    max_abs(r0, &bad);
    fail_row(bad, "not finite");
    return rep;
  }
  std::vector<Index> zcols(s.n);
  for (std::size_t j = 0; j < s.n; ++j) zcols[j] = ix(j);
  const std::optional<SparseJacobian> pattern = sparse_pattern(model, s.n, options.sparse_from);

  // The constraint rows (g, gdot) depend on neither y' nor an algebraic
  // unknown: each is replaced by its time derivative dr/dt + (dr/dy_states)
  // y'_states = 0. Their coefficients do not depend on z, so they are
  // computed once here. A redundant row's are not constraint rows any more
  // (pin_redundant_multipliers made them lambda = 0 and mu = 0).
  std::vector<bool> redundant(s.np, false);
  for (std::size_t k : s.redundant) redundant[k] = true;
  std::vector<Index> pure;
  std::vector<Index> pure_at(s.n, -1);  // row -> its index in pure
  for (Index k = 0; k < n; ++k)
    if (const RowRole role = residual_row_role(s, sz(k)); role.kind != RowRole::equation && !redundant[role.row]) {
      pure_at[sz(k)] = ix(pure.size());
      pure.push_back(k);
    }
  rep.differentiated_rows = pure.size();
  const Index nd = ix(pure.size());
  SparseRows A(nd, n);    // d r_k / d y_states in the z_states columns
  Vec b = Vec::Zero(nd);  // d r_k / d t
  if (nd > 0) {
    auto residual_at_y = [&](const Vec& yy, Vec& r) {
      constrained_residual(model, s, t, yy.data(), YP.data(), r.data());
      return r.allFinite();
    };
    const double h = fd_step(t);
    const double up = t + h, down = t - h;
    Vec rp(n), rm(n);
    constrained_residual(model, s, up, Y.data(), YP.data(), rp.data());
    constrained_residual(model, s, down, Y.data(), YP.data(), rm.data());
    std::vector<Eigen::Triplet<double>> entries;
    bool finite = rp.allFinite() && rm.allFinite();
    if (pattern) {
      std::vector<double> values(pattern->nonzeros());
      finite = grouped_differences(residual_at_y, Y, *pattern, s.ns, values) && finite;
      for (std::size_t j = 0; j < s.ns; ++j)
        for (long k = pattern->column_starts()[j]; k < pattern->column_starts()[j + 1]; ++k)
          if (const Index d = pure_at[static_cast<std::size_t>(pattern->rows()[static_cast<std::size_t>(k)])]; d >= 0)
            entries.emplace_back(d, ix(j), values[static_cast<std::size_t>(k)]);
    } else {
      std::vector<Index> scols(s.ns);
      for (std::size_t j = 0; j < s.ns; ++j) scols[j] = ix(j);
      const Linearization Ly = linearize(residual_at_y, Y, n, 0, n, scols);
      finite = Ly.finite && finite;
      for (Index d = 0; d < nd && finite; ++d)
        for (Index j = 0; j < ns; ++j)
          if (Ly.J(pure[sz(d)], j) != 0.0) entries.emplace_back(d, j, Ly.J(pure[sz(d)], j));
    }
    if (!finite) {
      rep.error = fmt::format(
          "consistent initial values: a constraint row is not finite near the assembled initial "
          "values (t = {} s)",
          format_time(t));
      return rep;
    }
    for (Index d = 0; d < nd; ++d) b[d] = (rp[pure[sz(d)]] - rm[pure[sz(d)]]) / (up - down);
    // Index one: mu = 0 in place of the position rows' derivatives (their
    // row is mu's own index in y, and so in z).
    if (options.index_one) {
      std::vector<Eigen::Triplet<double>> kept;
      for (const auto& e : entries)
        if (residual_row_role(s, sz(pure[sz(e.row())])).kind != RowRole::position_constraint) kept.push_back(e);
      for (Index d = 0; d < nd; ++d)
        if (residual_row_role(s, sz(pure[sz(d)])).kind == RowRole::position_constraint) {
          kept.emplace_back(d, pure[sz(d)], 1.0);
          b[d] = 0.0;
        }
      entries.swap(kept);
    }
    A.setFromTriplets(entries.begin(), entries.end());
  }
  auto system = [&](const Vec& zz, Vec& F) {
    if (!residual_at_z(zz, F)) return false;
    for (Index d = 0; d < nd; ++d) F[pure[sz(d)]] = A.row(d).dot(zz) + b[d];
    return true;
  };

  // The Newton step at z from the system's value F there, and the size of
  // the terms its rows balance; false where the residual is not finite.
  auto newton_step = [&](const Vec& zz, const Vec& F, Vec& step, double& scale) {
    Index rank = 0;
    if (pattern) {
      std::vector<double> values(pattern->nonzeros());
      if (!grouped_differences(residual_at_z, zz, *pattern, s.n, values)) return false;
      std::vector<Eigen::Triplet<double>> entries;
      for (std::size_t j = 0; j < s.n; ++j)
        for (long k = pattern->column_starts()[j]; k < pattern->column_starts()[j + 1]; ++k) {
          const auto row = static_cast<std::size_t>(pattern->rows()[static_cast<std::size_t>(k)]);
          if (pure_at[row] < 0) entries.emplace_back(ix(row), ix(j), values[static_cast<std::size_t>(k)]);
        }
      for (Index d = 0; d < nd; ++d)
        for (SparseRows::InnerIterator e(A, d); e; ++e) entries.emplace_back(pure[sz(d)], e.col(), e.value());
      Sparse M(n, n);
      M.setFromTriplets(entries.begin(), entries.end());
      scale = term_scale(M, zz);
      step = sparse_step(M, F, &rank);
    } else {
      const Linearization L = linearize(residual_at_z, zz, n, 0, n, zcols);
      if (!L.finite) return false;
      Mat J = L.J;
      for (Index d = 0; d < nd; ++d) J.row(pure[sz(d)]) = A.row(d);
      scale = newton::term_scale(J, zz, zcols);
      step = min_norm_step(J, F, &rank);
    }
    rep.rank = sz(rank);
    return true;
  };

  Vec F(n);
  Index worst = 0;
  if (!system(z, F)) {
    max_abs(F, &worst);
    fail_row(worst, "not finite");
    return rep;
  }
  // The system is affine for multibody models: one step, then a check. The
  // finite-difference Jacobian is good to ~1e-10, so a second step takes the
  // residual from there to rounding; steps continue while they pay (each at
  // least halves the residual) down to kTight, and the result is accepted
  // below kAccept, both relative to 1 + the size of the terms in the rows.
  constexpr int kMaxIterations = 10;
  constexpr double kTight = 1e-14, kAccept = 1e-9;
  double scale = 0.0;
  for (;;) {
    Vec step;
    if (!newton_step(z, F, step, scale)) break;
    const double residual = max_abs(F);
    if (residual <= kTight * (1.0 + scale) || rep.iterations >= kMaxIterations) break;
    Vec z_new = z + step, F_new(n);
    if (!system(z_new, F_new)) break;
    const double new_residual = max_abs(F_new);
    if (new_residual < residual) {
      z = z_new;
      F = F_new;
      ++rep.iterations;
    }
    if (!(new_residual <= 0.5 * residual)) break;
  }
  const double tol = kAccept * (1.0 + scale);
  rep.residual = max_abs(F, &worst);
  rep.least_squares = !(rep.residual <= tol) && options.least_squares && rep.rank < s.n;
  if (!(rep.residual <= tol) && !rep.least_squares) {
    rep.error = fmt::format(
        "consistent initial values: the residual of {} is {} after {} Newton iterations: y' and "
        "the algebraic unknowns cannot be determined at the assembled state (t = {} s){}",
        residual_row_name(model, s, sz(worst)), g2(rep.residual), rep.iterations, format_time(t),
        rep.rank < s.n ? fmt::format("; the Newton matrix has rank {} of {} (redundant or "
                                     "contradictory constraints?)",
                                     rep.rank, s.n)
                       : std::string());
    return rep;
  }

  for (Index j = 0; j < ns; ++j) yp_io[j] = z[j];
  for (Index j = ns; j < n; ++j) y_io[j] = z[j];
  rep.ok = true;
  return rep;
}

std::string describe(const InitialValuesReport& r, const ConstraintShape& s) {
  std::string text = fmt::format(
      "y' of {} states and {} algebraic unknowns computed by the runtime ({} constraint rows "
      "differentiated once), residual {} after {} Newton iteration{}",
      s.ns, s.n - s.ns, r.differentiated_rows, g2(r.residual), r.iterations,
      r.iterations == 1 ? "" : "s");
  if (r.rank < r.unknowns)
    text += fmt::format("; rank {} of {}: the multipliers are not unique (redundant constraints?)",
                        r.rank, r.unknowns);
  return text;
}

}  // namespace mbgrt::detail
