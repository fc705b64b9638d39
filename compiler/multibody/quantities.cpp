// multibody/quantities.cpp — the quantities of the bodies and joints users may name (the table: quantities.hpp).
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

void Expander::define_quantities() {
  for (const std::string& name : m_.body_order) {
    const Body& body = m_.bodies.at(name);
    const BodySym n(name);
    Build B(body.decl->loc, symbols_);
    if (body.kind.field()) {
      flexible_quantities(B, body);
      continue;
    }
    auto quantity = [&](const char* q, E value) { quantities_.define(n.quantity(q), std::move(value)); };
    E r = position(B, name), v = velocity(B, name);
    quantity("position", r);
    quantity("velocity", v);
    quantity("momentum",
             body_frame_velocity(body) ? B.op('*', rotation(B, name), B.ref(n.m().momentum())) : B.ref(n.m().momentum()));
    E ke = B.op('*', B.num(0.5), B.dot(B.ref(n.v().flow()), B.ref(n.m().momentum())));  // in the junction's own axes
    if (!body.kind.particle()) {
      // R and w: the frame of the body's equations and the body's angular
      // velocity in its axes (a rotor's frame leaves out its spin: what is
      // read of the body's own axes turns it back, attitude())
      E R = rotation(B, name), w = B.ref(n.w().flow());
      E q = attitude_quaternion(B, name), turn = rotor_turn(B, body, "rot_axis_angle");
      quantity("quaternion", q);
      quantity("rotation", attitude(B, name));
      quantity("bryant", B.call("bryant", {q}));
      quantity("omega", turn ? B.op('*', B.call("transpose", {turn}), w) : w);
      quantity("omega_world", B.op('*', R, w));
      quantity("angular_momentum", B.op('*', R, B.ref(n.J().momentum())));
      ke = B.op('+', ke, B.op('*', B.num(0.5), B.dot(w, B.ref(n.J().momentum()))));
      for (const auto& [p, x] : body.points) {
        const PointSym point = n.point(p);
        E local = B.op('-', B.ref(point), B.ref(n.com()));
        quantities_.define(point.quantity("position"), B.op('+', r, B.op('*', R, local)));
        quantities_.define(point.quantity("velocity"), B.op('+', v, B.op('*', R, B.call("cross", {w, local}))));
      }
    }
    quantity("kinetic_energy", ke);
    quantity("potential_energy", m_.gravity ? B.neg(B.op('*', B.ref(n.mass()), B.dot(B.ref(Sym::gravity()), r))) : B.num(0));
  }
  for (const Joint& j : m_.joints) {
    const JointSym jn(j.decl->name);
    Build B(j.decl->loc, symbols_);
    auto quantity = [&](const char* q, E value) { quantities_.define(jn.quantity(q), std::move(value)); };
    const auto& [A, Bf] = frames_.at(j.decl->name);
    const Frame& body_side = Bf.kind.ground() ? A : Bf;
    // a joint with no rows (free) constrains nothing: it has no violation
    if (std::vector<E> r = rows(B, j, A, Bf); !r.empty()) quantity("violation", B.list(r));
    if (auto cv = coordinate_values_.find(j.decl->name); cv != coordinate_values_.end()) {
      // joint coordinates: the reaction is the effort on the bonds into the
      // child's junctions (force world, torque body frame); on b, by Newton's third law
      const std::string child = j.a_is_parent ? j.b.body : j.a.body;
      E sign = B.num(j.a_is_parent ? 1 : -1);
      E reaction_f = B.ref(jn.reaction_force().effort());
      if (body_frame_velocity(m_.bodies.at(child))) reaction_f = B.op('*', rotation(B, child), reaction_f);
      quantity("force", B.op('*', sign, reaction_f));
      if (!m_.bodies.at(child).kind.particle())
        quantity("torque", B.op('*', sign, B.op('*', rotation(B, child), B.ref(jn.reaction_torque().effort()))));
      if (j.kind->has_angle()) {
        quantity("angle", cv->second.angle);
        quantity("rate", cv->second.rate);
      }
      if (j.kind->has_displacement()) {
        quantity("displacement", cv->second.displacement);
        // its rate (a spring-damper in the joint's `force`): a state here, joint coordinates only
        if (cv->second.displacement_rate) quantity("displacement_rate", cv->second.displacement_rate);
      }
      continue;
    }
    // reaction on the second body (on the first, negated, if the second is ground)
    const char side = Bf.kind.ground() ? 'a' : 'b';
    E force = B.ref(jn.row_rate(side, 't').effort(1));
    if (!Bf.kind.ground()) force = B.neg(force);
    // (a cut joint on a body moved by joint coordinates: that junction is in the body's axes)
    if (body_frame_velocity(m_.bodies.at(body_side.body))) force = B.op('*', body_side.R, force);
    if (body_side.kind.particle()) {
      quantity("force", force);
    } else {
      E torque_body = B.ref(jn.row_rate(side, 'r').effort(1));
      if (!Bf.kind.ground()) torque_body = B.neg(torque_body);
      E lever = B.op('*', body_side.R, body_side.local);
      quantity("force", force);
      quantity("torque", B.op('-', B.op('*', body_side.R, torque_body), B.call("cross", {lever, force})));
    }
    E wrel = B.op('-', !Bf.kind.turns() ? B.vec(0, 0, 0) : B.op('*', Bf.R, B.ref(BodySym(Bf.body).w().flow())),
                  !A.kind.turns() ? B.vec(0, 0, 0) : B.op('*', A.R, B.ref(BodySym(A.body).w().flow())));
    if (j.kind->has_angle()) {
      quantity("angle", B.call("atan2", {B.dot(A.Y, Bf.X), B.dot(A.X, Bf.X)}));
      quantity("rate", B.dot(A.Z, wrel));
    }
    if (j.kind->has_displacement())
      quantity("displacement", j.kind->displacement({B, j, A, Bf, B.op('-', Bf.p, A.p), B.ref(jn.scale())}));
  }
}

}  // namespace mbgc::multibody::detail
