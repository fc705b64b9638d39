#include "guard.hpp"

#include <fmt/format.h>

#include <cmath>
#include <algorithm>
#include <limits>
#include <exception>

namespace mbgrt::detail {

namespace {

const char* value_word(double v) {
  if (std::isnan(v)) return "NaN";
  return v > 0 ? "+Inf" : "-Inf";
}

}  // namespace

GuardedModel::GuardedModel(Model& model)
    : model_(model),
      n_(model.size()),
      witness_broken_at_(std::nan("")),
      dae_(model.is_dae()),
      ids_(n_, 1.0),
      shape_(mbgrt::detail::constraint_shape(model)),
      events_(model) {
  if (dae_) model_.differential_ids(ids_.data());
  limits_.reserve(n_);
  for (std::size_t i = 0; i < n_; ++i) limits_.push_back(model_.state_limit(i));
  // (the largest finite double where there is no limit: an infinity is then beyond it, as a NaN is)
  for (double l : limits_) bounds_.push_back(std::min(l, kLargest));
}

namespace {
/// Whether |v[i]| <= bound(i) for every i: false at an infinity or a NaN
/// where the bound is finite. One loop without an early exit: it runs on
/// every state and every derivative.
template <class Bound>
bool within(const double* v, std::size_t n, Bound&& bound) {
  unsigned ok = 1;
  for (std::size_t i = 0; i < n; ++i) ok &= static_cast<unsigned>(std::abs(v[i]) <= bound(i));
  return ok != 0;
}
}  // namespace

std::size_t GuardedModel::first_non_finite(const double* v) const {
  if (within(v, n_, [](std::size_t) { return kLargest; })) return n_;
  for (std::size_t i = 0; i < n_; ++i)
    if (!std::isfinite(v[i])) return i;
  return n_;
}

int GuardedModel::record(double t, BlameSite site, std::size_t index, double value,
                         std::string detail) {
  if (!blame_) blame_ = Blame{t, site, index, value, std::move(detail)};
  return -1;
}

int GuardedModel::derivative(double t, const double* y, double* ydot, InputCheck check, double* rate) {
  // A non-finite input means an earlier step already went wrong; blaming the
  // state itself points the user at the real culprit, not at its consumers.
  if (check == InputCheck::before)
    if (std::size_t i = first_non_finite(y); i < n_) return record(t, BlameSite::state, i, y[i]);
  const int status = rates(t, y, ydot, [&] {
    if (rate)
      model_.derivative_and_power(t, y, ydot, rate);
    else
      model_.derivative(t, y, ydot);
  });
  if (rate) keep_finite(t, rate);
  return status;
}

int GuardedModel::position_rates(double t, const double* y, double* ydot) {
  if (!model_.has_position_rates()) return derivative(t, y, ydot, InputCheck::on_failure);
  return rates(t, y, ydot, [&] { model_.position_rates(t, y, ydot); });
}

template <class Evaluate>
int GuardedModel::rates(double t, const double* y, const double* ydot, Evaluate&& evaluate) {
  try {
    evaluate();
  } catch (const std::exception& e) {
    return record(t, BlameSite::exception, 0, 0.0, e.what());
  } catch (...) {
    return record(t, BlameSite::exception, 0, 0.0, "unknown exception");
  }
  if (std::size_t i = first_non_finite(ydot); i < n_) {
    if (std::size_t j = first_non_finite(y); j < n_) return record(t, BlameSite::state, j, y[j]);
    return record(t, BlameSite::derivative, i, ydot[i]);
  }
  return 0;
}

int GuardedModel::power(double t, const double* y, const double* yp, double* rate) {
  try {
    model_.power(t, y, yp, rate);
  } catch (...) {  // (the same exception will stop the run at its next derivative)
    rate[0] = rate[1] = std::nan("");
  }
  keep_finite(t, rate);
  return 0;
}

void GuardedModel::keep_finite(double t, double* rate) {
  for (int k = 0; k < 2; ++k)
    if (!std::isfinite(rate[k])) {
      if (std::isnan(witness_broken_at_)) witness_broken_at_ = t;
      rate[k] = 0.0;
    }
}

int GuardedModel::jacobian(double t, const double* y, double* J) {
  try {
    model_.jacobian(t, y, J);
  } catch (const std::exception& e) {
    return record(t, BlameSite::exception, 0, 0.0, e.what());
  } catch (...) {
    return record(t, BlameSite::exception, 0, 0.0, "unknown exception");
  }
  for (std::size_t k = 0; k < n_ * n_; ++k)
    if (!std::isfinite(J[k])) return record(t, BlameSite::derivative, k / n_, J[k], "in the Jacobian");
  return 0;
}

int GuardedModel::residual(double t, const double* y, const double* yp, double* r) {
  if (std::size_t i = first_non_finite(y); i < n_) return record(t, BlameSite::state, i, y[i]);
  try {
    constrained_residual(model_, shape_, t, y, yp, r);
  } catch (const std::exception& e) {
    return record(t, BlameSite::exception, 0, 0.0, e.what());
  } catch (...) {
    return record(t, BlameSite::exception, 0, 0.0, "unknown exception");
  }
  if (std::size_t i = first_non_finite(r); i < n_) return record(t, BlameSite::residual, i, r[i]);
  return 0;
}

bool GuardedModel::check_state(double t, const double* y) {
  if (within(y, n_, [&](std::size_t i) { return bounds_[i]; })) return true;  // the usual case
  if (std::size_t i = first_non_finite(y); i < n_) {
    record(t, BlameSite::state, i, y[i]);
    return false;
  }
  for (std::size_t i = 0; i < n_; ++i)
    if (std::abs(y[i]) > limits_[i]) {
      record(t, BlameSite::limit, i, y[i]);
      return false;
    }
  return true;
}

bool GuardedModel::check_constraints(double t, const double* y) {
  if (held_.empty()) return true;
  model_.constraints(t, y, rows_.data());
  for (std::size_t r = 0; r < shape_.np; ++r)
    if (!(std::abs(rows_[r]) <= bound_of(r))) {
      record(t, BlameSite::constraint, r, rows_[r]);
      return false;
    }
  return true;
}

void GuardedModel::hold_constraints(double bound, double penalty_bound) {
  held_bound_ = bound;
  penalty_bound_ = penalty_bound;
  held_.assign(shape_.np, 0);
  for (std::size_t r = 0; r < shape_.np; ++r) held_[r] = model_.constraint_held(r) ? 1 : 0;
  rows_.assign(shape_.count(), 0.0);
}

std::string GuardedModel::describe(const Blame& b) const {
  if (b.site == BlameSite::exception)
    return fmt::format("the model threw an exception: {}", b.detail);
  if (b.site == BlameSite::constraint)
    return held_[b.index] ? fmt::format("joint row {} is violated by {:.3g}, beyond the {:.3g} the run's tolerances allow a "
                                        "row that must hold",
                                        model_.constraint_name(b.index), std::abs(b.value), held_bound_)
                          : fmt::format("penalty joint row {} is stretched by {:.3g}, beyond the {:.3g} a joint may give "
                                        "(a compliance that large belongs in a spring-damper)",
                                        model_.constraint_name(b.index), std::abs(b.value), penalty_bound_);
  if (b.site == BlameSite::limit)
    return fmt::format("state '{}' = {:.6g} is beyond its limit {:.6g}: {}", model_.variable_name(b.index), b.value,
                       limits_.at(b.index), model_.state_limit_reason(b.index));
  // A constraint row of a lagrange DAE (at its multiplier's index): name the
  // constraint rather than the multiplier the row happens to share an index with.
  if (b.site == BlameSite::residual && residual_row_role(shape_, b.index).kind != RowRole::equation)
    return fmt::format("the residual of {} became {}", residual_row_name(model_, shape_, b.index),
                       value_word(b.value));
  const char* kind = ids_.at(b.index) != 0.0 ? "state" : "algebraic variable";
  std::string text =
      fmt::format("{} '{}' became {}", kind, model_.variable_name(b.index), value_word(b.value));
  if (b.site == BlameSite::derivative) text += " (derivative non-finite)";
  if (b.site == BlameSite::residual) text += " (residual non-finite)";
  return text;
}

}  // namespace mbgrt::detail
