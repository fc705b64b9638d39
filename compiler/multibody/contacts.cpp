// multibody/contacts.cpp — contacts: a sphere on a body point touching a
// surface (plane, sphere, cylinder) through a point of another body.
//
// A contact is written like a joint with one row: its gap g (>= 0 apart) is a
// position-level function of both bodies; MTFs carry each body's velocity to
// the rate g' on a 0-junction, where a CN with a restitution holds the
// contact's law (graph/build_graph: LawForm::Unilateral or Compliant). Its
// effort, times the MTFs' transposes, is the normal force on both bodies,
// moments and modal forces included: the same path joints take, for rigid
// bodies, particles, beams and modal bodies, in body or joint coordinates.
// Friction is a regularised Coulomb load at the contact point (apply_load).
#include "multibody/collect.hpp"
#include "multibody/expander.hpp"
#include "multibody/setting_names.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <tuple>

namespace mbgc::multibody::detail {

namespace {

const std::vector<std::string> kContactSettings = setting_names(contact_setting::kAll);
/// The words of `surface` and `strategy`, in the order of Surface and ContactStrategy.
const std::vector<std::string> kSurfaces = {"plane", "sphere", "cylinder", "polygon"};
const std::vector<std::string> kStrategies = {"unilateral", "compliant"};

}  // namespace

std::vector<std::string> contact_setting_names() { return kContactSettings; }

/// `vertices = [[x1, z1], [x2, z2], ...]`: at least three corners of a convex
/// polygon in the surface body's x-z plane, counter-clockwise (x to the right,
/// z up); when they are numbers, checked.
void Collector::check_polygon(const Contact& contact) {
  const AstJoint& c = *contact.decl;
  auto it = contact.attrs.find(contact_setting::vertices.name);
  const char* how = "write vertices = [[x1, z1], [x2, z2], [x3, z3], ...]: the corners of a convex polygon in the "
                    "surface body's x-z plane, counter-clockwise (x to the right, z up); it is extruded along y";
  if (it == contact.attrs.end()) {
    diags_.error(c.loc, fmt::format("the polygon of contact `{}` has no vertices", c.name), how);
    return;
  }
  const AstExpr& v = *it->second->value;
  const bool listed = v.kind == AstExpr::Kind::List && v.args.size() >= 3 &&
                      std::all_of(v.args.begin(), v.args.end(), [](const auto& p) { return p->kind == AstExpr::Kind::List && p->args.size() == 2; });
  if (!listed) {
    diags_.error(v.loc, fmt::format("the vertices of contact `{}` are not a list of three or more [x, z] pairs", c.name), how);
    return;
  }
  std::vector<std::array<double, 2>> corners;
  for (const auto& p : v.args) {
    auto x = constants_.constant_of(*p->args[0]), z = constants_.constant_of(*p->args[1]);
    if (!x || !z) return;  // (parameters: not checked)
    corners.push_back({*x, *z});
  }
  const std::size_t n = corners.size();
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = corners[i];
    const auto& b = corners[(i + 1) % n];
    const auto& d = corners[(i + 2) % n];
    const double turn = (b[0] - a[0]) * (d[1] - b[1]) - (b[1] - a[1]) * (d[0] - b[0]);
    if (turn <= 0) {
      diags_.error(v.args[(i + 1) % n]->loc,
                   fmt::format("the polygon of contact `{}` turns {} at vertex {}", c.name, turn < 0 ? "clockwise" : "straight", (i + 1) % n + 1),
                   how);
      return;
    }
  }
}

void Collector::add_contact(const AstJoint& c) {
  auto a = side(c.a);
  auto b = side(c.b);
  if (!a || !b) return;
  if (a->body == b->body) {
    diags_.error(c.loc, fmt::format("contact `{}` is between `{}` and itself", c.name, a->body),
                 "a contact is between two different bodies (or a body and ground)");
    return;
  }
  const auto default_surface = std::find(kSurfaces.begin(), kSurfaces.end(), contact_setting::surface.by_default.value);
  Contact contact{&c, *a, *b, static_cast<Surface>(default_surface - kSurfaces.begin()), contact_strategy_, {}};
  bool ok = collect_settings(c, kContactSettings, contact.attrs, fmt::format("it takes {}", fmt::join(kContactSettings, ", ")));
  for (const AstAttr& at : c.attrs) {  // in the text's order, each collected setting once
    if (auto it = contact.attrs.find(at.key); it == contact.attrs.end() || it->second != &at) continue;
    if (at.key == contact_setting::surface.name || at.key == contact_setting::strategy.name) {
      const bool surface = at.key == contact_setting::surface.name;
      const std::vector<std::string>& choices = surface ? kSurfaces : kStrategies;
      const std::string word = at.value->kind == AstExpr::Kind::Name ? at.value->name : "";
      auto it = std::find(choices.begin(), choices.end(), word);
      if (it == choices.end()) {
        std::string near = word.empty() ? "" : closest_name(word, choices);
        diags_.error(at.value->loc,
                     word.empty() ? fmt::format("the {} of contact `{}` must be a word", at.key, c.name)
                                  : fmt::format("unknown contact {} `{}`", at.key, word),
                     near.empty() ? fmt::format("write {} = {}", at.key, fmt::join(choices, " | "))
                                  : fmt::format("did you mean `{}`?", near));
        ok = false;
        continue;
      }
      const auto index = it - choices.begin();
      if (surface) contact.surface = static_cast<Surface>(index);
      else contact.strategy = static_cast<ContactStrategy>(index);
      continue;
    }
    if (at.key == contact_setting::vertices.name) continue;  // (checked below, with the surface)
    check_shape(*at.value, fmt::format("`{}` of contact `{}`", at.key, c.name),
                *find_setting(contact_setting::kAll, at.key)->expected);
  }
  if (!ok) return;
  using namespace contact_setting;
  auto given = [&](const Setting& s) { return given_in(contact.attrs, s) != nullptr; };
  auto constant = [&](const Setting& s) -> std::optional<double> {
    return given(s) ? constants_.constant_of(*given_in(contact.attrs, s)->value) : std::nullopt;
  };
  auto error_at = [&](const Setting& s) { return given(s) ? given_in(contact.attrs, s)->value->loc : c.loc; };
  const Body& surface_body = m_.bodies.at(b->body);
  const char* surface_name = contact.surface == Surface::Plane    ? "plane"
                             : contact.surface == Surface::Sphere ? "sphere"
                             : contact.surface == Surface::Cylinder ? "cylinder"
                                                                    : "polygon";
  if (surface_body.kind.particle() && contact.surface != Surface::Sphere)
    diags_.error(c.loc, fmt::format("a {} on `{}`, which is a particle", surface_name, b->body),
                 fmt::format("a particle has no orientation to carry a {}: put a sphere on it (surface = sphere; "
                             "surface_radius = R), or give `{}` an inertia",
                             surface_name, b->body));
  if (contact.surface == Surface::Plane && !given(normal))
    diags_.error(c.loc, fmt::format("the plane of contact `{}` has no normal", c.name),
                 fmt::format("give its outward normal in `{}`'s frame, e.g. normal = [0, 0, 1]", b->body));
  if (contact.surface == Surface::Cylinder && !given(axis))
    diags_.error(c.loc, fmt::format("the cylinder of contact `{}` has no axis", c.name),
                 fmt::format("give its axis in `{}`'s frame, e.g. axis = [0, 0, 1]", b->body));
  const bool round = contact.surface == Surface::Sphere || contact.surface == Surface::Cylinder;
  if (round && !given(surface_radius))
    diags_.error(c.loc, fmt::format("the {} of contact `{}` has no radius", surface_name, c.name),
                 "give it: surface_radius = R (m)");
  if (!round && given(surface_radius))
    diags_.error(given_in(contact.attrs, surface_radius)->loc, fmt::format("a {} has no radius (contact `{}`)", surface_name, c.name),
                 "remove surface_radius, or make the surface a sphere or a cylinder");
  if (contact.surface == Surface::Polygon) check_polygon(contact);
  else if (given(vertices))
    diags_.error(given_in(contact.attrs, vertices)->loc, fmt::format("a {} has no vertices (contact `{}`)", surface_name, c.name),
                 "vertices belong to surface = polygon");
  for (const Setting* s : {&radius, &surface_radius, &friction, &slip_speed, &stiffness}) {
    auto v = constant(*s);
    if (!v) continue;
    const bool positive = s == &slip_speed || s == &stiffness;
    if (positive ? *v > 0 : *v >= 0) continue;
    const char* key = s->name;
    diags_.error(error_at(*s), fmt::format("the {} of contact `{}` is {}", key, c.name, *v),
                 s == &friction ? "a Coulomb coefficient is >= 0 (0: frictionless)"
                 : positive                          ? fmt::format("the {} must be > 0", key)
                                                     : fmt::format("a {} is >= 0", key));
  }
  if (auto e = constant(restitution); e && (*e < 0 || *e > 1))
    diags_.error(error_at(restitution), fmt::format("the restitution of contact `{}` is {}", c.name, *e),
                 "Newton's coefficient is in [0, 1]: 0 a plastic impact, 1 an elastic one");
  if (contact.strategy == ContactStrategy::Compliant) {
    if (!given(stiffness))
      diags_.error(c.loc, fmt::format("compliant contact `{}` has no stiffness", c.name),
                   fmt::format("the Hunt-Crossley force is k d^n (1 + damping): give stiffness = k (N/m^{0} for the default "
                               "exponent {0})",
                               contact_setting::exponent.by_default.value));
    if (!given(restitution))
      diags_.error(c.loc, fmt::format("compliant contact `{}` has no restitution", c.name),
                   "its damping follows from the restitution e (0 < e <= 1): give restitution = e");
    else if (auto e = constant(restitution); e && *e == 0)
      diags_.error(error_at(restitution), fmt::format("compliant contact `{}` has restitution 0", c.name),
                   "a Hunt-Crossley force needs unbounded damping to stop a body dead: give e > 0, or use the "
                   "unilateral strategy");
  }
  // (a unilateral contact keeps its stiffness and exponent, a compliant one its stabilisation: unused,
  // they describe the contact under the other strategy, which mbgc --contacts may choose)
  if (given(slip_speed) && !given(friction))
    diags_.error(given_in(contact.attrs, slip_speed)->loc, fmt::format("contact `{}` has a slip speed but no friction", c.name),
                 "add friction = mu, or remove slip_speed");
  if (given(friction) && contact.strategy == ContactStrategy::Compliant)  // (a unilateral contact's friction: its rows)
    for (const Side* sd : {&contact.a, &contact.b})
      if (!m_.bodies.at(sd->body).kind.ground()) m_.loads[sd->body].push_back(ContactSym(c.name).friction_load());
  if (!diags_.has_errors()) m_.contacts.push_back(std::move(contact));
}

/// A convex polygon's signed distance to local point d (in its x-z plane),
/// and the outward normal there (local): outside, the distance to the nearest
/// edge (the normal: the edge's, or from its nearest end where that is
/// nearest); inside, the largest of the signed distances to the edges' lines.
/// C1 outside; a sphere of radius r around the point keeps the distance >= r
/// while it touches, so the direction to a corner is always defined.
std::pair<E, E> Expander::polygon_gap(const Build& B, const Contact& c, E d) {
  const AstExpr& v = *c.attrs.at(contact_setting::vertices.name)->value;
  const std::size_t n = v.args.size();
  const E X = B.at(d, 1), Z = B.at(d, 3);
  auto step = [&](E x) { return B.call("select", {x}); };  // (continuous choices: not events)
  auto pick = [&](E w, E a, E b) { return B.op('+', B.op('*', w, a), B.op('*', B.op('-', B.num(1), w), b)); };
  E dist, near_normal, inside, inside_normal;
  for (std::size_t i = 0; i < n; ++i) {
    const AstExpr& a = *v.args[i];
    const AstExpr& b = *v.args[(i + 1) % n];
    E ax = term(a.args[0]), az = term(a.args[1]);
    E ex = B.op('-', term(b.args[0]), ax), ez = B.op('-', term(b.args[1]), az);
    E len2 = B.op('+', B.op('*', ex, ex), B.op('*', ez, ez)), len = B.call("sqrt", {len2});
    E rx = B.op('-', X, ax), rz = B.op('-', Z, az);
    E along = B.op('/', B.op('+', B.op('*', rx, ex), B.op('*', rz, ez)), len2);
    E s = B.call("min", {B.num(1), B.call("max", {B.num(0), along})});
    E px = B.op('-', rx, B.op('*', s, ex)), pz = B.op('-', rz, B.op('*', s, ez));  // from the nearest point of the edge
    E di = B.call("sqrt", {B.op('+', B.op('*', px, px), B.op('*', pz, pz))});
    E face = B.list({B.op('/', ez, len), B.num(0), B.op('/', B.neg(ex), len)});  // outward (counter-clockwise)
    E at_end = B.op('+', step(B.neg(along)), step(B.op('-', along, B.num(1))));  // 1 beyond either end
    E corner = B.list({B.op('/', px, di), B.num(0), B.op('/', pz, di)});
    E ni = pick(at_end, corner, face);
    E hi = B.op('/', B.op('-', B.op('*', rx, ez), B.op('*', rz, ex)), len);  // signed, to the edge's line
    if (i == 0) {
      dist = di, near_normal = ni, inside = hi, inside_normal = face;
      continue;
    }
    E closer = step(B.op('-', dist, di));  // 1 where this edge is nearer
    near_normal = pick(closer, ni, near_normal);
    dist = B.call("min", {dist, di});
    E higher = step(B.op('-', hi, inside));
    inside_normal = pick(higher, face, inside_normal);
    inside = B.call("max", {inside, hi});
  }
  E out = step(inside);  // 1 outside (or on it)
  return {pick(out, dist, inside), pick(out, near_normal, inside_normal)};
}

void Expander::emit_contact(const Contact& c) {
  const ContactSym cn(c.decl->name);
  Build B(c.decl->loc, symbols_);
  auto setting = [&](const Setting& s, E fallback) -> E {
    const AstAttr* given = given_in(c.attrs, s);
    return given ? term(given->value) : fallback;
  };
  auto setting_or_default = [&](const Setting& s) { return setting(s, B.default_of(s)); };
  param(B, cn.radius(), setting_or_default(contact_setting::radius));
  param(B, cn.restitution(), setting_or_default(contact_setting::restitution));
  const Body& a = m_.bodies.at(c.a.body);
  const Body& b = m_.bodies.at(c.b.body);
  auto [pa, va] = world_point(B, c.a);
  auto [pb, vb] = world_point(B, c.b);
  E Rb = !b.kind.turns() ? nullptr : rotation(B, c.b.body);
  auto turned = [&](E local) { return Rb ? B.op('*', Rb, local) : local; };
  E d = B.op('-', pa, pb);
  E gap, normal;
  if (c.surface == Surface::Polygon) {
    std::tie(gap, normal) = polygon_gap(B, c, Rb ? B.op('*', B.call("transpose", {Rb}), d) : d);
    normal = turned(normal);
  } else if (c.surface == Surface::Plane) {
    E n = setting(contact_setting::normal, nullptr);
    property(B, cn.normal_b(), B.op('/', n, B.call("norm", {n})));
    normal = turned(B.ref(cn.normal_b()));
    gap = B.dot(normal, d);
  } else {
    param(B, cn.surface_radius(), setting(contact_setting::surface_radius, nullptr));
    E radial = d;
    if (c.surface == Surface::Cylinder) {
      E axis = setting(contact_setting::axis, nullptr);
      property(B, cn.axis_b(), B.op('/', axis, B.call("norm", {axis})));
      E ax = turned(B.ref(cn.axis_b()));
      radial = B.op('-', d, B.op('*', B.dot(ax, d), ax));
    }
    E len = B.call("norm", {radial});
    normal = B.op('/', radial, len);
    gap = B.op('-', len, B.ref(cn.surface_radius()));
  }
  gap = B.op('-', gap, B.ref(cn.radius()));
  const bool unilateral = c.strategy == ContactStrategy::Unilateral;
  const bool friction = given_in(c.attrs, contact_setting::friction) != nullptr;
  if (friction) param(B, cn.friction(), setting(contact_setting::friction, nullptr));
  // the contact point: on A's sphere, towards the surface
  E point = B.op('-', pa, B.op('*', B.ref(cn.radius()), normal));
  // The rows: the gap and, for a unilateral contact with friction, the two
  // tangential rows whose rate is the sliding velocity of the bodies' material
  // points at the contact: t_i . (a's point - b's point), the tangents and the
  // points' arms frozen (their rates are the bodies' own motion, not the
  // contact point's travel over them).
  std::vector<E> rows = {gap};
  if (unilateral && friction) {
    E t1, t2;
    if (c.surface == Surface::Cylinder) {
      t1 = turned(B.ref(cn.axis_b()));
    } else if (c.surface == Surface::Polygon) {
      t1 = turned(B.vec(0, 1, 0));  // the extrusion
    } else {
      // a fixed direction of the surface body not along the normal: its x axis, or y near the x axis
      E n_b = c.surface == Surface::Plane ? B.ref(cn.normal_b()) : B.vec(0, 0, 1);
      E pick = B.op('+', B.vec(1, 0, 0),
                    B.op('*', B.call("heaviside", {B.op('-', B.call("abs", {B.at(n_b, 1)}), B.num(0.9))}), B.vec(-1, 1, 0)));
      if (c.surface == Surface::Plane) {
        E across = B.call("cross", {n_b, pick});
        property(B, cn.tangent_b(), B.op('/', across, B.call("norm", {across})));
        t1 = turned(B.ref(cn.tangent_b()));
      } else {
        E across = B.call("cross", {normal, turned(pick)});
        t1 = B.op('/', across, B.call("norm", {across}));
      }
    }
    t2 = B.call("cross", {normal, t1});
    quantities_.define(cn.tangents(), B.call("hcat", {t1, t2}));
    auto material = [&](const Body& body, const Side& s, E p) -> E {  // the body's point now at `point`
      if (!body.kind.turns()) return B.op('+', p, B.call("frozen", {B.op('-', point, p)}));
      E R = rotation(B, s.body);
      return B.op('+', p, B.op('*', R, B.call("frozen", {B.op('*', B.call("transpose", {R}), B.op('-', point, p))})));
    };
    E slide = B.op('-', material(a, c.a, pa), material(b, c.b, pb));
    rows.push_back(B.dot(B.call("frozen", {t1}), slide));
    rows.push_back(B.dot(B.call("frozen", {t2}), slide));
  }
  const int dim = static_cast<int>(rows.size());
  E rows_vec = B.list(rows);
  // the row(s): body junctions -> MTFs (d rows / d position) -> 0-junction -> CN
  junction(B, '0', cn.rows(), dim, {}, {cn.constraint()});
  auto frame_of = [&](const Side& s, const Body& body) {
    Frame f;
    f.kind = body.kind;
    f.body = s.body;
    return f;
  };
  rates_into(B, [&](char flow) { return cn.row_rate('a', flow); }, rows_vec, frame_of(c.a, a), cn.rows(), true, true);
  rates_into(B, [&](char flow) { return cn.row_rate('b', flow); }, rows_vec, frame_of(c.b, b), cn.rows(), true, true);
  ir::ConstraintLaw law;
  law.g = rows_vec;
  law.restitution = B.ref(cn.restitution());
  if (c.strategy == ContactStrategy::Compliant) {
    param(B, cn.stiffness(), setting(contact_setting::stiffness, nullptr));
    param(B, cn.exponent(), setting_or_default(contact_setting::exponent));
    law.stiffness = B.ref(cn.stiffness());
    law.exponent = B.ref(cn.exponent());
  } else {
    param(B, cn.stabilisation(), setting_or_default(contact_setting::stabilisation));
    law.stabilisation = B.ref(cn.stabilisation());
    if (friction) law.friction = B.ref(cn.friction());
  }
  constraint(B, cn.constraint(), std::move(law));
  // The push (>= 0): the CN's effort, signed so that it parts the bodies
  // (power e f into the CN is -push * g'); the friction likewise.
  E effort = B.ref(cn.constraint().effort());
  E push = B.neg(dim == 1 ? effort : B.at(effort, 1));
  quantities_.define(cn.gap(), gap);
  quantities_.define(cn.normal(), normal);
  quantities_.define(cn.normal_force(), push);
  quantities_.define(cn.closed(), B.ref(cn.constraint().closed()));  // 1 while in contact
  if (unilateral && friction) quantities_.define(cn.stuck(), B.ref(cn.constraint().stick()));
  auto spin = [&](const Body& body, const Side& s) -> E {  // world angular velocity
    if (!body.kind.turns()) return nullptr;
    return B.op('*', rotation(B, s.body), B.ref(BodySym(s.body).w().flow()));
  };
  auto point_velocity = [&](E v, E w, E arm) { return w ? B.op('+', v, B.call("cross", {w, arm})) : v; };
  E slip = B.op('-', point_velocity(va, spin(a, c.a), B.op('-', point, pa)), point_velocity(vb, spin(b, c.b), B.op('-', point, pb)));
  E tangential = B.op('-', slip, B.op('*', B.dot(normal, slip), normal));
  quantities_.define(cn.slip_velocity(), tangential);
  E friction_force = B.vec(0, 0, 0);
  if (friction && unilateral) {
    // the CN's tangential rows: their efforts (signed like the push) along the tangents
    E tangents = quantities_.at(cn.tangents().str());
    friction_force = B.neg(B.op('*', tangents, B.list({B.at(effort, 2), B.at(effort, 3)})));
  } else if (friction) {
    // regularised Coulomb: -mu push vt / sqrt(|vt|^2 + eps^2) on A, its opposite on B
    param(B, cn.slip_speed(), setting_or_default(contact_setting::slip_speed));
    E eps = B.ref(cn.slip_speed());
    E scale = B.call("sqrt", {B.op('+', B.dot(tangential, tangential), B.op('*', eps, eps))});
    friction_force = B.op('*', B.op('/', B.neg(B.op('*', B.ref(cn.friction()), push)), scale), tangential);
    apply_load(B, cn.friction_load(), c.a, friction_force, B.call("cross", {B.op('-', point, pa), friction_force}), 1.0);
    apply_load(B, cn.friction_load(), c.b, friction_force, B.call("cross", {B.op('-', point, pb), friction_force}), -1.0);
  }
  quantities_.define(cn.friction_force(), friction_force);
  quantities_.define(cn.force(), B.op('+', B.op('*', push, normal), friction_force));
}

}  // namespace mbgc::multibody::detail
