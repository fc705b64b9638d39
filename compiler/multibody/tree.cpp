// multibody/tree.cpp — the spanning tree and initial conditions along it.
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

// ---- 4. initial conditions along a spanning tree from ground ----------------------------
/// A spanning tree from ground, breadth first: each body is placed by the
/// first joint that reaches it; the other joints close loops.
void Expander::find_tree() {
  std::deque<std::string> queue{"ground"};
  while (!queue.empty()) {
    std::string from = queue.front();
    queue.pop_front();
    for (Joint& j : joints_) {
      if (j.tree) continue;
      bool forward = j.a.body == from, backward = j.b.body == from;
      if (!forward && !backward) continue;
      const std::string& child = forward ? j.b.body : j.a.body;
      if (bodies_.at(child).placed) continue;  // closes a loop: the runtime assembles it
      j.tree = true;
      j.a_is_parent = forward;
      Body& c = bodies_.at(child);
      c.placed = true;
      c.placed_by = j.decl->name;
      tree_order_.push_back(&j);
      queue.push_back(child);
    }
  }
  mark_coordinate_bodies();
}

/// Which bodies the tree joints move by joint coordinates (their joint's strategy).
void Expander::mark_coordinate_bodies() {
  for (const Joint* j : tree_order_) {
    Body& c = bodies_.at(j->a_is_parent ? j->b.body : j->a.body);
    const std::string& parent = j->a_is_parent ? j->a.body : j->b.body;
    c.by_coordinates = j->strategy == Strategy::Coordinates;
    c.tree_parent = c.by_coordinates && parent != "ground" ? parent : "";
  }
}

/// constraints = auto: joint coordinates when they can move every joint left
/// to auto (a tree, no particle a joint turns, ...), else multipliers.
void Expander::choose_strategy() {
  std::vector<Joint*> open;
  for (Joint& j : joints_)
    if (j.strategy == Strategy::Auto) open.push_back(&j);
  if (open.empty()) return;
  for (Joint* j : open) j->strategy = Strategy::Coordinates;
  mark_coordinate_bodies();
  const std::vector<Problem> problems = coordinate_problems();
  std::string report;
  if (problems.empty()) {
    std::vector<std::string> cut;
    for (const Joint* j : open)
      if (!j->tree) cut.push_back("`" + j->decl->name + "`");
    report = cut.empty() ? std::string("constraints = auto: coordinates (the joints form a tree: joint coordinates as states, "
                                       "an ODE without constraint rows)")
                         : fmt::format("constraints = auto: coordinates on a spanning tree, with cut joint{} {} (their rows "
                                       "held at acceleration level by multipliers, Baumgarte-stabilised: an ODE)",
                                       cut.size() == 1 ? "" : "s", fmt::join(cut, ", "));
  } else {
    for (Joint* j : open) j->strategy = Strategy::Lagrange;
    mark_coordinate_bodies();
    report = fmt::format("constraints = auto: lagrange (multipliers, a DAE), because {}", problems.front().message);
  }
  if (strategy_report_) *strategy_report_ = report;
}

/// The tree joints from `body` up to ground.
std::vector<std::string> Expander::path_to_ground(std::string body) const {
  std::vector<std::string> path;
  while (body != "ground" && bodies_.at(body).placed) {
    const std::string& jn = bodies_.at(body).placed_by;
    path.push_back(jn);
    for (const Joint& j : joints_)
      if (j.decl->name == jn) body = j.a_is_parent ? j.a.body : j.b.body;
  }
  return path;
}

/// What keeps joint coordinates from moving a joint: a particle a joint would
/// turn, a flexible body held at an origin that moves, and rows-strategy
/// constraint rows (a CN) on a body that has no position states. (A joint
/// that closes a loop is a cut joint: its rows act through multipliers on the
/// tree, emit_joint.)
std::vector<Expander::Problem> Expander::coordinate_problems() const {
  std::vector<Problem> out;
  for (const Joint& j : joints_) {
    const AstJoint& d = *j.decl;
    if (j.strategy == Strategy::Coordinates) {
      for (const Side* s : {&j.a, &j.b})
        if (bodies_.at(s->body).kind.field() && s->point.empty() && !bodies_.at(s->body).kind.field()->origin_fixed()) {
          out.push_back({d.loc, fmt::format("joint `{}` holds the flexible body `{}` at its frame's origin, which moves with "
                                            "its modes: not implemented in joint coordinates",
                                            d.name, s->body),
                         fmt::format("declare a point of `{}` where the joint sits and name it (`{}.p`): its deflection "
                                     "and turn come from the modes there; or put the frame at a clamped root",
                                     s->body, s->body)});
          break;
        }
    }
    if (j.strategy == Strategy::Coordinates && j.tree && !j.kind->moves_particles())
      for (const Side* s : {&j.a, &j.b})
        if (bodies_.at(s->body).kind.particle()) {
          const bool parent = (s == &j.a) == j.a_is_parent;
          if (parent)
            out.push_back({d.loc, fmt::format("joint `{}` hangs `{}` from the particle `{}`, which joint coordinates "
                                              "cannot do", d.name, (j.a_is_parent ? j.b : j.a).body, s->body),
                           fmt::format("a particle has no orientation for the joint's frame to turn with: give `{}` "
                                       "an inertia, or write constraints = lagrange or penalty for this model",
                                       s->body)});
          else
            out.push_back({d.loc, fmt::format("joint `{}` cannot move the particle `{}` by joint coordinates", d.name, s->body),
                           fmt::format("a particle has no angular-velocity junction for the joint's rotation rates to "
                                       "drive, so they would carry no inertia: give `{}` an inertia, or write "
                                       "constraints = lagrange or penalty for this model",
                                       s->body)});
          break;
        }
    if (j.strategy != Strategy::Coordinates)
      for (const Side* s : {&j.a, &j.b})
        if (bodies_.at(s->body).by_coordinates) {
          out.push_back({d.loc, fmt::format("joint `{}` uses constraint rows, but `{}` moves by joint coordinates", d.name, s->body),
                         fmt::format("a constraintor CN acts through the rates of a body's position states, and `{}` has "
                                     "none (its pose is a function of joint `{}`'s coordinates): use one strategy for the "
                                     "whole model (constraints = lagrange, penalty or coordinates)",
                                     s->body, bodies_.at(s->body).placed_by)});
          break;
        }
  }
  return out;
}

void Expander::check_coordinates() {
  for (const Problem& p : coordinate_problems()) diags_.error(p.loc, p.message, p.hint);
}

void Expander::place_bodies() {
  // A body moved by joint coordinates has its pose as signals of them
  // (emit_coordinate_joint): no initial-pose parameters to compute.
  for (const Joint* j : tree_order_)
    if (j->strategy != Strategy::Coordinates) place(*j, j->a_is_parent);
  for (const std::string& n : body_order_) {
    Body& body = bodies_.at(n);
    const AstBody& d = *body.decl;
    Build B(d.loc);
    if (body.placed) {
      for (const Setting* initial : {&body_setting::r0, &body_setting::quat0, &body_setting::v0, &body_setting::w0})
        for (const AstAttr& a : d.attrs)
          if (a.key == initial->name)
            diags_.error(a.loc, fmt::format("body `{}` is placed by joint `{}`, so `{}` cannot be given", n, body.placed_by, a.key),
                         placed_hint(body.placed_by));
      continue;
    }
    const BodySym at(n);
    E r0 = attr(d, body_setting::r0), v0 = attr(d, body_setting::v0);
    param(B, at.r0(), r0 ? r0 : B.vec(0, 0, 0));
    param(B, at.v0(), v0 ? v0 : B.vec(0, 0, 0));
    if (body.kind.particle()) continue;
    E q0 = attr(d, body_setting::quat0), w0 = attr(d, body_setting::w0);
    param(B, at.q0(), q0 ? q0 : B.list({B.num(1), B.num(0), B.num(0), B.num(0)}));
    param(B, at.w0(), w0 ? w0 : B.vec(0, 0, 0));
  }
}

/// How to set the initial pose of a body that joint `jn` places.
std::string Expander::placed_hint(const std::string& jn) const {
  std::string coords;
  for (const Joint& j : joints_)
    if (j.decl->name == jn) coords = j.kind->initial_settings();
  std::string start = fmt::format("the initial pose and velocity follow from the parent body along joint `{}`", jn);
  if (coords.empty()) return start + "; remove the setting, or join the body by another joint";
  return fmt::format("{}: give the joint's {} instead", start, coords);
}

Pose Expander::pose(const Build& B, const std::string& body) {
  const Body& b = bodies_.at(body);
  if (b.kind.ground()) return {B.list({B.num(1), B.num(0), B.num(0), B.num(0)}), B.call("eye", {B.num(3)}), B.vec(0, 0, 0), B.vec(0, 0, 0), B.vec(0, 0, 0)};
  const BodySym n(body);
  E q = b.kind.particle() ? B.list({B.num(1), B.num(0), B.num(0), B.num(0)}) : B.ref(n.q0());
  E w = b.kind.particle() ? B.vec(0, 0, 0) : B.ref(n.w0());
  return {q, B.call("rotq", {q}), B.ref(n.r0()), B.ref(n.v0()), w};
}

/// Initial pose of the child of a tree joint from its parent and the joint coordinates.
void Expander::place(const Joint& j, bool a_is_parent) {
  const JointSym jn(j.decl->name);
  Build B(j.decl->loc);
  const auto [angle, angle_rate, axial, axial_rate, qrel, w_rel, v_rel] = j.kind->initial(B, j);
  E axis_a = B.ref(jn.axis('a'));
  E pa = B.op('+', B.ref(jn.point('a')), B.op('*', axis_a, axial));  // A's point, moved along the axis
  E pb = B.ref(jn.point('b'));
  E fa = B.ref(jn.frame_q('a')), fb = B.ref(jn.frame_q('b'));
  const std::string& child = a_is_parent ? j.b.body : j.a.body;
  const BodySym placed(child);
  const std::string& parent = a_is_parent ? j.a.body : j.b.body;
  const Body& cb = bodies_.at(child);
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
  bool parent_ground = bodies_.at(parent).kind.ground();
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
