#include "constraints.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "error_weights.hpp"
#include "newton_detail.hpp"
#include "report.hpp"

namespace mbgrt::detail {

namespace {

using namespace newton;

/// One Gauss-Newton phase: drives entries [row0, row0 + rows) of the
/// constraint vector to zero by moving y[cols]. Each step is the minimum-norm
/// step, halved until the 2-norm of the residual falls; a phase that finds no
/// such step has stagnated (an inconsistent set of constraints).
struct Phase {
  Index row0 = 0, rows = 0;
  std::vector<Index> cols;
  double tol = 0.0;
  bool to_rounding = false;  ///< beyond tol, on while a step still lowers the residual
  // results
  int iterations = 0;
  bool converged = false;
  double residual = 0.0;
  Index worst = 0;  ///< row (relative to row0) with the largest |residual|
};

/// `jacobian(y, J)` gives the phase's rows' derivatives by its columns.
template <class Eval, class Jacobian>
void run_phase(Eval& eval, Jacobian&& jacobian, Vec& y, Vec& c, Phase& ph) {
  Vec trial_y(y.size()), trial_c(c.size());
  for (;;) {
    ph.residual = max_abs(c.segment(ph.row0, ph.rows), &ph.worst);
    ph.converged = ph.residual <= ph.tol;
    if (ph.converged && !ph.to_rounding) return;
    if (ph.iterations >= kAssemblyMaxIterations || ph.cols.empty() || ph.residual == 0.0) return;
    Mat J;
    if (!jacobian(y, J)) return;
    const Vec step = min_norm_step(J, c.segment(ph.row0, ph.rows));
    const double norm0 = c.segment(ph.row0, ph.rows).norm();
    bool accepted = false;
    double alpha = 1.0;
    for (int halvings = 0; halvings < 40 && !accepted; ++halvings, alpha *= 0.5) {
      trial_y = y;
      for (std::size_t k = 0; k < ph.cols.size(); ++k)
        trial_y[ph.cols[k]] += alpha * step[ix(k)];
      accepted = eval(trial_y, trial_c) && trial_c.segment(ph.row0, ph.rows).norm() < norm0;
    }
    ++ph.iterations;
    if (!accepted) return;
    y = trial_y;
    c = trial_c;
    // past the tolerance, only steps that at least halve the residual pay
    if (ph.converged && !(trial_c.segment(ph.row0, ph.rows).norm() <= 0.5 * norm0)) {
      ph.residual = max_abs(c.segment(ph.row0, ph.rows), &ph.worst);
      return;
    }
  }
}

std::string quoted_constraint(const Model& model, std::size_t i) {
  return fmt::format("`{}`", model.constraint_name(i));
}

}  // namespace

std::vector<std::size_t> ConstraintShape::states_with(UnknownRole r) const {
  std::vector<std::size_t> out;
  for (std::size_t j = 0; j < ns && j < role.size(); ++j)
    if (role[j] == r) out.push_back(j);
  return out;
}

ConstraintShape constraint_shape(const Model& model) {
  ConstraintShape s;
  s.n = model.size();
  s.dae = model.is_dae();
  s.ns = s.dae ? model.state_count() : s.n;
  s.np = model.position_constraint_count();
  s.nv = model.velocity_constraint_count();
  s.enforced = model.constraints_enforced();
  if (!s.any()) return s;
  for (std::size_t i = 0; i < s.n; ++i) s.role.push_back(model.unknown_role(i));
  if (s.dae)
    for (std::size_t k = 0; k < s.np; ++k) {
      s.lambda_at.push_back(model.multiplier_index(k));
      s.mu_at.push_back(model.stabiliser_index(k));
    }
  model.constraint_jacobian_pattern(s.g_row_starts, s.g_columns);
  return s;
}

namespace {

const char* role_name(UnknownRole r) {
  switch (r) {
    case UnknownRole::unspecified: return "unspecified";
    case UnknownRole::position: return "a position";
    case UnknownRole::velocity: return "a velocity";
    case UnknownRole::algebraic: return "algebraic";
    case UnknownRole::multiplier: return "a multiplier";
    case UnknownRole::stabiliser: return "a stabiliser";
  }
  return "?";
}

bool is_state_role(UnknownRole r) { return r == UnknownRole::position || r == UnknownRole::velocity; }

/// What the layout (roles, multipliers, G's pattern) gets wrong, or empty.
std::string layout_violation(const Model& model, const ConstraintShape& s) {
  for (std::size_t i = 0; i < s.n; ++i) {
    const UnknownRole r = s.role[i];
    const bool state = i < s.ns;
    if (r == UnknownRole::unspecified || is_state_role(r) != state)
      return fmt::format("unknown_role() says '{}' (entry {}) is {}, but it is {}", model.variable_name(i), i,
                         role_name(r), state ? "a state (a position or a velocity)" : "an algebraic unknown");
  }
  for (std::size_t k = 0; k < s.lambda_at.size(); ++k)
    for (auto [at, role] : {std::pair{s.lambda_at[k], UnknownRole::multiplier}, {s.mu_at[k], UnknownRole::stabiliser}})
      if (at >= 0 && (static_cast<std::size_t>(at) >= s.n || s.role[static_cast<std::size_t>(at)] != role))
        return fmt::format("constraint '{}' puts its {} at entry {}, which unknown_role() does not call {}",
                           model.constraint_name(k), role_name(role), at, role_name(role));
  std::vector<int> claimed(s.n, 0);
  for (std::size_t k = 0; k < s.lambda_at.size(); ++k)
    for (long at : {s.lambda_at[k], s.mu_at[k]})
      if (at >= 0 && ++claimed[static_cast<std::size_t>(at)] > 1)
        return fmt::format("two constraint rows put a multiplier at entry {} ('{}')", at,
                           model.variable_name(static_cast<std::size_t>(at)));
  for (std::size_t i = 0; i < s.n; ++i)
    if ((s.role[i] == UnknownRole::multiplier || s.role[i] == UnknownRole::stabiliser) && claimed[i] == 0)
      return fmt::format("unknown_role() calls '{}' (entry {}) {}, but no constraint row puts its multiplier there",
                         model.variable_name(i), i, role_name(s.role[i]));
  if (s.np == 0) return {};
  if (s.g_row_starts.size() != s.np + 1 || s.g_row_starts.front() != 0 ||
      s.g_row_starts.back() != static_cast<long>(s.g_columns.size()))
    return fmt::format("constraint_jacobian_pattern() gives {} row starts for {} position constraints (expected {}, "
                       "the last one the number of entries)",
                       s.g_row_starts.size(), s.np, s.np + 1);
  for (std::size_t r = 0; r < s.np; ++r) {
    if (s.g_row_starts[r] > s.g_row_starts[r + 1])
      return fmt::format("constraint_jacobian_pattern(): the row starts decrease at row {}", r);
    for (long e = s.g_row_starts[r]; e < s.g_row_starts[r + 1]; ++e) {
      const long j = s.g_columns[static_cast<std::size_t>(e)];
      if (j < 0 || static_cast<std::size_t>(j) >= s.ns ||
          (e > s.g_row_starts[r] && j <= s.g_columns[static_cast<std::size_t>(e - 1)]))
        return fmt::format("constraint_jacobian_pattern(): row {} ('{}') lists column {}, not an ascending state index",
                           r, model.constraint_name(r), j);
      if (s.role[static_cast<std::size_t>(j)] != UnknownRole::position)
        return fmt::format("constraint '{}' reads '{}', which unknown_role() calls {}: a position constraint reads "
                           "positions only",
                           model.constraint_name(r), model.variable_name(static_cast<std::size_t>(j)),
                           role_name(s.role[static_cast<std::size_t>(j)]));
    }
  }
  return {};
}

}  // namespace

std::string contract_violation(const Model& model, const ConstraintShape& s,
                               const std::vector<double>& ids) {
  if (!s.any()) return {};
  auto broken = [&](const std::string& what) {
    return fmt::format("model '{}' breaks the runtime contract: {}", model.name(), what);
  };
  if (s.ns > s.n) return broken(fmt::format("state_count() = {} exceeds size() = {}", s.ns, s.n));
  if (s.dae)
    for (std::size_t i = 0; i < s.n && i < ids.size(); ++i)
      if ((ids[i] != 0.0) != (i < s.ns))
        return broken(fmt::format(
            "y must be [states; algebraic unknowns] with state_count() = {} states first, but differential_ids() "
            "marks '{}' (entry {}) as {}",
            s.ns, model.variable_name(i), i, ids[i] != 0.0 ? "differential" : "algebraic"));
  if (std::string what = layout_violation(model, s); !what.empty()) return broken(what);
  return {};
}

RowRole residual_row_role(const ConstraintShape& s, std::size_t row) {
  for (std::size_t k = 0; k < s.lambda_at.size(); ++k) {
    if (s.lambda_at[k] == static_cast<long>(row)) return {RowRole::velocity_constraint, k};
    if (s.mu_at[k] == static_cast<long>(row)) return {RowRole::position_constraint, k};
  }
  return {RowRole::equation, row};
}

std::string residual_row_name(const Model& model, const ConstraintShape& s, std::size_t row) {
  const RowRole r = residual_row_role(s, row);
  switch (r.kind) {
    case RowRole::velocity_constraint: return fmt::format("constraint '{}'", model.constraint_name(s.np + r.row));
    case RowRole::position_constraint: return fmt::format("constraint '{}'", model.constraint_name(r.row));
    case RowRole::equation: break;
  }
  return fmt::format("the equation of '{}'", model.variable_name(row));
}

std::string joint_row_name(const Model& model, std::size_t row) {
  std::string name = model.constraint_name(row);
  if (name.size() > 2 && name.compare(name.size() - 2, 2, " g") == 0) name.resize(name.size() - 2);
  return name;
}

void pin_redundant_multipliers(const ConstraintShape& s, const double* y, double* r) {
  for (std::size_t k : s.redundant)
    for (long at : {s.lambda_at[k], s.mu_at[k]})
      if (at >= 0) r[at] = y[at];
}

void constrained_residual(Model& model, const ConstraintShape& s, double t, const double* y,
                          const double* yp, double* r) {
  model.residual(t, y, yp, r);
  pin_redundant_multipliers(s, y, r);
}

RedundancyReport find_redundant_constraints(Model& model, const ConstraintShape& s, double t,
                                            const double* y_in) {
  RedundancyReport rep;
  const Index np = ix(s.np);
  if (s.lambda_at.empty() || np == 0) return rep;
  const Vec y = Eigen::Map<const Vec>(y_in, ix(s.n));
  std::vector<Index> all(s.ns);
  for (std::size_t j = 0; j < s.ns; ++j) all[j] = ix(j);
  Mat G;
  if (!SymbolicG{model, s, t}(y, all, G)) return rep;
  // Gram-Schmidt over the equilibrated gradients, in row order, so the rows
  // dropped are the later ones (normally those of the loop-closing joint).
  Mat basis(ix(s.ns), 0);
  rep.smallest_kept = kInf;
  for (Index k = 0; k < np; ++k) {
    if (s.lambda_at[sz(k)] < 0) continue;  // penalty rows are forces, never singular
    ++rep.lagrange_rows;
    Vec v = G.row(k).transpose();
    const double big = v.cwiseAbs().maxCoeff();
    if (big == 0.0) continue;  // depends on no state: assembly has reported it if violated
    v /= v.norm();
    for (int pass = 0; pass < 2; ++pass) v -= basis * (basis.transpose() * v);  // twice: stable
    const double left = v.norm();
    if (left < kRedundantRowThreshold) {
      rep.redundant.push_back(sz(k));
      continue;
    }
    rep.smallest_kept = std::min(rep.smallest_kept, left);
    basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
    basis.col(basis.cols() - 1) = v / left;
  }
  return rep;
}

std::string rank_loss_note(Model& model, const ConstraintShape& shape, double t0, const double* y0, double t,
                           const double* y) {
  if (shape.lambda_at.empty()) return {};
  const RedundancyReport then = find_redundant_constraints(model, shape, t0, y0);
  const RedundancyReport now = find_redundant_constraints(model, shape, t, y);
  if (now.redundant.size() <= then.redundant.size() && now.smallest_kept >= 0.05 * then.smallest_kept) return {};
  return fmt::format(
      "at t = {:.6g} s the joints' constraint rows are close to losing rank (the least independent row "
      "kept {:.2g} of its norm, {:.2g} at the start): the mechanism is at or near a singular configuration - "
      "a dead point, or links aligned - where the joints alone do not determine the motion",
      t, now.smallest_kept, then.smallest_kept);
}

AssemblyReport assemble(Model& model, const ConstraintShape& s, double t, double* y_io, bool to_rounding) {
  AssemblyReport rep;
  const Index n = ix(s.n), np = ix(s.np), nv = ix(s.nv);
  Vec y = Eigen::Map<const Vec>(y_io, n);
  const Vec y_start = y;
  Vec c(np + nv);
  auto eval = [&](const Vec& yy, Vec& cc) {
    model.constraints(t, yy.data(), cc.data());
    return cc.allFinite();
  };

  if (!eval(y, c)) {
    Index bad = 0;
    max_abs(c, &bad);
    rep.error = fmt::format(
        "assembly failed: constraint {} is {} at the initial values (t = {} s); check the initial "
        "joint coordinates",
        quoted_constraint(model, sz(bad)), std::isnan(c[bad]) ? "NaN" : "infinite", format_time(t));
    return rep;
  }

  // The positions g reads (the columns of G's pattern) and the velocities:
  // the model's layout.
  std::vector<Index> positions, velocities;
  {
    std::vector<bool> read(s.ns, false);
    for (long j : s.g_columns) read[static_cast<std::size_t>(j)] = true;
    for (std::size_t j : s.states_with(UnknownRole::position))
      if (read[j]) positions.push_back(ix(j));
    for (std::size_t j : s.states_with(UnknownRole::velocity)) velocities.push_back(ix(j));
  }
  rep.position_states = positions.size();
  rep.velocity_states = velocities.size();
  SymbolicG symbolic{model, s, t};
  auto position_jacobian = [&](const Vec& yy, Mat& J) { return symbolic(yy, positions, J); };

  // (a) positions
  Phase pos;
  pos.row0 = 0;
  pos.rows = np;
  pos.cols = positions;
  pos.to_rounding = to_rounding;
  if (np > 0) {
    Mat Jp;
    if (!position_jacobian(y, Jp)) {
      rep.error = fmt::format(
          "assembly failed: the derivative of a position constraint is not finite at the initial values (t = {} "
          "s); check the initial joint coordinates",
          format_time(t));
      return rep;
    }
    pos.tol = 1e-12 * (1.0 + term_scale(Jp, y, positions));
    run_phase(eval, position_jacobian, y, c, pos);
  }
  rep.position_iterations = pos.iterations;
  if (np > 0 && !pos.converged) {
    rep.error = fmt::format(
        "assembly failed: constraint {} residual {} after {} iterations — the joints cannot all be "
        "closed from the given joint coordinates; check lengths and initial angles",
        quoted_constraint(model, sz(pos.worst)), g2(pos.residual), pos.iterations);
    return rep;
  }

  // (b) velocities: gdot is affine in them.
  Phase vel;
  vel.row0 = np;
  vel.rows = nv;
  vel.cols = velocities;
  vel.to_rounding = to_rounding;
  auto velocity_jacobian = [&](const Vec& yy, Mat& J) {
    Linearization L = linearize(eval, yy, np + nv, np, nv, velocities);
    J = std::move(L.J);
    return L.finite;
  };
  if (nv > 0) {
    Mat Jv;
    vel.tol = 1e-12 * (1.0 + (velocity_jacobian(y, Jv) ? term_scale(Jv, y, velocities) : 0.0));
    run_phase(eval, velocity_jacobian, y, c, vel);
    if (!vel.converged) {
      rep.velocity_iterations = vel.iterations;
      rep.error = fmt::format(
          "assembly failed: velocity constraint {} residual {} after {} iterations — the initial "
          "velocities cannot be made to satisfy the joints; check the initial rates and any joint "
          "drivers",
          quoted_constraint(model, s.np + sz(vel.worst)), g2(vel.residual), vel.iterations);
      return rep;
    }
  }
  rep.velocity_iterations = vel.iterations;

  rep.g_residual = max_abs(c.segment(0, np));
  rep.gdot_residual = max_abs(c.segment(np, nv));
  for (Index j : positions)
    rep.moved_positions = std::max(rep.moved_positions, std::abs(y[j] - y_start[j]));
  for (Index j : velocities)
    rep.moved_velocities = std::max(rep.moved_velocities, std::abs(y[j] - y_start[j]));
  std::copy(y.data(), y.data() + n, y_io);
  rep.ok = true;
  return rep;
}

ConstraintMonitor::ConstraintMonitor(Model& model, const ConstraintShape& shape)
    : model_(model), shape_(shape), c_(shape.count()) {}

void ConstraintMonitor::observe(double t, const double* y) {
  ++points_;
  if (!shape_.any()) return;
  model_.constraints(t, y, c_.data());
  auto scan = [&](std::size_t from, std::size_t count, double& last, Peak& peak) {
    last = 0.0;
    for (std::size_t i = from; i < from + count; ++i) {
      const double a = std::isfinite(c_[i]) ? std::abs(c_[i]) : kInf;
      last = std::max(last, a);
      if (a > peak.value) peak = Peak{a, i, t};
    }
  };
  scan(0, shape_.np, last_g_, g_);
  scan(shape_.np, shape_.nv, last_gdot_, gdot_);
}

std::string describe(const AssemblyReport& a) {
  return fmt::format(
      "|g| {}, |gdot| {} after {} iterations ({} position, {} velocity); moved positions by {}, "
      "velocities by {}",
      g2(a.g_residual), g2(a.gdot_residual), a.position_iterations + a.velocity_iterations,
      a.position_iterations, a.velocity_iterations, g2(a.moved_positions), g2(a.moved_velocities));
}

std::string describe(const RedundancyReport& r, const Model& model) {
  std::vector<std::string> names;
  for (std::size_t k : r.redundant) {
    if (names.size() == 12) {
      names.push_back(fmt::format("and {} more", r.redundant.size() - 12));
      break;
    }
    names.push_back(joint_row_name(model, k));
  }
  return fmt::format(
      "{} of {} lagrange rows implied by the others at the assembled state ({}); their multipliers "
      "are held at 0, so the other rows carry those reactions",
      r.redundant.size(), r.lagrange_rows, fmt::join(names, ", "));
}

std::string describe(const ConstraintMonitor& m) {
  const ConstraintShape& s = m.shape();
  auto part = [&](const char* level, const ConstraintMonitor::Peak& p) {
    if (p.value < 0.0) return std::string();
    return fmt::format("{} {} ({} at t = {} s)", level, g2(p.value), m.model().constraint_name(p.index),
                       format_time(p.t));
  };
  std::string parts;
  for (std::string piece : {part("position", m.position()), part("velocity", m.velocity())})
    if (!piece.empty()) parts += (parts.empty() ? "" : ", ") + piece;
  return fmt::format("{}: {}", s.enforced ? "constraint drift" : "largest constraint violation",
                     parts.empty() ? "no output points" : parts);
}

double held_row_bound(const Settings& s) {
  return std::min(kHeldFactor * (std::max(s.rtol, ErrorWeights::kResolvedRtol) + s.atol), kHeldCeiling);
}

}  // namespace mbgrt::detail
