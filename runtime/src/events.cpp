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
  roots_at_instant_ = 0;
  last_t_.assign(n_, std::nan(""));
  last_dt_.assign(n_, std::nan(""));
  shrinking_.assign(n_, 0);
  zeno_event_ = -1;
  if (n_ == 0) return true;
  if (!functions(t, y, yp, g_.data())) return false;
  // An argument that is exactly 0 at the start (ramp(0), a table of time
  // from t = 0) takes the side it moves to: its sign a moment later, the
  // state held. The integrators' root finding never reports a root at the
  // start, so a wrong side here would never be corrected.
  bool on_edge = false;
  for (std::size_t k = 0; k < n_; ++k) on_edge = on_edge || (g_[k] == 0.0 && contacts_.of_event(k) < 0);
  std::vector<double> later;
  if (on_edge) {
    later.resize(n_);
    if (!functions(t + 1e-9 * std::max(1.0, std::abs(t)), y, yp, later.data())) return false;
  }
  for (std::size_t k = 0; k < n_; ++k)
    if (contacts_.of_event(k) < 0) model_.set_event_mode(k, (g_[k] == 0.0 && later[k] != 0.0 ? later[k] : g_[k]) >= 0.0);
  contacts_.start(t, y, yp);
  return true;
}

void Events::save(std::vector<double>& out) const {
  out.push_back(jumped_energy_);
  out.push_back(instant_);
  out.push_back(static_cast<double>(at_instant_));
  out.push_back(root_instant_);
  out.push_back(static_cast<double>(roots_at_instant_));
  out.push_back(static_cast<double>(zeno_event_));
  for (std::size_t k = 0; k < n_; ++k) {
    out.push_back(k < last_t_.size() ? last_t_[k] : std::nan(""));
    out.push_back(k < last_dt_.size() ? last_dt_[k] : std::nan(""));
    out.push_back(k < shrinking_.size() ? static_cast<double>(shrinking_[k]) : 0.0);
    out.push_back(g_[k]);
  }
  for (std::size_t c = 0; c < contacts_.count(); ++c) {
    out.push_back(contacts_.closed(c) ? 1.0 : 0.0);
    out.push_back(contacts_.stuck(c) ? 1.0 : 0.0);
  }
}

void Events::restore(const double*& in) {
  jumped_energy_ = *in++;
  instant_ = *in++;
  at_instant_ = static_cast<long>(*in++);
  root_instant_ = *in++;
  roots_at_instant_ = static_cast<long>(*in++);
  zeno_event_ = static_cast<long>(*in++);
  last_t_.assign(n_, 0.0);
  last_dt_.assign(n_, 0.0);
  shrinking_.assign(n_, 0);
  for (std::size_t k = 0; k < n_; ++k) {
    last_t_[k] = *in++;
    last_dt_[k] = *in++;
    shrinking_[k] = static_cast<long>(*in++);
    g_[k] = *in++;
  }
  for (std::size_t c = 0; c < contacts_.count(); ++c) {
    const bool closed = *in++ != 0.0;
    const bool stuck = *in++ != 0.0;
    contacts_.restore(c, closed, stuck);
  }
}

bool Events::fire(double t, std::size_t k, bool on, double* y) {
  if (!count_jumped_energy_) return switch_and_jump(t, k, on, y);
  // the energy a jump takes (an impact's, by Newton's law) is the witness's,
  // not an integration error
  double before = 0.0, after = 0.0;
  model_.stored_energy(t, y, nullptr, &before);
  const bool fired = switch_and_jump(t, k, on, y);
  model_.stored_energy(t, y, nullptr, &after);
  jumped_energy_ += before - after;
  return fired;
}

bool Events::switch_and_jump(double t, std::size_t k, bool on, double* y) {
  if (const long c = contacts_.of_event(k); c >= 0) {
    const auto i = static_cast<std::size_t>(c);
    const bool friction = contacts_.is_friction_event(k);
    const ContactSwitch s = friction ? contacts_.fire_friction(t, i, on, y) : contacts_.fire(t, i, on, y);
    if (s.kind == ContactSwitch::None) return false;
    record(t, k, friction ? s.kind == ContactSwitch::Stick : contacts_.closed(i),
           s.kind == ContactSwitch::Bounce || s.kind == ContactSwitch::Rest || s.kind == ContactSwitch::Stop,
           Contacts::describe(s), Contacts::state(s));
    return true;
  }
  if (!model_.set_event_mode(k, on)) return false;
  record(t, k, on, model_.event_jump(k, on, t, y), {});
  return true;
}

void Events::record(double t, std::size_t k, bool on, bool jump, std::string note, const char* what) {
  // One instant: equal times, up to the rounding of a located root.
  if (!log_.empty() && std::abs(t - instant_) <= 1e-12 * std::max(1.0, std::abs(t))) {
    ++at_instant_;
  } else {
    instant_ = t;
    at_instant_ = 1;
  }
  log_.push_back({t, k, on, jump, std::move(note), what});
  const double dt = t - last_t_[k];
  shrinking_[k] = dt < last_dt_[k] ? shrinking_[k] + 1 : 0;  // (false while either is NaN)
  last_t_[k] = t;
  last_dt_[k] = dt;
  if (shrinking_[k] >= kZenoCount && dt <= kZenoInterval * std::max(1.0, std::abs(t)) && zeno_event_ < 0)
    zeno_event_ = static_cast<long>(k);
}

void Events::note_roots(double t) {
  if (roots_at_instant_ > 0 && std::abs(t - root_instant_) <= 1e-12 * std::max(1.0, std::abs(t))) {
    ++roots_at_instant_;
  } else {
    root_instant_ = t;
    roots_at_instant_ = 1;
  }
}

std::string Events::describe(const EventRecord& e) const {
  if (e.what)  // a contact: its note says what happened (an impact is the jump)
    return fmt::format("t = {:.9g} s: {}: {}", e.t, model_.event_name(e.index), e.note);
  return fmt::format("t = {:.9g} s: {} {}{}{}", e.t, model_.event_name(e.index), e.on ? "on" : "off", e.jump ? ", jump" : "",
                     e.note.empty() ? "" : ": " + e.note);
}

bool chatter_failure(const Events& events, double t, SolverFailure& failure) {
  if (events.accumulating()) {
    const std::size_t k = events.accumulating_event();
    failure = SolverFailure{t, "EVENTS_ACCUMULATE",
                            fmt::format("events accumulate (Zeno): `{}` switched {} times in a row, each sooner after the "
                                        "one before, the last {:.3g} s apart, at t = {:.9g} s; its switches would never end (a "
                                        "bouncing ball that loses energy at every impact): a model must let it rest there",
                                        events.model_name(k), Events::kZenoCount + 1, events.last_interval(k), t),
                            {}, -1};
    return false;
  }
  if (!events.chattering()) return true;
  if (events.log().empty()) {
    failure = SolverFailure{t, "EVENTS_CHATTER",
                            fmt::format("the root finder reported more than {} crossings at t = {:.9g} s without any "
                                        "event switching", Events::kMaxAtOneInstant, t),
                            {}, -1};
    return false;
  }
  const EventRecord& last = events.log().back();
  failure = SolverFailure{t, "EVENTS_CHATTER",
                          fmt::format("more than {} events at one instant, the last {}: a mode that switches "
                                      "itself back (the step's argument jumps across zero when it switches)",
                                      Events::kMaxAtOneInstant, events.describe(last)),
                          {}, -1};
  return false;
}

bool fire_events(Events& events, double t, double* y, const std::vector<int>& root_info, SolverFailure& failure) {
  events.note_roots(t);
  for (std::size_t k = 0; k < root_info.size(); ++k)
    if (root_info[k] != 0) events.fire(t, k, root_info[k] > 0, y);
  return chatter_failure(events, t, failure);
}

void add_counts(SolverStats& st, const SolverStats& before) {
  auto add = [](long& a, long b) {
    if (a >= 0 && b > 0) a += b;
  };
  add(st.steps, before.steps);
  add(st.rhs_evals, before.rhs_evals);
  add(st.fd_jac_evals, before.fd_jac_evals);
  add(st.position_evals, before.position_evals);
  add(st.jac_evals, before.jac_evals);
  add(st.nonlin_iters, before.nonlin_iters);
  add(st.nonlin_conv_fails, before.nonlin_conv_fails);
  add(st.err_test_fails, before.err_test_fails);
}

}  // namespace mbgrt::detail
