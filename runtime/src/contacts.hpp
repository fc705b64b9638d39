// The model's contacts during a run (Model::contact_count): which event is
// whose, their modes at the start, and what a located crossing of a contact's
// event function does. Written once over every model and solver:
//
// * unilateral, open, gap falling through 0: an impact. Newton's law sets the
//   normal speed after it to -e times the one before, by an impulse through
//   the mass matrix: the state derivative with the contact closed is affine in
//   the row's bias b (the normal acceleration the row imposes), and so is the
//   velocity change an impulse makes; their column dy/db is the change per unit
//   of normal speed (positions do not jump). An impact whose rebound would fly
//   for less than kRestFlight (scaled by max(1, |t|)) ends plastically and
//   closes the contact: it comes to rest (Zeno's accumulation avoided).
// * unilateral, closed, normal force falling through 0: released (opens),
//   unless it is still deeper than kDeepestRelease (a start inside).
// * compliant, gap falling through 0: closes, Hunt-Crossley's damping set from
//   the approach speed; gap rising through 0: opens.
// * friction of a closed unilateral contact (its second event): stuck, when
//   mu push - |friction| falls through 0 it slides, against the friction it
//   had; sliding, when the speed along the slip direction falls through 0 it
//   sticks (and slides on at once, the other way, if sticking needs more than
//   mu push). Impulses are frictionless.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// Hunt-Crossley's chi for restitution e in (0, 1]: with the force
/// k d^n (1 + chi d'/v-), a contact without other forces ends at -e v-.
/// From the phase-plane integral (m d' dd'/dd = -k d^n (1 + a d'), a = chi / v-):
/// chi - ln(1 + chi) = -chi e - ln(1 - chi e), the root in (0, 1/e).
double hunt_crossley_chi(double e);

/// What a contact's event did.
struct ContactSwitch {
  enum Kind { None, Bounce, Rest, Stop, Close, Release, Open, Stick, Slide } kind = None;
  double speed = 0.0;  ///< impacts and closings: the approach speed -dg/dt before (m/s)
};

class Contacts {
 public:
  explicit Contacts(Model& model);

  std::size_t count() const { return info_.size(); }
  /// The contact whose event (or friction's event) is k, or -1.
  long of_event(std::size_t k) const { return k < contact_of_event_.size() ? contact_of_event_[k] : -1; }
  bool is_friction_event(std::size_t k) const { return k < friction_event_.size() && friction_event_[k]; }
  /// Modes from the state the run starts in: closed where the gap is <= 0 (a
  /// unilateral contact only if it then pushes).
  void start(double t, const double* y, const double* yp);
  /// Contact c's event function crossed zero at t, rising or not: switches its
  /// mode and applies an impact to y (ODE models).
  ContactSwitch fire(double t, std::size_t c, bool rising, double* y);
  /// Contact c's friction event crossed zero: sticks or slides.
  ContactSwitch fire_friction(double t, std::size_t c, bool rising, double* y);
  bool closed(std::size_t c) const { return closed_[c] != 0; }
  bool stuck(std::size_t c) const { return stuck_[c] != 0; }
  /// Contact c's modes as a run left them (Events::restore): closed, stuck.
  void restore(std::size_t c, bool closed, bool stuck) { closed_[c] = closed ? 1 : 0, stuck_[c] = stuck ? 1 : 0; }
  bool compliant(std::size_t c) const { return info_[c].compliant; }
  /// Contact c's event (Model::event_name).
  std::size_t event(std::size_t c) const { return info_[c].event; }
  /// Contact c's gap where the run started (start(); m).
  double start_gap(std::size_t c) const { return start_gap_[c]; }
  /// Contact c's gap at (t, y), closed or not (its mode is opened for the
  /// evaluation and put back).
  double gap(double t, const double* y, std::size_t c);
  /// "impact at 4.43 m/s: bounces", "closes at 1.2 m/s", ... (no commas: a CSV cell)
  static std::string describe(const ContactSwitch& s);
  /// What happened, in one word (the event log's state): "impact", "rest",
  /// "stop", "close", "release", "open", "stick", "slide".
  static const char* state(const ContactSwitch& s);

  /// A rebound shorter than this (times max(1, |t|)) ends in rest.
  static constexpr double kRestFlight = 1e-4;
  /// Unilateral, when it opens: its gap is put at least this far above 0 (m;
  /// doubled until the positions can tell it from 0), so that a flight
  /// shorter than a step still changes its sign between two steps, and the
  /// contact point leaves from the surface, not through it. Small: the lift
  /// adds m g kLift to the energy at each bounce (an elastic ball bouncing
  /// a thousand times gained 1e-8 J with 1e-12 m).
  static constexpr double kLift = 1e-15;
  /// Unilateral, closed: its normal force falling through 0 does not release
  /// it while its gap is below -kDeepestRelease (m). Only a contact that
  /// started inside its surface is that deep: its row's stabilisation then
  /// pulls as well as pushes until the bodies are out (critically damped, so
  /// they arrive at the surface at rest relative to each other), instead of
  /// letting go inside it and moving the positions out in one jump.
  static constexpr double kDeepestRelease = 1e-6;
  /// A contact that closes slower than this along the surface (m/s) sticks.
  static constexpr double kStickSpeed = 1e-8;
  /// Compliant: the approach speed Hunt-Crossley's damping divides by is at least this (m/s).
  static constexpr double kMinApproachSpeed = 1e-4;

 private:
  void set_closed(std::size_t c, bool on);
  bool has_friction(std::size_t c) const { return info_[c].friction_event >= 0; }
  /// Contact c's sliding velocity and friction in its tangent basis (tangents_).
  void tangents(double t, const double* y, std::size_t c, double v[2], double f[2]);
  void set_sliding(std::size_t c, double d1, double d2);
  void set_stuck(std::size_t c);
  /// Contact c just closed (or starts closed): sticks if it barely slides and
  /// mu push holds it, else slides along its motion (or against its friction).
  void start_friction(double t, const double* y, std::size_t c);
  /// Contact c slides the way its friction (as it is now) resists; false if it has none.
  bool slide_against_friction(double t, const double* y, std::size_t c);
  /// Stuck contact c whose friction would exceed mu push slides against it.
  bool slide_if_slipping(double t, const double* y, std::size_t c);
  /// The change of y per unit of contact c's normal speed (an impulse; zero
  /// in the entries it leaves alone, the positions among them): the state
  /// derivative with c closed is affine in its row's bias. In col_.
  void normal_response(double t, std::size_t c, const double* y);
  /// Opens unilateral contact c, its gap moved to kLift along the motion the
  /// velocity change col_ makes (positions only: the entries col_ leaves alone).
  void open_separated(double t, std::size_t c, double* y);
  double speed(double t, const double* y, std::size_t c);
  double event_function(double t, const double* y, std::size_t c);
  ContactSwitch impact(double t, std::size_t c, double* y);

  Model& m_;
  std::vector<ContactInfo> info_;
  std::vector<long> contact_of_event_;
  std::vector<char> closed_;
  std::vector<char> stuck_;
  std::vector<char> friction_event_;  // per event: a contact's friction
  std::vector<double> v_, g_, d0_, d1_, y1_, col_, tangents_, start_gap_;
};

}  // namespace mbgrt::detail
