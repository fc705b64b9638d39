// multibody/tyres.cpp — `tyre NAME(wheel.centre, ground) { ... }`: the road
// loads on a wheel from Pacejka's Magic Formula (the MF 5.2 equations,
// without camber and aligning moment), with combined slip and first-order
// relaxation lengths, settings named as in tyre data (.tir) files.
//
// Geometry (docs/notes/tyre.md): the road is the plane z = h(x) of the world
// (h = 0, or a height profile `profile = [[x1, h1], ...]` along world x,
// piecewise linear), with normal n. The wheel turns about `axis` (its
// frame). The tyre's directions: e_x = unit(axis x n) (forward),
// e_y = n x e_x (left). The centre is hc above the road (along n); the
// tyre is deflected by rho = R0 - hc and pushes Fz = max(0, kz rho + cz rho').
// Slip: the centre's velocity V_cx, V_cy along e_x, e_y, the spin Omega about
// the axle, the slip velocity V_sx = V_cx - (R0 - rho) Omega. The lagged slips
// (states) follow the relaxation equations
//   sigma_kappa kappa' + |V_cx| kappa = -V_sx,   sigma_alpha t' + |V_cx| t = V_cy,
// alpha = atan(t): no division by the speed, so the wheel may stand still.
// The force Fx e_x + Fy e_y + Fz n acts at the contact point, below the
// centre: on the wheel, the same force at the centre and its moment.
#include "multibody/collect.hpp"
#include "multibody/expander.hpp"
#include "multibody/setting_names.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace mbgc::multibody::detail {

namespace {

/// A generic passenger-car tyre (symmetric: no offsets), for models that do
/// not give their own data; every entry may be set in the tyre's block.
struct TyreSetting {
  const char* name;
  double default_value;
  const char* meaning;
  /// The unit of its value: the load, the radius and the radial stiffness
  /// and damping have one, the Magic Formula's coefficients none (a
  /// relaxation length is given over R0, a shift over FNOMIN).
  units::Dimension dimension = units::Dimension::none();
  /// Only a value > 0 makes sense (a load, a radius, a stiffness, a
  /// relaxation length's factors): a constant that is not is an error.
  bool positive = false;
};
const std::vector<TyreSetting> kTyreSettings = {
    {"FNOMIN", 4000, "nominal wheel load (N)", units::dim::force(), true},
    {"UNLOADED_RADIUS", 0.3, "free tyre radius R0 (m)", units::dim::length(), true},
    {"VERTICAL_STIFFNESS", 2.0e5, "radial stiffness kz (N/m)", units::dim::force() / units::dim::length(), true},
    {"VERTICAL_DAMPING", 500, "radial damping cz (N s/m)", units::dim::force() / units::dim::velocity()},
    {"LMUX", 1, "scale of the longitudinal friction (road)"},
    {"LMUY", 1, "scale of the lateral friction (road)"},
    // longitudinal, pure slip
    {"PCX1", 1.65, "shape factor Cx"},
    {"PDX1", 1.0, "longitudinal friction mu_x at FNOMIN"},
    {"PDX2", 0, "variation of mu_x with load"},
    {"PEX1", -0.5, "curvature factor Ex at FNOMIN"},
    {"PEX2", 0, "variation of Ex with load"},
    {"PEX3", 0, "variation of Ex with load squared"},
    {"PEX4", 0, "Ex's asymmetry in the slip's sign"},
    {"PKX1", 20, "slip stiffness Kx / Fz at FNOMIN"},
    {"PKX2", 0, "variation of Kx / Fz with load"},
    {"PKX3", 0, "exponential variation of Kx / Fz with load"},
    {"PHX1", 0, "horizontal shift SHx at FNOMIN"},
    {"PHX2", 0, "variation of SHx with load"},
    {"PVX1", 0, "vertical shift SVx / Fz at FNOMIN"},
    {"PVX2", 0, "variation of SVx / Fz with load"},
    // lateral, pure slip (ISO: a positive slip angle gives a negative force, so PKY1 < 0)
    {"PCY1", 1.3, "shape factor Cy"},
    {"PDY1", 1.0, "lateral friction mu_y at FNOMIN"},
    {"PDY2", 0, "variation of mu_y with load"},
    {"PEY1", -1.0, "curvature factor Ey at FNOMIN"},
    {"PEY2", 0, "variation of Ey with load"},
    {"PEY3", 0, "Ey's asymmetry in the slip angle's sign"},
    {"PKY1", -15, "maximum of the cornering stiffness Ky / FNOMIN"},
    {"PKY2", 1.7, "load (/ FNOMIN) at which Ky is largest", units::Dimension::none(), true},
    {"PHY1", 0, "horizontal shift SHy at FNOMIN"},
    {"PHY2", 0, "variation of SHy with load"},
    {"PVY1", 0, "vertical shift SVy / Fz at FNOMIN"},
    {"PVY2", 0, "variation of SVy / Fz with load"},
    // combined slip
    {"RBX1", 12, "slope factor of Fx's reduction by slip angle"},
    {"RBX2", 10, "its variation with the slip ratio"},
    {"RCX1", 1, "shape factor of Fx's reduction"},
    {"RHX1", 0, "its shift"},
    {"RBY1", 7, "slope factor of Fy's reduction by slip ratio"},
    {"RBY2", 2.5, "its variation with the slip angle"},
    {"RBY3", 0, "its shift in the slip angle"},
    {"RCY1", 1, "shape factor of Fy's reduction"},
    {"RHY1", 0, "its shift at FNOMIN"},
    {"RHY2", 0, "its variation with load"},
    {"RVY1", 0, "slip-ratio-induced side force / (mu_y Fz) at FNOMIN"},
    {"RVY2", 0, "its variation with load"},
    {"RVY4", 0, "its variation with the slip angle"},
    {"RVY5", 1.9, "its variation with the slip ratio"},
    {"RVY6", 10, "its variation with the slip ratio (atan)"},
    // relaxation lengths
    {"PTX1", 0.8, "longitudinal relaxation length / R0 at FNOMIN", units::Dimension::none(), true},
    {"PTX2", 0, "its variation with load"},
    {"PTX3", 0, "its exponential variation with load"},
    {"PTY1", 2.0, "largest lateral relaxation length / R0", units::Dimension::none(), true},
    {"PTY2", 1.7, "load (/ FNOMIN) at which it is largest", units::Dimension::none(), true},
};


}  // namespace

std::optional<double> tyre_coefficient_default(const std::string& name) {
  for (const TyreSetting& s : kTyreSettings)
    if (name == s.name) return s.default_value;
  return std::nullopt;
}

std::optional<units::Dimension> tyre_setting_dimension(const std::string& name) {
  if (const Setting* s = find_setting(tyre_setting::kAll, name)) return s->dimension;
  for (const TyreSetting& s : kTyreSettings)
    if (name == s.name) return s.dimension;
  return std::nullopt;
}

std::vector<std::string> tyre_setting_names() {
  std::vector<std::string> names = setting_names(tyre_setting::kAll);
  for (const TyreSetting& s : kTyreSettings) names.push_back(s.name);
  return names;
}

void Collector::add_tyre(const AstJoint& t) {
  auto wheel = side(t.a);
  auto road = side(t.b);
  if (!wheel || !road) return;
  const Body& w = m_.bodies.at(wheel->body);
  const std::string not_a_wheel = w.kind.visit(
      [&](const Ground&) { return fmt::format("tyre `{}` is on ground, not on a wheel", t.name); },
      [&](const Particle&) { return fmt::format("tyre `{}` is on `{}`, which is a particle", t.name, wheel->body); },
      [&](const Flexible&) { return fmt::format("tyre `{}` is on `{}`, which is a flexible body", t.name, wheel->body); },
      [](const Rigid&) { return std::string(); });
  if (!not_a_wheel.empty()) {
    diags_.error(t.a.loc, not_a_wheel,
                 "a tyre's first point is the centre of a rigid wheel (a body with an inertia, turning on its axle)");
    return;
  }
  if (road->body != "ground" || !road->point.empty()) {
    diags_.error(t.b.loc, fmt::format("the road of tyre `{}` must be `ground`", t.name),
                 "the road is the world's plane z = 0 (or z = h(x) with profile = [[x1, h1], ...]): write tyre " + t.name +
                     "(wheel.centre, ground)");
    return;
  }
  Tyre tyre{&t, *wheel, {}};
  const bool ok = collect_settings(t, tyre_setting_names(), tyre.attrs,
                                   "its settings are axis, profile and the Magic Formula's coefficients as a .tir file names "
                                   "them (FNOMIN, UNLOADED_RADIUS, VERTICAL_STIFFNESS, PCX1, PDX1, ..., PKY1, ..., RBX1, ..., "
                                   "PTX1, PTY1)");
  for (const AstAttr& at : t.attrs) {  // in the text's order, each collected setting once
    if (auto it = tyre.attrs.find(at.key); it == tyre.attrs.end() || it->second != &at) continue;
    if (at.key == tyre_setting::axis.name)
      check_shape(*at.value, fmt::format("`axis` of tyre `{}`", t.name), *tyre_setting::axis.expected);
    else if (at.key != tyre_setting::profile.name)
      check_shape(*at.value, fmt::format("`{}` of tyre `{}`", at.key, t.name), {{1, 1}, "a tyre coefficient is a scalar"});
  }
  if (!ok) return;
  if (const AstAttr* profile = given_in(tyre.attrs, tyre_setting::profile)) check_profile(tyre, *profile->value);
  for (const TyreSetting& s : kTyreSettings) {
    auto it = tyre.attrs.find(s.name);
    if (!s.positive || it == tyre.attrs.end()) continue;
    const char* key = s.name;
    if (auto v = constants_.constant_of(*it->second->value); v && !(*v > 0))
      diags_.error(it->second->value->loc, fmt::format("{} of tyre `{}` is {}", key, t.name, *v), fmt::format("{} must be > 0", key));
  }
  if (diags_.has_errors()) return;
  m_.loads[wheel->body].push_back(TyreSym(t.name));  // its loads on the wheel (apply_load)
  m_.tyres.push_back(std::move(tyre));
}

/// `profile = [[x1, h1], [x2, h2], ...]`: two or more points of the road's
/// height along world x, x increasing; constant before the first and after
/// the last.
void Collector::check_profile(const Tyre& tyre, const AstExpr& v) {
  const char* how = "write profile = [[x1, h1], [x2, h2], ...]: the road's height h (m) at world x (m), x increasing; "
                    "between the points it is linear, outside them constant";
  const bool listed = v.kind == AstExpr::Kind::List && v.args.size() >= 2 &&
                      std::all_of(v.args.begin(), v.args.end(), [](const auto& p) { return p->kind == AstExpr::Kind::List && p->args.size() == 2; });
  if (!listed) {
    diags_.error(v.loc, fmt::format("the profile of tyre `{}` is not a list of two or more [x, h] pairs", tyre.decl->name), how);
    return;
  }
  std::optional<double> previous;
  for (const auto& p : v.args) {
    auto x = constants_.constant_of(*p->args[0]);
    if (!x) {
      diags_.error(p->args[0]->loc, fmt::format("the profile of tyre `{}` has an x that is not a number", tyre.decl->name),
                   "the points of a profile are numbers (or parameters of numbers)");
      return;
    }
    if (previous && !(*x > *previous)) {
      diags_.error(p->args[0]->loc, fmt::format("the profile of tyre `{}` does not increase in x at {}", tyre.decl->name, *x), how);
      return;
    }
    previous = x;
  }
}

void Expander::emit_tyre(const Tyre& tyre) {
  const TyreSym tn(tyre.decl->name);
  const std::string& wheel = tyre.wheel.body;
  Build B(tyre.decl->loc, symbols_);
  auto p = [&](const std::string& key) { return B.ref(tn.setting(key)); };
  // Properties: folded where they are numbers (the defaults' zeros remove
  // whole terms), run-time parameters where the model gives a parameter.
  for (const TyreSetting& s : kTyreSettings) {
    auto it = tyre.attrs.find(s.name);
    property(B, tn.setting(s.name), it == tyre.attrs.end() ? B.num(s.default_value) : term(it->second->value));
  }
  auto sig = [&](const std::string& what, E value) {
    signal(B, tn.signal(what), std::move(value));
    return B.ref(tn.signal(what));
  };
  auto mul = [&](E a, E b) { return B.op('*', std::move(a), std::move(b)); };
  auto add = [&](E a, E b) { return B.op('+', std::move(a), std::move(b)); };
  auto sub = [&](E a, E b) { return B.op('-', std::move(a), std::move(b)); };
  auto div = [&](E a, E b) { return B.op('/', std::move(a), std::move(b)); };
  auto fn = [&](const char* f, E a) { return B.call(f, {std::move(a)}); };
  auto num = [&](double v) { return B.num(v); };
  // Identities that save a transcendental call each: cos(atan u) = 1 / sqrt(1 + u^2),
  // sin(2 atan u) = 2 u / (1 + u^2).
  auto cos_atan = [&](E u) { return div(num(1), fn("sqrt", add(num(1), mul(u, u)))); };
  auto sin_2atan = [&](E u) { return div(mul(num(2), u), add(num(1), mul(u, u))); };
  auto is_one = [&](const char* key) {  // a setting that is (by default or literally) 1
    auto it = tyre.attrs.find(key);
    if (it == tyre.attrs.end()) return true;
    auto v = constants_.constant_of(*it->second->value);
    return v && *v == 1;
  };

  // The wheel: its centre, its velocity, its axle and angular velocity (world).
  auto [centre, v_centre] = world_point(B, tyre.wheel);
  E R = rotation(B, wheel);
  const AstAttr* axis = given_in(tyre.attrs, tyre_setting::axis);
  E axis_local = axis ? term(axis->value) : B.default_of(tyre_setting::axis);
  E axle = mul(R, div(axis_local, B.call("norm", {axis_local})));
  E omega = mul(R, B.ref(BodySym(wheel).w().flow()));

  // The road below the centre: height h(x) and slope h'(x) along world x.
  E h = num(0), slope = num(0);
  if (const AstAttr* profile = given_in(tyre.attrs, tyre_setting::profile)) {
    const AstExpr& pts = *profile->value;
    E x = sig("x", B.at(centre, 1));
    h = sig("road_height", B.call("table", {x, term(profile->value)}));  // the language's table: exact kinks
    // its slope: each segment's between its two points (select: a step that is no event)
    for (std::size_t k = 0; k + 1 < pts.args.size(); ++k) {
      const E x0 = term(pts.args[k]->args[0]), h0 = term(pts.args[k]->args[1]), x1 = term(pts.args[k + 1]->args[0]), h1 = term(pts.args[k + 1]->args[1]);
      slope = add(slope, mul(div(sub(h1, h0), sub(x1, x0)), sub(fn("select", sub(x, x0)), fn("select", sub(x, x1)))));
    }
    slope = sig("road_slope", slope);
  }
  E root = fn("sqrt", add(num(1), mul(slope, slope)));
  E n = sig_vector(B, tn.normal(), B.list({div(B.neg(slope), root), num(0), div(num(1), root)}));
  E hc = sig("centre_height", div(sub(B.at(centre, 3), h), root));
  E ex = B.call("cross", {axle, n});
  ex = sig_vector(B, tn.forward(), div(ex, B.call("norm", {ex})));
  E ey = sig_vector(B, tn.left(), B.call("cross", {n, ex}));

  // Vertical: the radial spring and damper, pushing only.
  E rho = sig("deflection", sub(p("UNLOADED_RADIUS"), hc));
  E rho_rate = B.neg(B.dot(n, v_centre));
  E fz = sig("Fz", B.call("max", {num(0), add(mul(p("VERTICAL_STIFFNESS"), rho), mul(p("VERTICAL_DAMPING"), rho_rate))}));
  E dfz = sig("dfz", div(sub(fz, p("FNOMIN")), p("FNOMIN")));

  // Slip velocities and the relaxation equations (lagged slips are states).
  E vcx = sig("Vcx", B.dot(ex, v_centre));
  E vcy = sig("Vcy", B.dot(ey, v_centre));
  E spin = sig("spin", B.dot(axle, omega));
  E vsx = sig("Vsx", sub(vcx, mul(sub(p("UNLOADED_RADIUS"), rho), spin)));
  E floor = mul(num(0.01), p("UNLOADED_RADIUS"));
  E sigma_kappa = sig("sigma_kappa", B.call("max", {floor, mul(mul(mul(fz, add(p("PTX1"), mul(p("PTX2"), dfz))),
                                                                       fn("exp", B.neg(mul(p("PTX3"), dfz)))),
                                                                   div(p("UNLOADED_RADIUS"), p("FNOMIN")))}));
  E sigma_alpha = sig("sigma_alpha", B.call("max", {floor, mul(mul(p("PTY1"), sin_2atan(div(fz, mul(p("PTY2"), p("FNOMIN"))))),
                                                               p("UNLOADED_RADIUS"))}));
  auto lag = [&](const std::string& slip, E rate) {
    const SourceLoc& at = tyre.decl->loc;
    element(B, "Sf", tn.lag_rate(slip), std::move(rate));
    element(B, "C", tn.lag(slip), nullptr, {kv(element_setting::c_effort, num(0), at), kv(element_setting::q0, num(0), at)});
    junction_(B, tn.lag_junction(slip), {tn.lag_rate(slip)}, {tn.lag(slip)});
    return B.ref(tn.lag(slip).displacement());
  };
  E speed = fn("abs", vcx);
  E kappa = lag("kappa", div(sub(B.neg(vsx), mul(speed, B.ref(tn.lag("kappa").displacement()))), sigma_kappa));
  E tan_alpha = lag("tan_alpha", div(sub(vcy, mul(speed, B.ref(tn.lag("tan_alpha").displacement()))), sigma_alpha));
  E alpha = sig("slip_angle", fn("atan", tan_alpha));
  quantities_.define(tn.slip_ratio(), kappa);

  // Magic Formula, pure slip.
  auto magic = [&](E b, E c, E d, E e, E x) {  // D sin(C atan(B x - E (B x - atan(B x))))
    E bx = mul(b, x);
    return mul(d, fn("sin", mul(c, fn("atan", sub(bx, mul(e, sub(bx, fn("atan", bx))))))));
  };
  auto signed_ = [&](const char* coefficient, E x) {  // 1 - P sign(x), only when P may be nonzero
    auto it = tyre.attrs.find(coefficient);
    if (it == tyre.attrs.end()) return num(1);
    if (auto v = constants_.constant_of(*it->second->value); v && *v == 0) return num(1);
    return sub(num(1), mul(p(coefficient), fn("sign", x)));
  };
  E kx = sig("kappa_x", add(kappa, add(p("PHX1"), mul(p("PHX2"), dfz))));
  E mux = mul(add(p("PDX1"), mul(p("PDX2"), dfz)), p("LMUX"));
  E dx = sig("Dx", mul(mux, fz));
  E ex_ = mul(add(add(p("PEX1"), mul(p("PEX2"), dfz)), mul(p("PEX3"), mul(dfz, dfz))), signed_("PEX4", kx));
  E kxk = sig("Kx", mul(mul(fz, add(p("PKX1"), mul(p("PKX2"), dfz))), fn("exp", mul(p("PKX3"), dfz))));
  E bx = div(kxk, add(mul(p("PCX1"), dx), num(1e-9)));
  E fx0 = sig("Fx0", add(magic(bx, p("PCX1"), dx, ex_, kx), mul(fz, add(p("PVX1"), mul(p("PVX2"), dfz)))));

  E ay = sig("alpha_y", add(alpha, add(p("PHY1"), mul(p("PHY2"), dfz))));
  E muy = sig("mu_y", mul(add(p("PDY1"), mul(p("PDY2"), dfz)), p("LMUY")));
  E dy = sig("Dy", mul(muy, fz));
  E ey_ = mul(add(p("PEY1"), mul(p("PEY2"), dfz)), signed_("PEY3", ay));
  E kya = sig("Ky", mul(mul(p("PKY1"), p("FNOMIN")), sin_2atan(div(fz, mul(p("PKY2"), p("FNOMIN"))))));
  E by = div(kya, add(mul(p("PCY1"), dy), num(1e-9)));
  E fy0 = sig("Fy0", add(magic(by, p("PCY1"), dy, ey_, ay), mul(fz, add(p("PVY1"), mul(p("PVY2"), dfz)))));

  // Combined slip: cosine weights.
  auto weight = [&](E b, const char* c, E shift, E x) {  // cos(C atan(B (x + S))) / cos(C atan(B S))
    if (is_one(c)) return div(cos_atan(mul(b, add(x, shift))), cos_atan(mul(b, shift)));
    return div(fn("cos", mul(p(c), fn("atan", mul(b, add(x, shift))))), fn("cos", mul(p(c), fn("atan", mul(b, shift)))));
  };
  E bxa = mul(p("RBX1"), cos_atan(mul(p("RBX2"), kappa)));
  E gxa = sig("Gx", weight(bxa, "RCX1", p("RHX1"), alpha));
  E byk = mul(p("RBY1"), cos_atan(mul(p("RBY2"), sub(alpha, p("RBY3")))));
  E gyk = sig("Gy", weight(byk, "RCY1", add(p("RHY1"), mul(p("RHY2"), dfz)), kappa));
  E dvyk = mul(mul(dy, add(p("RVY1"), mul(p("RVY2"), dfz))), cos_atan(mul(p("RVY4"), alpha)));
  E svyk = mul(dvyk, fn("sin", mul(p("RVY5"), fn("atan", mul(p("RVY6"), kappa)))));
  E fx = sig("Fx", mul(gxa, fx0));
  E fy = sig("Fy", add(mul(gyk, fy0), svyk));

  // On the wheel: the force at the contact point, hc below the centre along -n.
  E force = sig_vector(B, tn.force(), add(add(mul(fx, ex), mul(fy, ey)), mul(fz, n)));
  E torque = B.call("cross", {mul(B.neg(hc), n), force});
  quantities_.define(tn.contact_point(), sub(centre, mul(hc, n)));
  // the power of the road's force on the wheel: F . v of the wheel's material point at the contact
  quantities_.define(tn.power(), B.dot(force, add(v_centre, B.call("cross", {omega, mul(B.neg(hc), n)}))));
  apply_load(B, tn, tyre.wheel, force, torque, 1.0);
}

/// A 3-vector as three signals (vectors cannot be signals: VectorSym), the
/// expression of their list, which is also the quantity `name`.
E Expander::sig_vector(const Build& B, const VectorSym& name, E value) {
  std::vector<E> items;
  for (int i = 1; i <= 3; ++i) {
    signal(B, name.component(i), B.at(value, i));
    items.push_back(B.ref(name.component(i)));
  }
  E v = B.list(std::move(items));
  quantities_.define(name, v);
  return v;
}

}  // namespace mbgc::multibody::detail
