// solvers/carry_across.cpp — an implicit method's change points of the cut
// joints, left to dopri5.
#include "solvers/carry_across.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "solvers/sundials_util.hpp"

namespace mbgrt::detail {

double cut_joint_independence(GuardedModel& model, double t, const double* y, std::vector<double>& scratch) {
  const RankLossLog* log = model.model().rank_loss();
  if (!log) return 1.0;
  scratch.resize(model.size());
  try {
    model.model().derivative(t, y, scratch.data());
  } catch (...) {
    return 1.0;
  }
  return std::sqrt(std::max(0.0, log->latest_closest()));
}

CarryAcross::CarryAcross(GuardedModel& model, const Settings& s, double t0, const double* y0)
    : model_(model), settings_(s) {
  const RankLossLog* log = model.model().rank_loss();
  if (model.is_dae() || !log) return;
  start_ = cut_joint_independence(model, t0, y0, scratch_);
  if (log->cut_joints_solved() && start_ > 0.0) watch_below_ = kWatchFrom * start_;
}

void CarryAcross::begin(double t, const double* y, const double* energy) {
  dopri5_ = make_dopri5(model_, settings_);
  dopri5_->init(t, y, nullptr);
  from_ = t;
  energy_[0] = energy ? energy[0] : 0.0, energy_[1] = energy ? energy[1] : 0.0;
  last_ = cut_joint_independence(model_, t, y, scratch_);
  target_ = std::min(kBeyond * std::max(last_, kSmallestIndependence), kHighestTarget * start_);
}

bool CarryAcross::carry(double t_out, double& t, double* y, double* energy, SolverStats& counted,
                        SolverFailure& failure) {
  for (;;) {
    if (!dopri5_->advance_to(std::min(t_out, dopri5_->t() + kProbe))) {
      failure = dopri5_->failure();
      return false;
    }
    t = dopri5_->t();
    std::copy(dopri5_->y(), dopri5_->y() + model_.size(), y);
    if (const double* e = dopri5_->energy(); e && energy) energy[0] = energy_[0] + e[0], energy[1] = energy_[1] + e[1];
    const double now = cut_joint_independence(model_, t, y, scratch_);
    const bool beyond = now > last_ && now >= target_;
    last_ = now;
    if (beyond) {
      spans_.emplace_back(from_, t);
      add_counts(counted, dopri5_->stats());
      dopri5_.reset();
      return true;
    }
    if (reached(t, t_out)) return true;
  }
}

std::vector<std::pair<double, double>> CarryAcross::spans(double t) const {
  std::vector<std::pair<double, double>> all = spans_;
  if (dopri5_) all.emplace_back(from_, t);  // (the run ended inside one)
  return all;
}

std::string CarryAcross::describe(double t) const {
  const auto all = spans(t);
  if (all.empty()) return {};
  std::vector<std::string> parts;
  for (std::size_t k = 0; k < all.size() && k < kListed; ++k)
    parts.push_back(fmt::format("t = {:.6g} to {:.6g} s", all[k].first, all[k].second));
  if (all.size() > kListed) parts.push_back(fmt::format("and {} more", all.size() - kListed));
  return fmt::format("; across {} change point{} of the cut joints, where their rows became dependent, dopri5 "
                     "carried the run at the same tolerances: {}",
                     all.size(), all.size() == 1 ? "" : "s", fmt::join(parts, ", "));
}

void CarryAcross::add_open_counts(SolverStats& st) const {
  if (dopri5_) add_counts(st, dopri5_->stats());
}

}  // namespace mbgrt::detail
