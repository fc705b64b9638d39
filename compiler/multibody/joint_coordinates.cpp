// multibody/joint_coordinates.cpp — joints in joint coordinates.
#include "multibody/expander.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <ranges>
#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

// ---- 3b. joints in joint coordinates (constraints = coordinates) ----------------------
/// The joint's free directions as independent rates (thesis §8.4, the
/// minimal-variable form): per coordinate a 1-junction whose flow is a free
/// rate source `Sf { rate0 }` (a state), with a zero-effort C integrating it
/// into the coordinate. The child's velocity junctions get their flows from
/// the parent's and these rates through MTFs summed on 0-junctions, so the
/// child's inertias take derivative causality; reduce differentiates their
/// momenta and solves the accelerations (a mass-matrix system) from the
/// rate sources' zero-effort equations.
void Expander::emit_coordinate_joint(const Build& B, const Joint& j) {
  const AstJoint& d = *j.decl;
  const JointSym jn(d.name);
  const bool fwd = j.a_is_parent;
  const std::string& parent = fwd ? j.a.body : j.b.body;
  const std::string& child = fwd ? j.b.body : j.a.body;
  const Body& P = m_.bodies.at(parent);
  const Body& C = m_.bodies.at(child);
  const FlexibleSym on_parent(parent), on_child(child);  // (modal names only where flexible)
  TreeScope tree(*this, child);
  // The relative motion of B's joint frame in A's: a translation disp (A's
  // axes) and a rotation qrel, from the kind. Each rate junction k adds
  // W_k u_k to the relative angular velocity and V_k u_k to the rate of disp.
  class Rates final : public Mobilizer {
   public:
    Rates(Expander& x, const Build& b, const Joint& j, bool child_particle) : Mobilizer(b, j, child_particle), x_(x) {}
    Rate& rate(const Sym& junction, const std::string& c, E q0, E rate0, bool prescribed) override {
      const SourceLoc& at = joint.decl->loc;
      const Sym source = sym.rate_source(c);
      Rate k{junction, nullptr, B.ref(source.flow()), nullptr, nullptr, nullptr, nullptr};
      if (prescribed) {
        E motion = term(given_attr(joint, joint_setting::motion)->value);
        x_.element(B, "Sf", source, B.call("partial_t", {motion}));
        x_.junction_(B, junction, {source});
        k.value = motion;
      } else {
        const Sym coordinate = sym.coordinate(c);
        x_.element(B, "Sf", source, nullptr, {kv(element_setting::rate0, rate0, at)});
        x_.element(B, "C", coordinate, nullptr, {kv(element_setting::c_effort, zero, at), kv(element_setting::q0, q0, at)});
        x_.junction_(B, junction, {source}, {coordinate});
        k.value = B.ref(coordinate.displacement());
      }
      rates.push_back(k);
      return rates.back();
    }
    /// The relative angular velocity in B's joint frame, integrated into the
    /// relative quaternion as a body's orientation is.
    void ball() override {
      const SourceLoc& at = joint.decl->loc;
      x_.element(B, "Sf", sym.spin_rate(), nullptr, {kv(element_setting::rate0, setting_or_default(joint_setting::w0), at)});
      x_.element(B, "C", sym.rot(), nullptr,
                 {kv(element_setting::c_effort, B.list({zero, zero, zero, zero}), at),
                  kv(element_setting::q0, setting_or_default(joint_setting::rot0), at)});
      x_.element(B, "MTF", sym.rot_rate(), B.call("quat_rate", {B.ref(sym.rot().displacement())}));
      x_.junction(B, '1', sym.spin(), 3, {sym.spin_rate()}, {sym.rot_rate().port(1)});
      x_.bond(B, sym.rot_rate().port(2), sym.rot(), 4);
      qrel = B.ref(sym.rot().displacement());
      free_rotation = true;
      // the spin is B's angular velocity in B's joint axes: W = R(q) in A's, I in B's
      rates.push_back({sym.spin(), nullptr, B.ref(sym.spin_rate().flow()), B.call("rotq", {qrel}), nullptr,
                       B.call("eye", {B.num(3)}), nullptr});
    }
    /// B's velocity in B's joint axes, a free rate source; the translation
    /// (A's joint axes) integrates it turned by the relative rotation.
    void float_in_child_axes(E r0, E v0) override {
      const SourceLoc& at = joint.decl->loc;
      const E rot_now = B.call("rotq", {qrel});
      const E u0 = B.op('*', B.call("transpose", {B.call("rotq", {setting_or_default(joint_setting::rot0)})}), std::move(v0));
      x_.element(B, "Sf", sym.drift_rate(), nullptr, {kv(element_setting::rate0, u0, at)});
      x_.element(B, "C", sym.offset(), nullptr,
                 {kv(element_setting::c_effort, B.vec(0, 0, 0), at), kv(element_setting::q0, std::move(r0), at)});
      x_.element(B, "MTF", sym.offset_rate(), rot_now);
      x_.junction(B, '1', sym.drift(), 3, {sym.drift_rate()}, {sym.offset_rate().port(1)});
      x_.bond(B, sym.offset_rate().port(2), sym.offset(), 3);
      disp = B.ref(sym.offset().displacement());
      // V = R(q) in A's joint axes, the identity in B's
      rates.push_back({sym.drift(), nullptr, B.ref(sym.drift_rate().flow()), nullptr, rot_now, nullptr, B.call("eye", {B.num(3)})});
    }
    std::deque<Rate> rates;  // a deque: references rate() returned stay valid

   private:
    Expander& x_;
  };
  Rates m(*this, B, j, C.kind.particle());
  for (const auto& [name, body] : m_.bodies) m.child_carries = m.child_carries || body.tree_parent == child;
  j.kind->mobilize(m);
  const std::deque<Mobilizer::Rate>& rates = m.rates;
  const E& disp = m.disp;
  const E& qrel = m.qrel;
  // B's joint frame in A's; a rotor's frame leaves its turn out (rotors.hpp)
  const bool rotor = !C.rotor_joint.empty();
  const E rot = rotor ? B.call("eye", {B.num(3)}) : m.rot ? m.rot : B.call("rotq", {qrel});
  auto qmul = [&](E x, E y) { return B.call("quat_mul", {std::move(x), std::move(y)}); };
  auto conj = [&](E x) { return B.call("quat_conj", {std::move(x)}); };
  drive_loads(B, j);
  // pose of the child as signals of the coordinates
  auto T = [&](E x) { return B.call("transpose", {std::move(x)}); };
  auto times = [&](E a, E b) { return B.op('*', std::move(a), std::move(b)); };
  E Fa = B.ref(jn.frame_R('a')), Fb = B.ref(jn.frame_R('b'));
  E fa = B.ref(jn.frame_q('a')), fb = B.ref(jn.frame_q('b'));
  // On a flexible body the joint's point deflects with the modes and its
  // section turns by the small rotation theta(eta): the joint frame there is
  // turned by rotq([1, theta / 2]) (orthonormal; its angular velocity is
  // W(theta) theta', below). A ball joint's free rotation needs no turned
  // reference: its relative quaternion is taken from the bodies' axes.
  const FlexibleSeat seat_a = flexible_seat(B, j.a, m.free_rotation), seat_b = flexible_seat(B, j.b, m.free_rotation);
  const FlexibleSeat& seat = fwd ? seat_a : seat_b;        // on the parent
  const FlexibleSeat& own_seat = fwd ? seat_b : seat_a;    // on the child
  if (seat_a.turn) Fa = times(seat_a.turn, Fa);
  if (seat_b.turn) Fb = times(seat_b.turn, Fb);
  // A's point, moved by d; a particle's joint point is its position
  E pa = B.op('+', m_.bodies.at(j.a.body).kind.particle() ? B.vec(0, 0, 0) : seat_a.point ? seat_a.point : B.ref(jn.point('a')),
              B.op('*', Fa, disp));
  E pb = m_.bodies.at(j.b.body).kind.particle() ? B.vec(0, 0, 0) : seat_b.point ? seat_b.point : B.ref(jn.point('b'));
  E qP = quaternion(B, parent), RP = rotation(B, parent);
  if (seat.quaternion) qP = qmul(qP, seat.quaternion);
  E qC = rotor ? qmul(qmul(qP, fa), conj(fb)) : fwd ? qmul(qmul(qmul(qP, fa), qrel), conj(fb)) : qmul(qmul(qmul(qP, fb), conj(qrel)), conj(fa));
  if (own_seat.quaternion) qC = qmul(qC, conj(own_seat.quaternion));
  // R_PC = R_P^T R_C, the relative rotation of the bodies: the joint's own
  // turn between its fixed frames F_a and F_b.
  E Rrel = fwd ? times(times(Fa, rot), T(Fb)) : times(times(Fb, T(rot)), T(Fa));
  // As signals (JointSym::relative_R) where its rate is known in closed form,
  // R_PC skew(omega_rel) with omega_rel = sum Fb Wb u in the child's axes:
  // every modulus below is R_PC^T times constants, and what they carry is
  // differentiated for the accelerations (the bias terms), through these
  // rates instead of the chain rule through R(q) (for a quaternion, its
  // quotient by |q|^2 differentiated by each of four components). A turn
  // about one axis keeps the chain rule: d/dt of cos and sin costs less
  // than the signals (the planar chain: 1.5 % fewer operations).
  int turning = 0;
  for (const Mobilizer::Rate& r : rates) turning += r.W ? 1 : 0;
  if (fwd && !C.kind.particle() && !seat_a.turn && !seat_b.turn && (m.free_rotation || turning > 1)) {
    E omega = nullptr;
    bool known = true;
    for (const Mobilizer::Rate& r : rates) {
      if (!r.W) continue;
      if (!r.Wb) known = false;
      else omega = omega ? B.op('+', omega, times(times(Fb, r.Wb), r.rate)) : times(times(Fb, r.Wb), r.rate);
    }
    if (known && omega) {
      std::vector<E> rows_;
      for (int r = 1; r <= 3; ++r) {
        std::vector<E> row;
        for (int c = 1; c <= 3; ++c) row.push_back(B.ref(jn.relative_R(r, c)));
        rows_.push_back(B.list(row));
      }
      const E named = B.list(rows_), rate = times(named, B.call("skew", {omega}));
      for (int r = 1; r <= 3; ++r)
        for (int c = 1; c <= 3; ++c)
          signal(B, jn.relative_R(r, c), idx2(B, Rrel, r, c), idx2(B, rate, r, c));
      Rrel = named;
    }
  }
  if (!C.kind.particle()) {
    for (int k = 0; k < 4; ++k) signal(B, on_child.pose_q(k + 1), B.at(qC, k + 1));
    // The child's rotation matrix, propagated from its parent's (R_C = R_P R_PC):
    // no quaternion product and no normalisation. Its rate is R_C skew(omega_C)
    // with omega_C the child's angular velocity in its own axes (the flow of
    // the bond into its omega junction, below): 2 products an entry, where the
    // chain rule through R_P R_PC(q) would differentiate every factor.
    E Rc = !P.kind.turns() ? Rrel : times(RP, Rrel);
    E omega = B.ref(jn.reaction_torque().flow());
    if (E spin = rotor_spin(B, C)) omega = B.op('-', omega, spin);  // a rotor's frame turns without its spin
    const E rate = times(rotation(B, child), B.call("skew", {omega}));
    for (int r = 1; r <= 3; ++r)
      for (int c = 1; c <= 3; ++c)
        signal(B, on_child.pose_R(r, c), idx2(B, Rc, r, c), idx2(B, rate, r, c));
  }
  E RC = rotation(B, child);
  E joint_point = B.op('+', position(B, parent), B.op('*', RP, fwd ? pa : pb));
  if (P.kind.ground()) joint_point = fwd ? pa : pb;  // ground points are absolute
  E rC = B.op('-', joint_point, B.op('*', RC, fwd ? pb : pa));
  for (int k = 0; k < 3; ++k) signal(B, on_child.pose_r(k + 1), B.at(rC, k + 1));
  // Velocities as sums of MTF flows: the child's omega in its own axes and
  // its centre-of-mass velocity, in its own axes too where it turns
  // (body_frame_velocity), else (a particle) in world axes. In the child's
  // axes every modulus is the joint's relative rotation R_PC(q) = R_P^T R_C
  // (from the joint's own coordinates: its time derivative touches no other
  // joint) times constants of the joint.
  auto skew = [&](E x) { return B.call("skew", {std::move(x)}); };
  int fed = 0;
  auto feed = [&](const Sym& from, E modulus, const Sym& sum) {
    const Sym mtf = jn.feed(++fed);
    element(B, "MTF", mtf, std::move(modulus));
    bond(B, from, mtf.port(1));
    bond(B, mtf.port(2), sum);
  };
  // (a particle has no angular-velocity junction: nothing turns it, nothing reads it)
  const Sym wsum = jn.w_sum(), vsum = jn.v_sum();
  const bool parent_turns = P.kind.turns();
  E RrelT = T(Rrel);  // R_PC^T: parent axes -> child axes
  // Nothing turns the child when the parent does not turn and the joint has
  // no rotation (a prismatic joint from ground): its angular velocity is 0,
  // a flow source that takes whatever torque holds it (else its 0-junction
  // would have no bond to set its effort).
  const bool turns = parent_turns || seat.turn || own_seat.turn ||
                     std::any_of(rates.begin(), rates.end(), [](const Mobilizer::Rate& r) { return bool(r.W); });
  if (!C.kind.particle() && turns) {
    junction(B, '0', wsum, 3, {}, {});
    if (parent_turns) feed(on_parent.w(), RrelT, wsum);
    // in the child's axes, R_PC^T Fa W = Fb R^T W: where the kind gives R^T W
    // (Wb), no product of the rotation with its transpose is left to fold
    for (const Mobilizer::Rate& r : rates)
      if (r.W) feed(r.junction, fwd ? (r.Wb ? times(Fb, r.Wb) : times(times(RrelT, Fa), r.W)) : B.neg(times(Fa, r.W)), wsum);
  } else if (!C.kind.particle()) {
    element(B, "Sf", jn.still(), B.vec(0, 0, 0));
  }
  junction(B, '0', vsum, 3, {}, {});
  if (!C.kind.particle()) {
    // V_C = R_PC^T (V_P + omega_P x a + Fa d') - omega_C x b, with a and b the
    // joint's points from the parent's and the child's centre of mass
    if (parent_turns && body_frame_velocity(P)) {
      // The joint point's velocity in the parent's axes, V_P + omega_P x a,
      // on its own 0-junction, turned into the child's axes by one MTF. The
      // parent then reads the child's force there (R_PC f) and its moment
      // about the parent's centre through the lever arm's MTF: a x (the
      // force it reads), not a second product with the rotation.
      const Sym vpa = jn.point_velocity();
      junction(B, '0', vpa, 3, {}, {});
      named_bond(B, jn.parent_velocity(), on_parent.v(), vpa);
      feed(on_parent.w(), B.neg(skew(fwd ? pa : pb)), vpa);
      feed(vpa, RrelT, vsum);
    } else {
      if (!P.kind.ground()) feed(on_parent.v(), body_frame_velocity(P) || P.kind.particle() ? RrelT : times(RrelT, T(RP)), vsum);
      if (parent_turns) feed(on_parent.w(), times(RrelT, B.neg(skew(fwd ? pa : pb))), vsum);
    }
    // (R_PC^T Fa V = Fb R^T V: where the kind gives R^T V (Vb), no rotation is left)
    for (const Mobilizer::Rate& r : rates)
      if (r.V) feed(r.junction, fwd ? (r.Vb ? times(Fb, r.Vb) : times(times(RrelT, Fa), r.V)) : B.neg(times(Fa, r.V)), vsum);
    feed(on_child.w(), skew(fwd ? pb : pa), vsum);
    if (seat.point) {  // the parent's modal rates move and turn the joint's seat
      E q = B.ref(on_parent.eta().displacement());
      feed(on_parent.etadot(), times(RrelT, B.call("jacobian", {fwd ? pa : pb, q})), vsum);
      if (seat.turn) feed(on_parent.etadot(), times(times(RrelT, seat.turn_rate), B.call("jacobian", {seat.slope, q})), wsum);
    }
    if (own_seat.point) {  // and the child's own modal rates move and turn its seat under the joint
      E q = B.ref(on_child.eta().displacement());
      feed(on_child.etadot(), B.neg(B.call("jacobian", {fwd ? pb : pa, q})), vsum);
      if (own_seat.turn) feed(on_child.etadot(), B.neg(times(own_seat.turn_rate, B.call("jacobian", {own_seat.slope, q}))), wsum);
    }
    named_bond(B, jn.reaction_torque(), turns ? wsum : jn.still(), on_child.w());
  } else {  // world axes
    if (seat.point)
      feed(on_parent.etadot(), times(RP, B.call("jacobian", {fwd ? pa : pb, B.ref(on_parent.eta().displacement())})), vsum);
    if (!P.kind.ground()) feed(on_parent.v(), body_frame_velocity(P) ? RP : B.call("eye", {B.num(3)}), vsum);
    if (parent_turns) feed(on_parent.w(), B.neg(times(RP, skew(fwd ? pa : pb))), vsum);
    for (const Mobilizer::Rate& r : rates)
      if (r.V) feed(r.junction, fwd ? times(times(RP, Fa), r.V) : B.neg(times(times(RC, Fa), r.V)), vsum);
  }
  named_bond(B, jn.reaction_force(), vsum, on_child.v());
  coordinate_values_[d.name] = {m.angle, m.angle_rate, m.axial, m.axial_rate};
}

Expander::FlexibleSeat Expander::flexible_seat(const Build& B, const Side& s, bool free_rotation) const {
  const Body& P = m_.bodies.at(s.body);
  if (!P.kind.field() || s.point.empty()) return {};  // rigid, or a flexible body's fixed origin (check_coordinates)
  const Eta eta = state_eta(B, s.body, *P.kind.field());
  FlexibleSeat seat;
  seat.point = P.kind.field()->point(B, FlexibleSym(s.body), s.point, eta);
  seat.slope = P.kind.field()->slope(B, FlexibleSym(s.body), s.point, eta);
  if (free_rotation) return seat;
  // q = [1, theta / 2] (normalised by rotq): omega = 2 vec(q' q*) / |q|^2 = (theta' + theta x theta' / 2) / (1 + |theta|^2 / 4)
  E half = B.op('*', B.num(0.5), seat.slope);
  E q = section_quaternion(B, seat.slope);
  E norm2 = B.op('+', B.num(1), B.dot(half, half));
  seat.turn = section_turn(B, seat.slope);
  seat.quaternion = B.op('/', q, B.call("sqrt", {norm2}));
  seat.turn_rate = B.op('/', B.op('+', B.call("eye", {B.num(3)}), B.call("skew", {half})), norm2);
  return seat;
}

}  // namespace mbgc::multibody::detail
