// multibody/forces.cpp — force elements.
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

// ---- 5. quantities users may name ------------------------------------------------------
// ---- 4. force elements ------------------------------------------------------------
/// World position and velocity of a force element's point.
std::pair<E, E> Expander::world_point(const Build& B, const Side& s) {
  const Body& body = m_.bodies.at(s.body);
  const BodySym n(s.body);
  E local = s.point.empty() ? B.vec(0, 0, 0) : B.ref(n.point(s.point));
  using Motion = std::pair<E, E>;
  return body.kind.visit(
      [&](const Ground&) -> Motion { return {local, B.vec(0, 0, 0)}; },
      [&](const Particle&) -> Motion { return {position(B, s.body), velocity(B, s.body)}; },
      [&](const Rigid&) -> Motion {
        E r = position(B, s.body), v = velocity(B, s.body), R = rotation(B, s.body);
        E arm = B.op('-', local, B.ref(n.com()));
        return {B.op('+', r, B.op('*', R, arm)), B.op('+', v, B.op('*', R, B.call("cross", {B.ref(n.w().flow()), arm})))};
      },
      [&](const Flexible& f) -> Motion {
        Eta eta = state_eta(B, s.body, *f.field);
        return flexible_point_motion(B, s.body, s.point.empty() ? B.vec(0, 0, 0) : f.field->point(B, FlexibleSym(s.body), s.point, eta));
      });
}

void Expander::emit_force(const ForceElement& f) {
  const ForceSym fn(f.decl->name);
  Build B(f.decl->loc, symbols_);
  auto user = [&](const Setting& s) -> E {
    const AstAttr* given = given_in(f.attrs, s);
    return given ? rewrite_.expr(term(given->value)) : nullptr;
  };
  auto [pa, va] = world_point(B, f.a);
  auto [pb, vb] = world_point(B, f.b);
  E d = B.op('-', pb, pa);
  quantities_.define(fn.quantity("length"), B.call("norm", {d}));
  E force = user(force_setting::force);
  if (E k = user(force_setting::stiffness), c = user(force_setting::damping); k || c) {
    if (k) param(B, fn.stiffness(), k);
    if (c) param(B, fn.damping(), c);
    if (E l0 = user(force_setting::length)) param(B, fn.length0(), l0);
    E len = B.call("norm", {d}), u = B.op('/', d, len);
    E tension = B.num(0);
    if (k) tension = B.op('*', B.ref(fn.stiffness()), B.op('-', len, B.ref(fn.length0())));
    if (c) tension = B.op('+', tension, B.op('*', B.ref(fn.damping()), B.dot(u, B.op('-', vb, va))));
    E spring = B.neg(B.op('*', tension, u));
    force = force ? B.op('+', force, spring) : spring;
  }
  if (!force) force = B.default_of(force_setting::force);
  E torque = user(force_setting::torque);
  quantities_.define(fn.quantity("force"), force);
  if (torque) quantities_.define(fn.quantity("torque"), torque);
  apply_load(B, fn, f.a, force, torque, -1.0);
  apply_load(B, fn, f.b, force, torque, 1.0);
}

/// `sign` times a world force at side s's point and a world torque (may be
/// null) on its body, as the effort sources of `source` on it (LoadSym::on:
/// a force and a torque, or on a flexible body one source on its whole
/// junction); nothing on ground.
void Expander::apply_load(const Build& B, const LoadSym& source, const Side& s, E force, E torque, double sign) {
  const Body& body = m_.bodies.at(s.body);
  auto signed_ = [&](E e) { return sign < 0 ? B.neg(e) : e; };
  // the force on the junction of the centre's velocity (in the body's axes where that is)
  auto push = [&] {
    element(B, "Se", source.on(s.body, 'f'),
            signed_(body_frame_velocity(body) ? B.op('*', B.call("transpose", {rotation(B, s.body)}), force) : force));
  };
  body.kind.visit(
      [](const Ground&) {},
      [&](const Particle&) { push(); },
      [&](const Rigid&) {  // and its moment about the centre, with the torque, on the angular velocity's
        push();
        E Rt = B.call("transpose", {rotation(B, s.body)});
        const BodySym n(s.body);
        E local = s.point.empty() ? B.vec(0, 0, 0) : B.ref(n.point(s.point));
        E arm = B.op('-', local, B.ref(n.com()));
        E moment = B.call("cross", {arm, B.op('*', Rt, force)});
        if (torque) moment = B.op('+', moment, B.op('*', Rt, torque));
        element(B, "Se", source.on(s.body, 't'), signed_(moment));
      },
      [&](const Flexible&) { element(B, "Se", source.on(s.body), signed_(flexible_load(B, s.body, s.point, force, torque))); });
}

}  // namespace mbgc::multibody::detail
