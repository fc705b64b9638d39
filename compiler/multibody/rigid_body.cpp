// multibody/rigid_body.cpp — rigid bodies and particles; the pose of any body.
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

void Expander::emit_body(const Body& body) {
  TreeScope tree(*this, body.decl->name);
  body.kind.visit([](const Ground&) {}, [&](const Particle&) { emit_rigid(body); }, [&](const Rigid&) { emit_rigid(body); },
                  [&](const Flexible&) { emit_flexible(body); });
}

/// A rigid body's fragment; a particle's is its translational half.
void Expander::emit_rigid(const Body& body) {
  const AstBody& d = *body.decl;
  const BodySym n(d.name);
  Build B(d.loc, symbols_);
  property(B, n.mass(), body_term(d, body_setting::mass));
  for (const auto& [p, v] : body.points) property(B, n.point(p), term(v));
  // initial pose and velocity (overwritten by place_bodies for joint-placed bodies)
  // applied loads (force elements) push into the body's junctions
  std::vector<Sym> forces_in, torques_in;
  if (m_.gravity) forces_in.push_back(n.weight());
  if (auto it = m_.loads.find(d.name); it != m_.loads.end())
    for (const LoadSym& f : it->second) {
      forces_in.push_back(f.on(d.name, 'f'));
      if (!body.kind.particle()) torques_in.push_back(f.on(d.name, 't'));
    }
  // A body moved by joint coordinates has no states of its own: its inertias
  // take derivative causality and its pose is a function of the coordinates.
  const bool own_states = !body.by_coordinates;
  // Moved by joint coordinates, a turning body's translational junction is in
  // its own axes (the parent-to-child MTFs then need only the joint's
  // relative rotation): Newton's law there has the term omega x p, a second
  // Euler junction structure, power-free like the rotational one.
  const bool body_axes = body_frame_velocity(body);
  std::vector<Sym> v_out = {n.m()};
  if (own_states) v_out.push_back(n.r());
  if (body_axes) v_out.push_back(n.ejs_v());
  junction(B, '1', n.v(), 3, forces_in, v_out);
  std::vector<TermAttr> m_init, J_init;
  if (own_states) m_init.push_back(kv(element_setting::f0, B.ref(n.v0()), d.loc)), J_init.push_back(kv(element_setting::f0, B.ref(n.w0()), d.loc));
  element(B, "I", n.m(), B.op('*', B.ref(n.mass()), B.call("eye", {B.num(3)})), m_init);
  if (own_states)
    element(B, "C", n.r(), nullptr,
            {kv(element_setting::c_effort, B.vec(0, 0, 0), d.loc), kv(element_setting::q0, B.ref(n.r0()), d.loc)});
  if (m_.gravity)
    element(B, "Se", n.weight(),
            B.op('*', B.ref(n.mass()),
                 body_axes ? B.op('*', B.call("transpose", {rotation(B, d.name)}), B.ref(Sym::gravity())) : B.ref(Sym::gravity())));
  // The Euler junction structures turn the momenta with the frame of the
  // junctions: the body's angular velocity, a rotor's less its spin.
  const E spin = rotor_spin(B, body);
  auto frame_turn = [&](E omega) { return spin ? B.op('-', std::move(omega), spin) : omega; };
  if (body_axes)
    element(B, "R", n.ejs_v(), nullptr,
            {kv(element_setting::r_effort, B.call("cross", {frame_turn(B.ref(n.J().flow())), B.ref(n.m().momentum())}), d.loc)});
  if (body.kind.particle()) return;
  E com = body_term(d, body_setting::com);
  property(B, n.com(), com ? com : B.default_of(body_setting::com));
  property(B, n.inertia(), body_term(d, body_setting::inertia));
  std::vector<Sym> w_out = {n.J(), n.ejs()};
  if (own_states) w_out.push_back(n.qrate().port(1));
  junction(B, '1', n.w(), 3, torques_in, w_out);
  element(B, "I", n.J(), B.ref(n.inertia()), J_init);
  // Euler junction structure: torque omega x h on the body-frame junction, no
  // power (a rotor's Omega x h, Omega = omega less the spin: no power either,
  // its inertia being symmetric about the spin's axis).
  element(B, "R", n.ejs(), nullptr, {kv(element_setting::r_effort, B.call("cross", {frame_turn(B.ref(Sym::own_flow())), B.ref(n.J().momentum())}), d.loc)});
  if (!own_states) return;
  element(B, "MTF", n.qrate(), B.call("quat_rate", {B.ref(n.q().displacement())}));
  element(B, "C", n.q(), nullptr,
          {kv(element_setting::c_effort, B.list({B.num(0), B.num(0), B.num(0), B.num(0)}), d.loc),
           kv(element_setting::q0, B.ref(n.q0()), d.loc)});
  bond(B, n.qrate().port(2), n.q(), 4);
}

// ---- pose of a body: its states, or (joint coordinates) signals of its tree joint ----
/// Centre-of-mass position, world frame.
E Expander::position(const Build& B, const std::string& body) const {
  const Body& b = m_.bodies.at(body);
  if (b.kind.ground()) return B.vec(0, 0, 0);
  const BodySym n(body);
  if (!b.by_coordinates) return B.ref(n.r().displacement());
  return B.list({B.ref(n.pose_r(1)), B.ref(n.pose_r(2)), B.ref(n.pose_r(3))});
}

/// Orientation quaternion [w, x, y, z], body -> world.
E Expander::quaternion(const Build& B, const std::string& body) const {
  const Body& b = m_.bodies.at(body);
  if (!b.kind.turns()) return B.list({B.num(1), B.num(0), B.num(0), B.num(0)});
  const BodySym n(body);
  if (!b.by_coordinates) return B.ref(n.q().displacement());
  std::vector<E> q;
  for (int k = 1; k <= 4; ++k) q.push_back(B.ref(n.pose_q(k)));
  return B.list(q);
}

/// Is the body's translational junction in its own axes (a turning body moved by joint coordinates)?
bool Expander::body_frame_velocity(const Body& b) const { return b.by_coordinates && !b.kind.particle() && !b.kind.ground(); }

/// Centre-of-mass velocity, world frame.
E Expander::velocity(const Build& B, const std::string& body) const {
  const Body& b = m_.bodies.at(body);
  if (b.kind.ground()) return B.vec(0, 0, 0);
  const Sym v = BodySym(body).v().flow();
  if (body_frame_velocity(b)) return B.op('*', rotation(B, body), B.ref(v));
  return B.ref(v);
}

E Expander::rotor_spin(const Build& B, const Body& body) const {
  if (body.rotor_joint.empty()) return nullptr;
  const JointSym jn(body.rotor_joint);
  return B.op('*', B.ref(jn.axis('b')), B.ref(jn.rate_source(kTurnCoordinate).flow()));
}

E Expander::rotor_turn(const Build& B, const Body& body, const char* form) const {
  if (body.rotor_joint.empty()) return nullptr;
  return B.call(form, {B.ref(JointSym(body.rotor_joint).axis('b')), coordinate_values_.at(body.rotor_joint).angle});
}

E Expander::attitude(const Build& B, const std::string& body) const {
  E turn = rotor_turn(B, m_.bodies.at(body), "rot_axis_angle");
  return turn ? B.op('*', rotation(B, body), turn) : rotation(B, body);
}

E Expander::attitude_quaternion(const Build& B, const std::string& body) const {
  E turn = rotor_turn(B, m_.bodies.at(body), "quat_axis_angle");
  return turn ? B.call("quat_mul", {quaternion(B, body), turn}) : quaternion(B, body);
}

/// Rotation matrix body -> world (computed once per body in coordinates).
E Expander::rotation(const Build& B, const std::string& body) const {
  const Body& b = m_.bodies.at(body);
  if (!b.kind.turns()) return B.call("eye", {B.num(3)});
  const BodySym n(body);
  if (!b.by_coordinates) return B.call("rotq", {B.ref(n.q().displacement())});
  std::vector<E> rows_;
  for (int r = 1; r <= 3; ++r) {
    std::vector<E> row;
    for (int c = 1; c <= 3; ++c) row.push_back(B.ref(n.pose_R(r, c)));
    rows_.push_back(B.list(row));
  }
  return B.list(rows_);
}

}  // namespace mbgc::multibody::detail
