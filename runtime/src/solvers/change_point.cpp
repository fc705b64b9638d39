// solvers/change_point.cpp — stepping an index-2 DAE across a change point.
#include "solvers/change_point.hpp"

#include <fmt/format.h>

#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>

namespace mbgrt::detail {
namespace {

// IDA is stepped across where the rows kept less than this share of their
// independence at the start.
constexpr double kNearChangePoint = 0.3;
// The steps end beyond the crossing where the rows are four times as
// independent as where IDA stopped (about 0.1 of the start's, IDA's watch):
// beyond kNearChangePoint, so that a failure of IDA just after its restart is
// not taken for another change point (measured on IFToMM's N four-bar, N =
// 4 and 10: with twice, 15 to 25 steps across 13 passages, each extra one
// costing up to 4e-7 J; with four times, one step across each).
constexpr double kBeyond = 5.0;
// Below this independence the crossing is taken to be here (its rate is
// measured poorly so close to it).
constexpr double kSmallestIndependence = 1e-3;
// The longest Runge-Kutta step (s). Its truncation error is what a step
// across costs in energy: measured on IFToMM's N four-bar at rtol 1e-10,
// 10 ms left 2e-8 to 4e-8 J a passage, a phase error of up to 3.7e-6 m over
// 10 s for N = 40; 2.5 ms brings N = 1, 4, 10 and 40 within 1e-6 m.
constexpr double kLongestStep = 2.5e-3;
// The most steps across one change point.
constexpr int kMostSteps = 200;
// The time over which the independence's rate is measured (s).
constexpr double kRateProbe = 1e-6;

}  // namespace

double row_independence(Model& model, const ConstraintShape& shape, double t, const double* y, std::size_t* row) {
  // Gram-Schmidt over the unit gradients in row order leaves of row k the
  // part sqrt(D_k), where L D L' is the Cholesky factorization of their Gram
  // matrix in the same order: find_redundant_constraints's measure, sparse
  // (IDA's root function asks for it at every step).
  std::vector<bool> skip(shape.np, false);
  for (std::size_t k : shape.redundant) skip[k] = true;
  std::vector<double> values(shape.g_columns.size());
  model.constraint_jacobian(t, y, values.data());
  using Sparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  std::vector<Eigen::Triplet<double>> entries;
  int rows = 0;
  std::vector<std::size_t> row_of;  // the position row of each of G's rows here
  for (std::size_t r = 0; r < shape.np; ++r) {
    if (skip[r] || shape.lambda_at[r] < 0) continue;
    const auto first = static_cast<std::size_t>(shape.g_row_starts[r]);
    const auto last = static_cast<std::size_t>(shape.g_row_starts[r + 1]);
    double norm = 0.0;
    for (std::size_t e = first; e < last; ++e) norm += values[e] * values[e];
    if (!std::isfinite(norm)) return 1.0;  // (the run's own checks report it)
    if (norm == 0.0) continue;             // depends on no state
    norm = std::sqrt(norm);
    for (std::size_t e = first; e < last; ++e)
      entries.emplace_back(rows, static_cast<int>(shape.g_columns[e]), values[e] / norm);
    row_of.push_back(r);
    ++rows;
  }
  if (rows == 0) return 1.0;
  Sparse G(rows, static_cast<Eigen::Index>(shape.ns));
  G.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<double> gram = G * G.transpose();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt(gram);
  const Eigen::VectorXd D = ldlt.vectorD();
  const double floor = kRedundantRowThreshold * kRedundantRowThreshold;
  Eigen::Index at = 0;
  const double least = D.size() > 0 ? D.minCoeff(&at) : 1.0;
  for (Eigen::Index k = 0; k < D.size(); ++k)  // the first dependent one, if any
    if (!(D[k] >= floor)) {
      at = k;
      break;
    }
  if (row) *row = row_of[static_cast<std::size_t>(at)];
  if (ldlt.info() != Eigen::Success) return 0.0;
  return least < floor ? 0.0 : std::sqrt(least);
}

std::optional<ChangePointStep> ChangePointStep::plan(Model& model, const ConstraintShape& shape, double start_independence,
                                                     double t0, const double* y0, const double* yp0, double t_limit,
                                                     std::string& why) {
  ChangePointStep step(model, shape);
  step.rho0_ = row_independence(model, shape, t0, y0, &step.row_);
  if (!(step.rho0_ < kNearChangePoint * start_independence)) {
    why = fmt::format("the joints' rows are not close to dependent there (independence {:.2g}, {:.2g} at the start)",
                      step.rho0_, start_independence);
    return std::nullopt;
  }
  // The independence falls linearly to 0 at the crossing and rises as fast
  // beyond it.
  std::vector<double> y1(y0, y0 + shape.n);
  for (std::size_t i = 0; i < shape.ns; ++i) y1[i] += kRateProbe * yp0[i];
  const double rate = (row_independence(model, shape, t0 + kRateProbe, y1.data()) - step.rho0_) / kRateProbe;
  if (!(std::abs(rate) > 0.0) || !std::isfinite(rate)) {
    why = fmt::format("the joints' rows are close to dependent (independence {:.2g}) but not changing", step.rho0_);
    return std::nullopt;
  }
  // Equal steps of at most kLongestStep that put the crossing halfway
  // between a step's middle stages and its end, until the rows are, beyond
  // it, kBeyond - 1 times as independent as here. (A stage at the crossing
  // would take its rates from contradictory rows: measured, a step ending
  // there changed the energy by 1e-4 J, ten thousand times what one that
  // straddles it does.)
  const double ahead = std::max(step.rho0_, kSmallestIndependence) / std::abs(rate);
  const double before = rate < 0.0 ? std::max(0.0, std::ceil(ahead / kLongestStep - 0.75)) : 0.0;
  const double h = rate < 0.0 ? ahead / (before + 0.75) : std::min(kLongestStep, ahead);
  // IDA's y there may be its interpolation's, and its y' is its BDF
  // formula's, not the DAE's: the first stage needs both the DAE's.
  Point start{t0, std::vector<double>(y0, y0 + shape.n), std::vector<double>(yp0, yp0 + shape.n), {0.0, 0.0}};
  if (!step.rates(t0, start.y, start.yp, true, why)) return std::nullopt;
  step.path_.push_back(std::move(start));
  const double target = (kBeyond - 1.0) * std::max(step.rho0_, kSmallestIndependence);
  double last = step.rho0_;
  for (int k = 0;; ++k) {
    const double t1 = std::min(step.path_.back().t + h, t_limit);
    if (!(t1 > step.path_.back().t) || k == kMostSteps) {
      why = fmt::format("the rows stayed close to dependent for {} steps of {:.3g} s", k, h);
      return std::nullopt;
    }
    if (!step.march(t1, step.path_, why)) return std::nullopt;
    if (t1 >= t_limit) break;  // the run ends inside the passage: its last steps are these
    const double now = row_independence(model, shape, t1, step.path_.back().y.data());
    if (now > last && now >= target) break;
    last = now;
  }
  return step;
}

bool ChangePointStep::rates(double t, std::vector<double>& y, std::vector<double>& yp, bool on_constraints,
                            std::string& why) const {
  if (on_constraints)
    if (const AssemblyReport a = assemble(*model_, *shape_, t, y.data(), true); !a.ok) {
      why = fmt::format("at t = {:.9g} s: {}", t, a.error);
      return false;
    }
  RatesOptions options;
  options.least_squares = true;
  options.index_one = true;
  const InitialValuesReport r = consistent_initial_values(*model_, *shape_, t, y.data(), yp.data(), options);
  if (!r.ok) why = fmt::format("no consistent rates at t = {:.9g} s: {}", t, r.error);
  return r.ok;
}

bool ChangePointStep::march(double t, std::vector<Point>& path, std::string& why) const {
  const std::size_t ns = shape_->ns;
  const Point start = path.back();
  const int steps = std::max(1, static_cast<int>(std::ceil((t - start.t) / kLongestStep)));
  const double h = (t - start.t) / steps;
  std::vector<double> stage, k, sum(ns);
  const double weight[4] = {1.0, 2.0, 2.0, 1.0}, advance[4] = {0.0, 0.5, 0.5, 1.0};
  for (int step = 0; step < steps; ++step) {
    Point next = path.back();
    std::fill(sum.begin(), sum.end(), 0.0);
    double power_sum[2] = {0.0, 0.0};
    k = next.yp;  // the first stage's rates: consistent at the step's start
    for (int s = 0; s < 4; ++s) {
      const double ts = next.t + advance[s] * h;
      stage = next.y;
      for (std::size_t i = 0; i < ns; ++i) stage[i] += advance[s] * h * k[i];
      if (s > 0 && !rates(ts, stage, k, false, why)) return false;
      for (std::size_t i = 0; i < ns; ++i) sum[i] += weight[s] * k[i];
      double p[2] = {0.0, 0.0};
      model_->power(ts, stage.data(), k.data(), p);
      power_sum[0] += weight[s] * p[0], power_sum[1] += weight[s] * p[1];
    }
    for (std::size_t i = 0; i < ns; ++i) next.y[i] += h / 6.0 * sum[i];
    next.t = step + 1 == steps ? t : start.t + (step + 1) * h;
    if (!rates(next.t, next.y, next.yp, true, why)) return false;
    next.energy[0] += h / 6.0 * power_sum[0], next.energy[1] += h / 6.0 * power_sum[1];
    path.push_back(std::move(next));
  }
  return true;
}

bool ChangePointStep::state_at(double t, double* y, double* yp, double* energy, std::string& why) const {
  std::size_t from = 0;
  while (from + 1 < path_.size() && path_[from + 1].t <= t) ++from;
  std::vector<Point> path = {path_[from]};
  if (t > path.back().t && !march(t, path, why)) return false;
  const Point& p = path.back();
  std::copy(p.y.begin(), p.y.end(), y);
  std::copy(p.yp.begin(), p.yp.end(), yp);
  energy[0] += p.energy[0], energy[1] += p.energy[1];
  return true;
}

}  // namespace mbgrt::detail
