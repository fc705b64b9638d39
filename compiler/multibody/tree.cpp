// multibody/tree.cpp — the initial conditions along the spanning tree (spanning_tree.hpp).
#include "multibody/constraint_strategy.hpp"
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

void Expander::place_bodies() {
  // A body moved by joint coordinates has its pose as signals of them
  // (emit_coordinate_joint): no initial-pose parameters to compute.
  for (const Joint* j : m_.tree_order)
    if (!constraint_strategy(j->strategy).tree_coordinates()) place(*j, j->a_is_parent);
  for (const std::string& n : m_.body_order) {
    const Body& body = m_.bodies.at(n);
    const AstBody& d = *body.decl;
    Build B(d.loc, symbols_);
    if (body.placed) {
      for (const Setting* initial : {&body_setting::r0, &body_setting::quat0, &body_setting::v0, &body_setting::w0})
        for (const AstAttr& a : d.attrs)
          if (a.key == initial->name)
            diags_.error(a.loc, fmt::format("body `{}` is placed by joint `{}`, so `{}` cannot be given", n, body.placed_by, a.key),
                         placed_hint(body.placed_by));
      continue;
    }
    const BodySym at(n);
    E r0 = body_term(d, body_setting::r0), v0 = body_term(d, body_setting::v0);
    param(B, at.r0(), r0 ? r0 : B.default_of(body_setting::r0));
    param(B, at.v0(), v0 ? v0 : B.default_of(body_setting::v0));
    if (body.kind.particle()) continue;
    E q0 = body_term(d, body_setting::quat0), w0 = body_term(d, body_setting::w0);
    param(B, at.q0(), q0 ? q0 : B.default_of(body_setting::quat0));
    param(B, at.w0(), w0 ? w0 : B.default_of(body_setting::w0));
  }
}

/// How to set the initial pose of a body that joint `jn` places.
std::string Expander::placed_hint(const std::string& jn) const {
  std::string coords;
  for (const Joint& j : m_.joints)
    if (j.decl->name == jn) coords = j.kind->initial_settings();
  std::string start = fmt::format("the initial pose and velocity follow from the parent body along joint `{}`", jn);
  if (coords.empty()) return start + "; remove the setting, or join the body by another joint";
  return fmt::format("{}: give the joint's {} instead", start, coords);
}

Pose Expander::pose(const Build& B, const std::string& body) {
  const Body& b = m_.bodies.at(body);
  if (b.kind.ground()) return {B.list({B.num(1), B.num(0), B.num(0), B.num(0)}), B.call("eye", {B.num(3)}), B.vec(0, 0, 0), B.vec(0, 0, 0), B.vec(0, 0, 0)};
  const BodySym n(body);
  E q = b.kind.particle() ? B.list({B.num(1), B.num(0), B.num(0), B.num(0)}) : B.ref(n.q0());
  E w = b.kind.particle() ? B.vec(0, 0, 0) : B.ref(n.w0());
  return {q, B.call("rotq", {q}), B.ref(n.r0()), B.ref(n.v0()), w};
}

/// Initial pose of the child of a tree joint from its parent and the joint coordinates.
void Expander::place(const Joint& j, bool a_is_parent) {
  const JointSym jn(j.decl->name);
  Build B(j.decl->loc, symbols_);
  const auto [angle, angle_rate, axial, axial_rate, qrel, w_rel, v_rel] = j.kind->initial(B, j);
  E axis_a = B.ref(jn.axis('a'));
  E pa = B.op('+', B.ref(jn.point('a')), B.op('*', axis_a, axial));  // A's point, moved along the axis
  E pb = B.ref(jn.point('b'));
  E fa = B.ref(jn.frame_q('a')), fb = B.ref(jn.frame_q('b'));
  const std::string& child = a_is_parent ? j.b.body : j.a.body;
  const BodySym placed(child);
  const std::string& parent = a_is_parent ? j.a.body : j.b.body;
  const Body& cb = m_.bodies.at(child);
  Pose P = pose(B, parent);
  auto qmul = [&](E x, E y) { return B.call("quat_mul", {std::move(x), std::move(y)}); };
  auto conj = [&](E x) { return B.call("quat_conj", {std::move(x)}); };
  if (!cb.kind.particle()) {
    E q = a_is_parent ? qmul(qmul(qmul(P.q, fa), qrel), conj(fb)) : qmul(qmul(qmul(P.q, fb), conj(qrel)), conj(fa));
    param(B, placed.q0(), q);
  }
  Pose C = pose(B, child);
  auto cross = [&](E x, E y) { return B.call("cross", {std::move(x), std::move(y)}); };
  auto T = [&](E m) { return B.call("transpose", {std::move(m)}); };
  // in A's frame (B's joint frame is fa qrel in it, A's joint frame fa)
  E rel_w = w_rel ? B.op('*', B.call("rotq", {qmul(fa, qrel)}), w_rel) : B.op('*', axis_a, angle_rate);
  E rel_v = v_rel ? B.op('*', B.call("rotq", {fa}), v_rel) : B.op('*', axis_a, axial_rate);
  // Ground points are absolute: their "local" coordinates already are world positions.
  auto world_point = [&](const Pose& X, E local, bool ground) { return ground ? local : B.op('+', X.r, B.op('*', X.R, local)); };
  bool parent_ground = m_.bodies.at(parent).kind.ground();
  if (a_is_parent) {
    E pa_world = world_point(P, pa, parent_ground);
    param(B, placed.r0(), B.op('-', pa_world, B.op('*', C.R, pb)));
    if (!cb.kind.particle()) param(B, placed.w0(), B.op('*', B.op('*', T(C.R), P.R), B.op('+', P.w, rel_w)));
    E v = B.op('+', B.op('+', P.v, B.op('*', P.R, cross(P.w, pa))), B.op('*', P.R, rel_v));
    param(B, placed.v0(), B.op('-', v, B.op('*', C.R, cross(C.w, pb))));
  } else {
    E pb_world = world_point(P, pb, parent_ground);
    param(B, placed.r0(), B.op('-', pb_world, B.op('*', C.R, pa)));
    if (!cb.kind.particle()) param(B, placed.w0(), B.op('-', B.op('*', B.op('*', T(C.R), P.R), P.w), rel_w));
    E v = B.op('+', P.v, B.op('*', P.R, cross(P.w, pb)));
    param(B, placed.v0(), B.op('-', B.op('-', v, B.op('*', C.R, cross(C.w, pa))), B.op('*', C.R, rel_v)));
  }
}

}  // namespace mbgc::multibody::detail
