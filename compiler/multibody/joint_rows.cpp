// multibody/joint_rows.cpp — joints as constraint rows, held as their strategy says
// (constraint_strategy.hpp): multipliers, a penalty, or a cut joint's stabilised multipliers.
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

Frame Expander::frame(const Build& B, const Joint& j, const Side& s, char side) {
  const Body& body = m_.bodies.at(s.body);
  Frame f;
  f.kind = body.kind;
  f.body = s.body;
  const JointSym jn(j.decl->name);
  f.R = rotation(B, s.body);
  E local = B.ref(jn.point(side));  // the point in CoM-relative body coordinates (ground: absolute)
  E turn = f.R;                       // the joint frame's rotation (a beam's section turns with its slope)
  if (body.kind.field() && !s.point.empty()) {
    Eta eta = state_eta(B, s.body, *body.kind.field());
    local = body.kind.field()->point(B, FlexibleSym(s.body), s.point, eta);
    turn = B.op('*', f.R, section_turn(B, body.kind.field()->slope(B, FlexibleSym(s.body), s.point, eta)));
  }
  if (body.kind.ground()) f.p = local;
  else if (body.kind.particle()) f.p = position(B, s.body);
  else f.p = B.op('+', position(B, s.body), B.op('*', f.R, local));
  f.local = local;
  E F = B.op('*', turn, B.ref(jn.frame_R(side)));
  f.X = B.op('*', F, B.vec(1, 0, 0));
  f.Y = B.op('*', F, B.vec(0, 1, 0));
  f.Z = B.op('*', F, B.vec(0, 0, 1));
  return f;
}

void Expander::joint_params(const Build& B, const Joint& j) {
  const JointSym jn(j.decl->name);
  for (const auto& [s, side] : {std::pair{&j.a, 'a'}, std::pair{&j.b, 'b'}}) {
    const Body& body = m_.bodies.at(s->body);
    const BodySym on(s->body);
    E point = s->point.empty() ? B.vec(0, 0, 0) : B.ref(on.point(s->point));
    if (!body.kind.turns()) property(B, jn.point(side), point);
    else property(B, jn.point(side), B.op('-', point, B.ref(on.com())));
    const AstAttr* ax = given_attr(j, side == 'a' ? joint_setting::axis_a : joint_setting::axis_b);
    E axis = ax ? term(ax->value) : setting_or_default(j, joint_setting::axis, B);
    property(B, jn.axis(side), B.op('/', axis, B.call("norm", {axis})));
    property(B, jn.frame_q(side), B.call("quat_arc", {B.ref(jn.axis(side))}));
    property(B, jn.frame_R(side), B.call("rotq", {B.ref(jn.frame_q(side))}));
  }
  // Length scale that turns the angular rows (dot products) into metres: the
  // radius of gyration of the lighter body, so one stiffness suits all rows.
  std::vector<E> radii;
  for (const Side* s : {&j.a, &j.b}) {
    const Body& body = m_.bodies.at(s->body);
    if (!body.kind.turns()) continue;
    const BodySym on(s->body);
    E I = B.ref(on.inertia());
    E trace = B.op('+', B.op('+', idx2(B, I, 1, 1), idx2(B, I, 2, 2)), idx2(B, I, 3, 3));
    radii.push_back(B.call("sqrt", {B.op('/', trace, B.op('*', B.num(3), B.ref(on.mass())))}));
  }
  E scale = radii.empty() ? B.num(1) : radii.size() == 1 ? radii[0] : B.call("min", {radii[0], radii[1]});
  property(B, jn.scale(), scale);
}

/// The constraint rows g (each a scalar AST expression) of a joint: its
/// kind's, then a prescribed motion's.
std::vector<E> Expander::rows(const Build& B, const Joint& j, const Frame& A, const Frame& Bf) {
  const JointFrames f{B, j, A, Bf, B.op('-', Bf.p, A.p), B.ref(JointSym(j.decl->name).scale())};
  std::vector<E> r;
  j.kind->rows(f, r);
  if (const AstAttr* m = given_attr(j, joint_setting::motion)) {
    E motion = term(m->value);
    if (j.kind->drives_along_axis()) r.push_back(B.op('-', B.dot(A.Z, f.d), motion));
    else r.push_back(B.op('*', f.scale, f.turned_by(motion)));  // scale * sin(theta - f(t)), without atan2
  }
  return r;
}

/// The rate of `rows` (a k-vector of position-level expressions) collected on
/// 0-junction `sum`: one MTF per body junction, modulus d(rows)/d(position) times
/// the map from the junction's flow to that position's rate; `mtf` names them
/// by the junction: 't' the velocity, 'r' the angular velocity, 'e' the modal rates.
void Expander::rates_into(const Build& B, const std::function<Sym(char)>& mtf, E rows_vec, const Frame& f, const Sym& sum,
                          bool towards_sum, bool translational) {
  if (f.kind.ground()) return;
  const std::string& b = f.body;
  const BodySym on(b);
  std::vector<std::pair<Sym, Sym>> parts;  // (MTF, body junction)
  const Body& body = m_.bodies.at(b);
  if (body.by_coordinates) {
    // (a cut joint on a body moved by joint coordinates: its pose is signals,
    // r and R; r' = R V for V in body axes (else V), R' = R skew(omega))
    E r = position(B, b), R = rotation(B, b);
    if (translational) {
      E Jr = B.call("jacobian", {rows_vec, r});
      element(B, "MTF", mtf('t'), body_frame_velocity(body) ? B.op('*', Jr, R) : Jr);
      parts.push_back({mtf('t'), on.v()});
    }
    if (!f.kind.particle()) {
      std::vector<E> entries;
      for (int i = 1; i <= 3; ++i)
        for (int k = 1; k <= 3; ++k) entries.push_back(B.ref(on.pose_R(i, k)));
      E JR = B.call("jacobian", {rows_vec, B.list(entries)});  // k x 9, row-major R
      std::vector<E> columns;
      for (int axis = 0; axis < 3; ++axis) {
        E turn = B.op('*', R, B.call("skew", {axis == 0 ? B.vec(1, 0, 0) : axis == 1 ? B.vec(0, 1, 0) : B.vec(0, 0, 1)}));
        std::vector<E> flat;
        for (int i = 1; i <= 3; ++i)
          for (int k = 1; k <= 3; ++k) flat.push_back(idx2(B, turn, i, k));
        columns.push_back(B.op('*', JR, B.list(flat)));
      }
      element(B, "MTF", mtf('r'), B.call("hcat", {columns[0], columns[1], columns[2]}));
      parts.push_back({mtf('r'), on.w()});
    }
  } else {
    if (translational) {
      element(B, "MTF", mtf('t'), B.call("jacobian", {rows_vec, B.ref(on.r().displacement())}));
      parts.push_back({mtf('t'), on.v()});
    }
    if (!f.kind.particle()) {
      const Sym q = on.q().displacement();
      element(B, "MTF", mtf('r'), B.op('*', B.call("jacobian", {rows_vec, B.ref(q)}), B.call("quat_rate", {B.ref(q)})));
      parts.push_back({mtf('r'), on.w()});
    }
  }
  if (m_.bodies.at(b).kind.field()) {  // the joint's point moves with the beam's deflection
    const FlexibleSym flex(b);
    element(B, "MTF", mtf('e'), B.call("jacobian", {rows_vec, B.ref(flex.eta().displacement())}));
    parts.push_back({mtf('e'), flex.etadot()});
  }
  for (const auto& [through, junc] : parts) {
    if (towards_sum) {
      bond(B, junc, through.port(1));
      bond(B, through.port(2), sum);
    } else {
      bond(B, sum, through.port(2));
      bond(B, through.port(1), junc);
    }
  }
}

/// The joint's `torque` or `force` as an effort source on its drive port
/// (JointSym::drive, a 1-junction on the joint coordinate's rate).
void Expander::drive_loads(const Build& B, const Joint& j) {
  const JointSym jn(j.decl->name);
  for (const Setting* drive : {&joint_setting::torque, &joint_setting::force}) {
    const AstAttr* load = given_attr(j, *drive);
    if (!load) continue;
    element(B, "Se", jn.applied(), term(load->value));
    applied_.push_back(generated_.size() - 1);  // may read joint quantities (a torsion spring: -k * j.angle)
    bond(B, jn.applied(), jn.drive());
  }
}

void Expander::emit_joint(const Joint& j) {
  const AstJoint& d = *j.decl;
  const JointSym jn(d.name);
  Build B(d.loc, symbols_);
  joint_params(B, j);
  j.kind->params(j, [&](const Sym& name, E value) { property(B, name, std::move(value)); });
  Frame A = frame(B, j, j.a, 'a');
  Frame Bf = frame(B, j, j.b, 'b');
  frames_[d.name] = {A, Bf};
  const ConstraintStrategy& strategy = constraint_strategy(j.strategy);
  if (strategy.tree_coordinates() && j.tree) {
    emit_coordinate_joint(B, j);
    return;
  }
  std::vector<E> g = rows(B, j, A, Bf);
  if (g.empty()) {
    diags_.error(d.loc, fmt::format("free joint `{}` constrains nothing, so it has no rows for {}", d.name, strategy.rows_are_for()),
                 strategy.free_joint_hint());
    return;
  }
  int k = static_cast<int>(g.size());
  E gvec = B.list(g);
  // constraint fragment: body junctions -> MTFs -> 0-junction -> CN
  junction(B, '0', jn.rows(), k, {}, {jn.constraint()});
  rates_into(B, [&](char flow) { return jn.row_rate('a', flow); }, gvec, A, jn.rows(), true, true);
  rates_into(B, [&](char flow) { return jn.row_rate('b', flow); }, gvec, Bf, jn.rows(), true, true);
  ir::ConstraintLaw law;
  law.g = gvec;
  strategy.hold({B, j, jn, A, Bf, [&](const Sym& name, E value) { param(B, name, std::move(value)); }}, law);
  constraint(B, jn.constraint(), std::move(law));
  if (given(j, joint_setting::motion)) {
    // the prescribed motion's explicit time dependence enters the rate as a flow source
    element(B, "Sf", jn.motion(), B.call("partial_t", {gvec}));
    bond(B, jn.motion(), jn.rows());
  }
  // drive port: a 1-junction whose flow is the joint coordinate's rate
  std::optional<E> coordinate = joint_coordinate(B, j, A, Bf);
  if (coordinate) {
    coordinates_[d.name] = *coordinate;
    const bool translational = j.kind->drives_along_axis();
    junction(B, '1', jn.drive(), 1, {}, {jn.drive_sum()});
    junction(B, '0', jn.drive_sum(), 1, {}, {});
    E cvec = B.list({*coordinate});
    rates_into(B, [&](char flow) { return jn.drive_rate('a', flow); }, cvec, A, jn.drive_sum(), false, translational);
    rates_into(B, [&](char flow) { return jn.drive_rate('b', flow); }, cvec, Bf, jn.drive_sum(), false, translational);
    drive_loads(B, j);
  }
}

/// The drive coordinate measured from the frames: the angle about the axis, or the slide along it.
std::optional<E> Expander::joint_coordinate(const Build& B, const Joint& j, const Frame& A, const Frame& Bf) {
  if (j.kind->drives_along_axis()) return B.dot(A.Z, B.op('-', Bf.p, A.p));
  if (j.kind->has_angle()) return B.call("atan2", {B.dot(A.Y, Bf.X), B.dot(A.X, Bf.X)});
  return std::nullopt;
}

}  // namespace mbgc::multibody::detail
