#include "events.hpp"

#include "integrator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace mbgrt::detail {

bool Events::functions(double t, const double* y, const double* yp, double* g) {
  model_.event_functions(t, y, yp, g);
  return std::all_of(g, g + n_, [](double v) { return std::isfinite(v); });
}

bool Events::start(double t, const double* y, const double* yp) {
  log_.clear();
  at_instant_ = 0;
  jumped_ = false;
  if (n_ == 0) return true;
  if (!functions(t, y, yp, g_.data())) return false;
  for (std::size_t k = 0; k < n_; ++k) model_.set_event_mode(k, g_[k] >= 0.0);
  return true;
}

bool Events::fire(double t, std::size_t k, bool on, double* y) {
  if (!model_.set_event_mode(k, on)) return false;
  const bool jump = model_.event_jump(k, on, t, y);
  jumped_ = jumped_ || jump;
  // One instant: equal times, up to the rounding of a located root.
  if (!log_.empty() && std::abs(t - instant_) <= 1e-12 * std::max(1.0, std::abs(t))) {
    ++at_instant_;
  } else {
    instant_ = t;
    at_instant_ = 1;
  }
  log_.push_back({t, k, on, jump});
  return true;
}

std::string Events::describe(const EventRecord& e) const {
  return fmt::format("t = {:.9g} s: {} {}{}", e.t, model_.event_name(e.index), e.on ? "on" : "off", e.jump ? ", jump" : "");
}

bool chatter_failure(const Events& events, double t, SolverFailure& failure) {
  if (!events.chattering()) return true;
  const EventRecord& last = events.log().back();
  failure = SolverFailure{t, "EVENTS_CHATTER",
                          fmt::format("more than {} events at one instant, the last {}: a mode that switches "
                                      "itself back (the step's argument jumps across zero when it switches)",
                                      Events::kMaxAtOneInstant, events.describe(last)),
                          {}, -1};
  return false;
}

bool fire_events(Events& events, double t, double* y, const std::vector<int>& root_info, SolverFailure& failure) {
  for (std::size_t k = 0; k < root_info.size(); ++k)
    if (root_info[k] != 0) events.fire(t, k, root_info[k] > 0, y);
  events.take_jump();  // the method restarts from y whether it jumped or not
  return chatter_failure(events, t, failure);
}

void add_counts(SolverStats& st, const SolverStats& before) {
  auto add = [](long& a, long b) {
    if (a >= 0 && b > 0) a += b;
  };
  add(st.steps, before.steps);
  add(st.rhs_evals, before.rhs_evals);
  add(st.fd_jac_evals, before.fd_jac_evals);
  add(st.jac_evals, before.jac_evals);
  add(st.nonlin_iters, before.nonlin_iters);
  add(st.nonlin_conv_fails, before.nonlin_conv_fails);
  add(st.err_test_fails, before.err_test_fails);
}

}  // namespace mbgrt::detail
