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
  stuck_.assign(n, 0);
  contact_of_event_.assign(m_.event_count(), -1);
  friction_event_.assign(m_.event_count(), 0);
  for (std::size_t c = 0; c < n; ++c) {
    info_[c] = m_.contact(c);
    if (info_[c].event < contact_of_event_.size()) contact_of_event_[info_[c].event] = static_cast<long>(c);
    if (const long k = info_[c].friction_event; k >= 0 && static_cast<std::size_t>(k) < contact_of_event_.size()) {
      contact_of_event_[static_cast<std::size_t>(k)] = static_cast<long>(c);
      friction_event_[static_cast<std::size_t>(k)] = 1;
    }
  }
  tangents_.resize(4 * n);
  v_.resize(n);
  g_.resize(m_.event_count());
}

void Contacts::set_closed(std::size_t c, bool on) {
  closed_[c] = on ? 1 : 0;
  m_.set_event_mode(info_[c].event, on);
}

void Contacts::tangents(double t, const double* y, std::size_t c, double v[2], double f[2]) {
  const std::size_t n = info_.size();
  m_.contact_tangents(t, y, nullptr, tangents_.data());
  v[0] = tangents_[2 * c];
  v[1] = tangents_[2 * c + 1];
  f[0] = tangents_[2 * n + 2 * c];
  f[1] = tangents_[2 * n + 2 * c + 1];
}

void Contacts::set_sliding(std::size_t c, double d1, double d2) {
  stuck_[c] = 0;
  m_.set_event_mode(static_cast<std::size_t>(info_[c].friction_event), false);
  m_.set_contact_slip(c, d1, d2);
}

void Contacts::set_stuck(std::size_t c) {
  stuck_[c] = 1;
  m_.set_event_mode(static_cast<std::size_t>(info_[c].friction_event), true);
  m_.set_contact_slip(c, 0.0, 0.0);
}

bool Contacts::slide_against_friction(double t, const double* y, std::size_t c) {
  double v[2], f[2];
  tangents(t, y, c, v, f);
  const double norm = std::hypot(f[0], f[1]);
  if (!(norm > 0.0)) return false;
  set_sliding(c, -f[0] / norm, -f[1] / norm);
  return true;
}

bool Contacts::slide_if_slipping(double t, const double* y, std::size_t c) {
  m_.event_functions(t, y, nullptr, g_.data());
  if (g_[static_cast<std::size_t>(info_[c].friction_event)] >= 0.0) return false;
  return slide_against_friction(t, y, c);
}

void Contacts::start_friction(double t, const double* y, std::size_t c) {
  if (!has_friction(c)) return;
  double v[2], f[2];
  tangents(t, y, c, v, f);
  const double speed = std::hypot(v[0], v[1]);
  if (speed > kStickSpeed) {
    set_sliding(c, v[0] / speed, v[1] / speed);
    return;
  }
  set_stuck(c);
  slide_if_slipping(t, y, c);
}

ContactSwitch Contacts::fire_friction(double t, std::size_t c, bool rising, double* y) {
  if (!closed(c) || rising) return {};
  if (stuck_[c]) return slide_against_friction(t, y, c) ? ContactSwitch{ContactSwitch::Slide, 0.0} : ContactSwitch{};
  set_stuck(c);
  if (slide_if_slipping(t, y, c)) return {ContactSwitch::Slide, 0.0};  // (the other way)
  return {ContactSwitch::Stick, 0.0};
}

void Contacts::normal_response(double t, std::size_t c, const double* y) {
  constexpr double kProbe = 1e6;  // (affine: any size; large, the difference is exact to rounding)
  const std::size_t n = m_.size();
  d0_.resize(n);
  d1_.resize(n);
  col_.resize(n);
  const bool was_closed = closed(c);
  set_closed(c, true);
  if (has_friction(c)) set_sliding(c, 0.0, 0.0);  // impulses are frictionless
  m_.set_contact_bias(c, 0.0);
  m_.derivative(t, y, d0_.data());
  m_.set_contact_bias(c, kProbe);
  m_.derivative(t, y, d1_.data());
  m_.set_contact_bias(c, 0.0);
  set_closed(c, was_closed);
  for (std::size_t i = 0; i < n; ++i) col_[i] = (d1_[i] - d0_[i]) / kProbe;
  // (the friction's modes are set again when the contact closes)
}

void Contacts::open_separated(double t, std::size_t c, double* y) {
  set_closed(c, false);
  const double g = event_function(t, y, c);  // open: the gap
  if (g >= kLift) return;
  // Positions moved by s times the rate change a unit of normal speed makes
  // raise the gap by s (to first order: g' is affine in the velocities).
  const std::size_t n = m_.size();
  y1_.resize(n);
  for (std::size_t i = 0; i < n; ++i) y1_[i] = y[i] + col_[i];
  m_.derivative(t, y, d0_.data());
  m_.derivative(t, y1_.data(), d1_.data());
  y1_.assign(y, y + n);
  for (double lift = kLift; lift < 1e-6; lift *= 2) {
    const double s = lift - g;
    for (std::size_t i = 0; i < n; ++i)
      if (col_[i] == 0.0) y[i] = y1_[i] + s * (d1_[i] - d0_[i]);
    if (event_function(t, y, c) > 0.0) return;
  }
}

double Contacts::speed(double t, const double* y, std::size_t c) {
  m_.contact_speeds(t, y, nullptr, v_.data());
  return v_[c];
}

double Contacts::gap(double t, const double* y, std::size_t c) {
  const bool was_closed = closed(c);
  if (was_closed) m_.set_event_mode(info_[c].event, false);
  const double g = event_function(t, y, c);
  if (was_closed) m_.set_event_mode(info_[c].event, true);
  return g;
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
    m_.set_contact_damping(c, 0.0);
    set_closed(c, false);
  }
  if (n == 0) return;
  m_.event_functions(t, y, yp, g_.data());
  m_.contact_speeds(t, y, yp, v_.data());
  start_gap_.resize(n);
  for (std::size_t c = 0; c < n; ++c) start_gap_[c] = g_[info_[c].event];
  for (std::size_t c = 0; c < n; ++c) {
    const double g = start_gap_[c];
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
  for (std::size_t c = 0; c < n; ++c)
    if (has_friction(c)) set_sliding(c, 0.0, 0.0);
  m_.event_functions(t, y, yp, g_.data());
  for (std::size_t c = 0; c < n; ++c)
    if (!info_[c].compliant && closed(c) && g_[info_[c].event] < 0.0) set_closed(c, false);
  for (std::size_t c = 0; c < n; ++c)
    if (closed(c)) start_friction(t, y, c);
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
    if (gap(t, y, c) < -kDeepestRelease) return {};  // still being pushed out: not let go inside the surface
    normal_response(t, c, y);
    open_separated(t, c, y);
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
  const bool rest = e == 0.0 || flight < kRestFlight * std::max(1.0, std::abs(t));  // (plastic: it stays)
  normal_response(t, c, y);
  const double dv = rest ? -v : -(1.0 + e) * v;
  for (std::size_t i = 0; i < n; ++i) y[i] += dv * col_[i];
  if (!rest) {
    open_separated(t, c, y);
    return {ContactSwitch::Bounce, -v};
  }
  set_closed(c, true);
  if (event_function(t, y, c) < 0.0) {  // stopped, but nothing presses it on
    open_separated(t, c, y);
    return {ContactSwitch::Stop, -v};
  }
  start_friction(t, y, c);
  return {ContactSwitch::Rest, -v};
}

std::string Contacts::describe(const ContactSwitch& s) {
  switch (s.kind) {
    case ContactSwitch::Bounce: return fmt::format("impact at {:.6g} m/s: bounces", s.speed);
    case ContactSwitch::Rest: return fmt::format("impact at {:.6g} m/s: comes to rest (its rebound would be shorter than {:g} s)",
                                                 s.speed, kRestFlight);
    case ContactSwitch::Stop:
      return fmt::format("impact at {:.6g} m/s: stops dead, and nothing presses it on", s.speed);
    case ContactSwitch::Close: return fmt::format("closes at {:.6g} m/s", s.speed);
    case ContactSwitch::Release: return "released (its normal force would pull)";
    case ContactSwitch::Open: return "opens";
    case ContactSwitch::Stick: return "sticks";
    case ContactSwitch::Slide: return "slides";
    case ContactSwitch::None: break;
  }
  return {};
}

const char* Contacts::state(const ContactSwitch& s) {
  switch (s.kind) {
    case ContactSwitch::Bounce: return "impact";
    case ContactSwitch::Rest: return "rest";
    case ContactSwitch::Stop: return "stop";
    case ContactSwitch::Close: return "close";
    case ContactSwitch::Release: return "release";
    case ContactSwitch::Open: return "open";
    case ContactSwitch::Stick: return "stick";
    case ContactSwitch::Slide: return "slide";
    case ContactSwitch::None: break;
  }
  return "";
}

}  // namespace mbgrt::detail
