// multibody/flexible_body.cpp — the floating-frame fragment every deformation kind shares (beam.hpp, modal_body.hpp).
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

/// eta of the body's state, split by group.
Eta Expander::state_eta(const Build& B, const std::string& body, const Deformation& field) const {
  const FlexibleSym n(body);
  return field.split([&](int k) { return eta_of(B, n, k); });
}

void Expander::emit_flexible(const Body& body) {
  const AstBody& d = *body.decl;
  const FlexibleSym n(d.name);
  const Deformation& beam = *body.kind.field();
  Build B(d.loc, symbols_);
  beam.params({B, d, [&](const Sym& name, E value) { property(B, name, std::move(value)); }, diags_});
  for (const auto& [p, v] : body.points) property(B, n.point(p), term(v));
  const int ne = beam.count(), N = 6 + ne;
  Eta eta = state_eta(B, d.name, beam);
  Eta rest = beam.split([&](int) { return B.num(0); });
  // the I field and its velocity terms on the common junction nu = [V; omega; eta']
  // (V in body axes). With its own states (rows strategies) nu is the I
  // field's flow; moved by joint coordinates, nu is assembled from the flows
  // the tree joint sets on its V and omega junctions and from the modal
  // rates, free rates of its own (the modal accelerations join the body's
  // block in the tree elimination).
  const bool own_states = !body.by_coordinates;
  std::vector<Sym> nu_in;
  if (m_.gravity) nu_in.push_back(n.weight());
  if (auto it = m_.loads.find(d.name); it != m_.loads.end())
    for (const LoadSym& f : it->second) nu_in.push_back(f.on(d.name));
  std::vector<Sym> nu_out = {n.M(), n.ejs()};
  if (own_states) nu_out.insert(nu_out.end(), {n.sv().port(1), n.sw().port(1), n.se().port(1)});
  junction(B, '1', n.nu(), N, nu_in, nu_out);
  std::vector<TermAttr> M_init;
  if (own_states) {
    E R0 = B.call("rotq", {B.ref(n.q0())});
    E nu0 = B.call("vcat", {B.op('*', B.call("transpose", {R0}), B.ref(n.v0())), B.ref(n.w0()), B.call("zeros", {B.num(ne)})});
    M_init.push_back(kv(element_setting::p0, B.op('*', rows_to_matrix(B, beam.mass_matrix(B, n, rest)), nu0), d.loc));
  }
  element(B, "I", n.M(), rows_to_matrix(B, beam.mass_matrix(B, n, eta)), M_init);
  std::get<ir::ExpandedElement>(generated_.back()).configuration_dependent = true;
  E f = B.ref(Sym::own_flow()), p = B.ref(n.M().momentum());
  auto part = [&](E v, int from) { return B.list({B.at(v, from), B.at(v, from + 1), B.at(v, from + 2)}); };
  E V = part(f, 1), w = part(f, 4), P = part(p, 1), H = part(p, 4);
  auto cross = [&](E a, E b) { return B.call("cross", {std::move(a), std::move(b)}); };
  // dT/deta at constant nu (Kirchhoff): the kinetic energy's change with the beam's shape
  E T = B.op('*', B.num(0.5), B.dot(f, B.op('*', rows_to_matrix(B, beam.mass_matrix(B, n, eta)), f)));
  E dT = B.call("transpose", {B.call("jacobian", {T, B.ref(n.eta().displacement())})});
  element(B, "R", n.ejs(), nullptr,
          {kv(element_setting::r_effort, B.call("vcat", {cross(w, P), B.op('+', cross(w, H), cross(V, P)), B.neg(dT)}), d.loc)});
  if (m_.gravity) {
    // generalised gravity force: -dU/d(position, rotation, eta) with U = -g . (m r + R s(eta))
    E g = B.op('*', B.call("transpose", {rotation(B, d.name)}), B.ref(Sym::gravity()));
    E coupling = rows_to_matrix(B, beam.translation_coupling(B, n, eta));
    element(B, "Se", n.weight(),
            B.call("vcat", {B.op('*', B.ref(n.mass()), g), cross(beam.first_moment(B, n, eta), g),
                            B.op('*', B.call("transpose", {coupling}), g)}));
  }
  // selectors (own states): V (turned to world axes), omega, eta'; or
  // (coordinates) their transposes, assembling nu from V, omega and eta'
  E pick_v = B.call("hcat", {B.call("eye", {B.num(3)}), B.call("zeros", {B.num(3), B.num(3 + ne)})});
  E pick_w = B.call("hcat", {B.call("zeros", {B.num(3), B.num(3)}), B.call("eye", {B.num(3)}), B.call("zeros", {B.num(3), B.num(ne)})});
  E pick_e = B.call("hcat", {B.call("zeros", {B.num(ne), B.num(6)}), B.call("eye", {B.num(ne)})});
  auto T_ = [&](E x) { return B.call("transpose", {std::move(x)}); };
  std::vector<Sym> modal_in, modal_out = {n.eta()};
  if (own_states) {
    E Rq = B.call("rotq", {B.ref(n.q().displacement())});
    element(B, "MTF", n.sv(), B.op('*', Rq, pick_v));
    element(B, "MTF", n.sw(), pick_w);
    element(B, "MTF", n.se(), pick_e);
    // position and orientation, as on a rigid body
    junction(B, '1', n.v(), 3, {n.sv().port(2)}, {n.r()});
    element(B, "C", n.r(), nullptr, {kv(element_setting::c_effort, B.vec(0, 0, 0), d.loc), kv(element_setting::q0, B.ref(n.r0()), d.loc)});
    junction(B, '1', n.w(), 3, {n.sw().port(2)}, {n.qrate().port(1)});
    element(B, "MTF", n.qrate(), B.call("quat_rate", {B.ref(n.q().displacement())}));
    element(B, "C", n.q(), nullptr,
            {kv(element_setting::c_effort, B.list({B.num(0), B.num(0), B.num(0), B.num(0)}), d.loc),
             kv(element_setting::q0, B.ref(n.q0()), d.loc)});
    bond(B, n.qrate().port(2), n.q(), 4);
    modal_in.push_back(n.se().port(2));
  } else {
    // the tree joint's flows arrive on v and w (body axes); the modal rates are free
    junction(B, '1', n.v(), 3, {}, {n.av().port(1)});
    junction(B, '1', n.w(), 3, {}, {n.aw().port(1)});
    element(B, "MTF", n.av(), T_(pick_v));
    element(B, "MTF", n.aw(), T_(pick_w));
    element(B, "MTF", n.ae(), T_(pick_e));
    element(B, "Sf", n.eta_rate(), nullptr, {kv(element_setting::rate0, B.call("zeros", {B.num(ne)}), d.loc)});
    modal_in.push_back(n.eta_rate());
    modal_out.push_back(n.ae().port(1));
    junction(B, '0', n.nusum(), N, {n.av().port(2), n.aw().port(2), n.ae().port(2)}, {});
    bond(B, n.nusum(), n.nu());
  }
  // elasticity and modal damping on eta'
  if (body_term(d, beam_setting::damping)) modal_out.push_back(n.damp());
  junction(B, '1', n.etadot(), ne, modal_in, modal_out);
  Rows K(static_cast<std::size_t>(ne), std::vector<E>(static_cast<std::size_t>(ne), B.num(0)));
  Rows D = K;
  beam.stiffness_and_damping(B, n, K, D);
  element(B, "C", n.eta(), nullptr,
          {kv(element_setting::c_effort, B.op('*', rows_to_matrix(B, K), B.ref(Sym::own_displacement())), d.loc),
           kv(element_setting::q0, B.call("zeros", {B.num(ne)}), d.loc)});
  std::get<ir::ExpandedElement>(generated_.back()).state_limits = beam.limits(d.name);
  if (body_term(d, beam_setting::damping)) element(B, "R", n.damp(), rows_to_matrix(B, D));
}

/// The load on b (world force F at Q, torque T) and its opposite on a, as
/// effort sources on the bodies' junctions: F on the centre-of-mass
/// velocity junction, the body-frame moment arm x (R^T F) + R^T T on the
/// angular-velocity one. A spring-damper acts along the line P -> Q.
/// World position and velocity of a beam's point at `local` (body axes,
/// deflected): it moves with the frame and, through the modes, on it.
std::pair<E, E> Expander::flexible_point_motion(const Build& B, const std::string& body, E local) const {
  const FlexibleSym n(body);
  E R = rotation(B, body);
  E rate = B.op('+', B.call("cross", {B.ref(n.w().flow()), local}),
                B.op('*', B.call("jacobian", {local, B.ref(n.eta().displacement())}), B.ref(n.etadot().flow())));
  return {B.op('+', position(B, body), B.op('*', R, local)), B.op('+', velocity(B, body), B.op('*', R, rate))};
}

/// A force F (and torque T), world axes, at a beam's point as an effort on
/// its junction nu = [V; omega; eta']: the power F.v_P + T.w_P written in
/// nu, i.e. [R'F; P x R'F + R'T; (dP/deta)' R'F + (dtheta/deta)' R'T].
E Expander::flexible_load(const Build& B, const std::string& body, const std::string& point, E force, E torque) {
  const Deformation& beam = *m_.bodies.at(body).kind.field();
  const FlexibleSym n(body);
  Eta eta = state_eta(B, body, beam);
  E at = point.empty() ? B.vec(0, 0, 0) : beam.point(B, n, point, eta);
  E Rt = B.call("transpose", {rotation(B, body)}), F = B.op('*', Rt, force), q = B.ref(n.eta().displacement());
  E moment = B.call("cross", {at, F});
  E modal = B.op('*', B.call("transpose", {B.call("jacobian", {at, q})}), F);
  if (torque) {
    E T = B.op('*', Rt, torque);
    moment = B.op('+', moment, T);
    if (!point.empty())
      modal = B.op('+', modal, B.op('*', B.call("transpose", {B.call("jacobian", {beam.slope(B, n, point, eta), q})}), T));
  }
  return B.call("vcat", {F, moment, modal});
}

/// A beam's quantities: those of a rigid body, for its frame origin (x = 0),
/// plus its modal coordinates, elastic energy and the deflection of its points.
void Expander::flexible_quantities(const Build& B, const Body& body) {
  const std::string& name = body.decl->name;
  const FlexibleSym n(name);
  const Deformation& beam = *body.kind.field();
  Eta eta = state_eta(B, name, beam);
  E r = position(B, name), v = velocity(B, name), q = quaternion(B, name), R = rotation(B, name), w = B.ref(n.w().flow());
  E p = B.ref(n.M().momentum());
  auto part = [&](E x, int from) { return B.list({B.at(x, from), B.at(x, from + 1), B.at(x, from + 2)}); };
  quantities_.define(n.quantity("position"), r);
  quantities_.define(n.quantity("velocity"), v);
  quantities_.define(n.quantity("momentum"), B.op('*', R, part(p, 1)));
  quantities_.define(n.quantity("quaternion"), q);
  quantities_.define(n.quantity("rotation"), R);
  quantities_.define(n.quantity("bryant"), B.call("bryant", {q}));
  quantities_.define(n.quantity("omega"), w);
  quantities_.define(n.quantity("omega_world"), B.op('*', R, w));
  quantities_.define(n.quantity("angular_momentum"), B.op('*', R, part(p, 4)));  // about the frame origin
  quantities_.define(n.modes(), B.ref(n.eta().displacement()));
  quantities_.define(n.quantity("kinetic_energy"), B.op('*', B.num(0.5), B.dot(B.ref(n.nu().flow()), p)));
  E elastic = B.op('*', B.num(0.5), B.dot(B.ref(n.eta().displacement()), B.ref(n.eta().effort())));
  quantities_.define(n.elastic_energy(), elastic);
  E gravity = m_.gravity ? B.neg(B.dot(B.ref(Sym::gravity()), B.op('+', B.op('*', B.ref(n.mass()), r),
                                                                    B.op('*', R, beam.first_moment(B, n, eta)))))
                       : B.num(0);
  quantities_.define(n.quantity("potential_energy"), B.op('+', gravity, elastic));
  for (const auto& [pt, at] : beam.points()) {
    E local = beam.point(B, n, pt, eta);
    auto [point_position, point_velocity] = flexible_point_motion(B, name, local);
    quantities_.define(n.point(pt).quantity("position"), point_position);
    quantities_.define(n.point(pt).quantity("velocity"), point_velocity);
    quantities_.define(n.point(pt).quantity("deflection"), B.op('-', local, B.vec(at[0], at[1], at[2])));  // body axes
    quantities_.define(n.point(pt).quantity("rotation_vector"), beam.slope(B, n, pt, eta));  // small, body axes
  }
}

}  // namespace mbgc::multibody::detail
