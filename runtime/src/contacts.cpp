#include "contacts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mbgrt::detail {

double hunt_crossley_chi(double e) {
  if (!(e > 0.0)) return std::numeric_limits<double>::infinity();  // a plastic contact: unbounded damping
  if (e >= 1.0) return 0.0;
  // f(x) = h(x) - h(-x e), h(x) = x - ln(1 + x): positive near 0 (~ x^2 (1 - e^2) / 2), -> -inf at 1/e.
  auto f = [e](double x) { return x - std::log1p(x) + x * e + std::log1p(-x * e); };
  double lo = 0.0, hi = 1.0 / e;
  // the positive lobe: start the bracket past the root at 0
  double x = 0.5 / e;
  while (f(x) <= 0.0 && x > 1e-12) {
    hi = x;
    x *= 0.5;
  }
  lo = x;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

Contacts::Contacts(Model& model) : m_(model) {
  const std::size_t n = m_.contact_count();
  info_.resize(n);
  closed_.assign(n, 0);
  contact_of_event_.assign(m_.event_count(), -1);
  for (std::size_t c = 0; c < n; ++c) {
    info_[c] = m_.contact(c);
    if (info_[c].event < contact_of_event_.size()) contact_of_event_[info_[c].event] = static_cast<long>(c);
  }
  v_.resize(n);
  g_.resize(m_.event_count());
}

void Contacts::set_closed(std::size_t c, bool on) {
  closed_[c] = on ? 1 : 0;
  m_.set_event_mode(info_[c].event, on);
}

void Contacts::open_lifted(double t, const double* y, std::size_t c) {
  set_closed(c, false);
  m_.set_contact_lift(c, 0.0);
  m_.set_contact_lift(c, std::max(0.0, kLift - event_function(t, y, c)));
}

double Contacts::speed(double t, const double* y, std::size_t c) {
  m_.contact_speeds(t, y, nullptr, v_.data());
  return v_[c];
}

double Contacts::event_function(double t, const double* y, std::size_t c) {
  m_.event_functions(t, y, nullptr, g_.data());
  return g_[info_[c].event];
}

void Contacts::start(double t, const double* y, const double* yp) {
  const std::size_t n = info_.size();
  for (std::size_t c = 0; c < n; ++c) {
    info_[c] = m_.contact(c);  // (its restitution is the run's: initial() computed it)
    m_.set_contact_bias(c, 0.0);
    m_.set_contact_lift(c, 0.0);
    m_.set_contact_damping(c, 0.0);
    set_closed(c, false);
  }
  if (n == 0) return;
  m_.event_functions(t, y, yp, g_.data());
  m_.contact_speeds(t, y, yp, v_.data());
  const std::vector<double> gap = g_;
  for (std::size_t c = 0; c < n; ++c) {
    const double g = gap[info_[c].event];
    if (info_[c].compliant) {
      if (g < 0.0) {
        m_.set_contact_damping(c, hunt_crossley_chi(info_[c].restitution) / std::max(-v_[c], kMinApproachSpeed));
        set_closed(c, true);
      }
    } else if (g <= 0.0) {
      set_closed(c, true);
    }
  }
  // a unilateral contact that starts closed but would pull is open
  m_.event_functions(t, y, yp, g_.data());
  for (std::size_t c = 0; c < n; ++c)
    if (!info_[c].compliant && closed(c) && g_[info_[c].event] < 0.0) set_closed(c, false);
}

ContactSwitch Contacts::fire(double t, std::size_t c, bool rising, double* y) {
  const bool is_closed = closed(c);
  if (info_[c].compliant) {
    if (!is_closed && !rising) {
      const double v = speed(t, y, c);
      m_.set_contact_damping(c, hunt_crossley_chi(info_[c].restitution) / std::max(-v, kMinApproachSpeed));
      set_closed(c, true);
      return {ContactSwitch::Close, -v};
    }
    if (is_closed && rising) {
      set_closed(c, false);
      return {ContactSwitch::Open, 0.0};
    }
    return {};
  }
  if (!is_closed && !rising) return impact(t, c, y);
  if (is_closed && !rising) {
    open_lifted(t, y, c);
    return {ContactSwitch::Release, 0.0};
  }
  return {};
}

ContactSwitch Contacts::impact(double t, std::size_t c, double* y) {
  const double v = speed(t, y, c);
  if (!(v < 0.0)) return {};  // grazing: nothing to stop
  const std::size_t n = m_.size();
  d0_.resize(n);
  d1_.resize(n);
  y1_.resize(n);
  // The approach acceleration while open, for the rest test (a difference
  // along the motion: a threshold needs no more).
  m_.derivative(t, y, d0_.data());
  const double h = 1e-6 * std::max(1.0, std::abs(t));
  for (std::size_t i = 0; i < n; ++i) y1_[i] = y[i] + h * d0_[i];
  const double a = (speed(t + h, y1_.data(), c) - v) / h;
  const double e = info_[c].restitution;
  const double flight = a < 0.0 ? 2.0 * e * -v / -a : std::numeric_limits<double>::infinity();
  const bool rest = flight < kRestFlight * std::max(1.0, std::abs(t));
  // dy per unit of normal speed: the closed row's response to its bias.
  constexpr double kProbe = 1e6;
  set_closed(c, true);
  m_.set_contact_bias(c, 0.0);
  m_.derivative(t, y, d0_.data());
  m_.set_contact_bias(c, kProbe);
  m_.derivative(t, y, d1_.data());
  m_.set_contact_bias(c, 0.0);
  const double dv = rest ? -v : -(1.0 + e) * v;
  for (std::size_t i = 0; i < n; ++i) y[i] += dv * (d1_[i] - d0_[i]) / kProbe;
  if (!rest) {
    open_lifted(t, y, c);
    return {ContactSwitch::Bounce, -v};
  }
  if (event_function(t, y, c) < 0.0) open_lifted(t, y, c);  // at rest, but nothing presses it on
  return {ContactSwitch::Rest, -v};
}

std::string Contacts::describe(const ContactSwitch& s) {
  switch (s.kind) {
    case ContactSwitch::Bounce: return fmt::format("impact at {:.6g} m/s: bounces", s.speed);
    case ContactSwitch::Rest: return fmt::format("impact at {:.6g} m/s: comes to rest (its rebound would be shorter than {:g} s)",
                                                 s.speed, kRestFlight);
    case ContactSwitch::Close: return fmt::format("closes at {:.6g} m/s", s.speed);
    case ContactSwitch::Release: return "released (its normal force would pull)";
    case ContactSwitch::Open: return "opens";
    case ContactSwitch::None: break;
  }
  return {};
}

}  // namespace mbgrt::detail
