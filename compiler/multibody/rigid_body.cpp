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
  const AstBody& d = *body.decl;
  const std::string& n = d.name;
  Build B(d.loc);
  TreeScope tree(*this, n);
  if (body.flex) {
    emit_flexible(body);
    return;
  }
  property(B, n + ".mass", attr(d, "mass"));
  for (const auto& [p, v] : body.points) property(B, n + "." + p, v);
  // initial pose and velocity (overwritten by place_bodies for joint-placed bodies)
  // applied loads (force elements) push into the body's junctions
  std::vector<std::string> forces_in, torques_in;
  if (gravity_) forces_in.push_back(n + ".weight");
  if (auto it = loads_.find(n); it != loads_.end())
    for (const std::string& f : it->second) {
      forces_in.push_back(f + ".on_" + n + "_f");
      if (!body.particle) torques_in.push_back(f + ".on_" + n + "_t");
    }
  // A body moved by joint coordinates has no states of its own: its inertias
  // take derivative causality and its pose is a function of the coordinates.
  const bool own_states = !body.by_coordinates;
  // Moved by joint coordinates, a turning body's translational junction is in
  // its own axes (the parent-to-child MTFs then need only the joint's
  // relative rotation): Newton's law there has the term omega x p, a second
  // Euler junction structure, power-free like the rotational one.
  const bool body_axes = body_frame_velocity(body);
  std::vector<std::string> v_out = {n + ".m"};
  if (own_states) v_out.push_back(n + ".r");
  if (body_axes) v_out.push_back(n + ".ejs_v");
  junction(B, '1', n + ".v", 3, forces_in, v_out);
  std::vector<AstAttr> m_init, J_init;
  if (own_states) m_init.push_back(kv("f0", B.name(n + ".v0"), d.loc)), J_init.push_back(kv("f0", B.name(n + ".w0"), d.loc));
  element(B, "I", n + ".m", B.op('*', B.name(n + ".mass"), B.call("eye", {B.num(3)})), m_init);
  if (own_states) element(B, "C", n + ".r", nullptr, {kv("e", B.vec(0, 0, 0), d.loc), kv("q0", B.name(n + ".r0"), d.loc)});
  if (gravity_)
    element(B, "Se", n + ".weight",
            B.op('*', B.name(n + ".mass"),
                 body_axes ? B.op('*', B.call("transpose", {rotation(B, n)}), B.name("gravity")) : B.name("gravity")));
  if (body_axes)
    element(B, "R", n + ".ejs_v", nullptr, {kv("e", B.call("cross", {B.name(n + ".J.f"), B.name(n + ".m.p")}), d.loc)});
  if (body.particle) return;
  E com = attr(d, "com");
  property(B, n + ".com", com ? com : B.vec(0, 0, 0));
  property(B, n + ".inertia", attr(d, "inertia"));
  std::vector<std::string> w_out = {n + ".J", n + ".ejs"};
  if (own_states) w_out.push_back(n + ".qrate.p1");
  junction(B, '1', n + ".w", 3, torques_in, w_out);
  element(B, "I", n + ".J", B.name(n + ".inertia"), J_init);
  // Euler junction structure: torque omega x h on the body-frame junction, no power.
  element(B, "R", n + ".ejs", nullptr, {kv("e", B.call("cross", {B.name("f"), B.name(n + ".J.p")}), d.loc)});
  if (!own_states) return;
  element(B, "MTF", n + ".qrate", B.call("quat_rate", {B.name(n + ".q.q")}));
  element(B, "C", n + ".q", nullptr, {kv("e", B.list({B.num(0), B.num(0), B.num(0), B.num(0)}), d.loc), kv("q0", B.name(n + ".q0"), d.loc)});
  bond(B, n + ".qrate.p2", n + ".q", 4);
}

// ---- pose of a body: its states, or (joint coordinates) signals of its tree joint ----
/// Centre-of-mass position, world frame.
E Expander::position(const Build& B, const std::string& body) const {
  const Body& b = bodies_.at(body);
  if (b.ground) return B.vec(0, 0, 0);
  if (!b.by_coordinates) return B.name(body + ".r.q");
  return B.list({B.name(body + ".pose.r1"), B.name(body + ".pose.r2"), B.name(body + ".pose.r3")});
}

/// Orientation quaternion [w, x, y, z], body -> world.
E Expander::quaternion(const Build& B, const std::string& body) const {
  const Body& b = bodies_.at(body);
  if (b.ground || b.particle) return B.list({B.num(1), B.num(0), B.num(0), B.num(0)});
  if (!b.by_coordinates) return B.name(body + ".q.q");
  std::vector<E> q;
  for (int k = 1; k <= 4; ++k) q.push_back(B.name(fmt::format("{}.pose.q{}", body, k)));
  return B.list(q);
}

/// Is the body's translational junction in its own axes (a turning body moved by joint coordinates)?
bool Expander::body_frame_velocity(const Body& b) const { return b.by_coordinates && !b.particle && !b.ground; }

/// Centre-of-mass velocity, world frame.
E Expander::velocity(const Build& B, const std::string& body) const {
  const Body& b = bodies_.at(body);
  if (b.ground) return B.vec(0, 0, 0);
  if (body_frame_velocity(b)) return B.op('*', rotation(B, body), B.name(body + ".v.f"));
  return B.name(body + ".v.f");
}

/// Rotation matrix body -> world (computed once per body in coordinates).
E Expander::rotation(const Build& B, const std::string& body) const {
  const Body& b = bodies_.at(body);
  if (b.ground || b.particle) return B.call("eye", {B.num(3)});
  if (!b.by_coordinates) return B.call("rotq", {B.name(body + ".q.q")});
  std::vector<E> rows_;
  for (int r = 1; r <= 3; ++r) {
    std::vector<E> row;
    for (int c = 1; c <= 3; ++c) row.push_back(B.name(fmt::format("{}.pose.R{}{}", body, r, c)));
    rows_.push_back(B.list(row));
  }
  return B.list(rows_);
}

}  // namespace mbgc::multibody::detail
