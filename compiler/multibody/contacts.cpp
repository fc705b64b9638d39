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
#include "multibody/expander.hpp"

#include <fmt/format.h>

namespace mbgc::multibody::detail {

namespace {

const std::vector<std::string> kContactSettings = {"radius", "surface", "normal", "axis", "surface_radius",
                                                   "strategy", "restitution", "stiffness", "exponent",
                                                   "friction", "slip_speed", "stabilisation"};
const std::map<std::string, Expected> kContactShapes = {
    {"radius", {{1, 1}, "the radius of the sphere around the touching point is a scalar (m); 0: the point itself"}},
    {"normal", {{3, 1}, "a plane's outward normal is a direction [x, y, z] in the surface body's frame"}},
    {"axis", {{3, 1}, "a cylinder's axis is a direction [x, y, z] in the surface body's frame"}},
    {"surface_radius", {{1, 1}, "the radius of the surface's sphere or cylinder is a scalar (m)"}},
    {"restitution", {{1, 1}, "the coefficient of restitution is a scalar in [0, 1]"}},
    {"stiffness", {{1, 1}, "the contact stiffness is a scalar (N/m^exponent)"}},
    {"exponent", {{1, 1}, "the force exponent is a scalar (1.5: Hertz)"}},
    {"friction", {{1, 1}, "the friction coefficient is a scalar >= 0"}},
    {"slip_speed", {{1, 1}, "the slip speed of regularised friction is a scalar (m/s)"}},
    {"stabilisation", {{1, 1}, "the stabilisation is a scalar (rad/s)"}},
};

}  // namespace

void Expander::add_contact(const AstJoint& c) {
  auto a = side(c.a);
  auto b = side(c.b);
  if (!a || !b) return;
  if (a->body == b->body) {
    diags_.error(c.loc, fmt::format("contact `{}` is between `{}` and itself", c.name, a->body),
                 "a contact is between two different bodies (or a body and ground)");
    return;
  }
  Contact contact{&c, *a, *b, Surface::Plane, contact_strategy_, {}};
  bool ok = true;
  for (const AstAttr& at : c.attrs) {
    if (std::find(kContactSettings.begin(), kContactSettings.end(), at.key) == kContactSettings.end()) {
      std::string near = closest_name(at.key, kContactSettings);
      diags_.error(at.loc, fmt::format("a contact has no setting `{}`", at.key),
                   near.empty() ? fmt::format("it takes {}", fmt::join(kContactSettings, ", ")) : fmt::format("did you mean `{}`?", near));
      ok = false;
      continue;
    }
    if (auto first = contact.attrs.find(at.key); first != contact.attrs.end()) {
      auto& d = diags_.error(at.loc, fmt::format("`{}` of contact `{}` is given twice", at.key, c.name), "keep one of them");
      d.notes.push_back({first->second->loc, "first given here"});
      ok = false;
      continue;
    }
    contact.attrs[at.key] = &at;
    if (at.key == "surface" || at.key == "strategy") {
      const bool surface = at.key == "surface";
      const std::vector<std::string> choices = surface ? std::vector<std::string>{"plane", "sphere", "cylinder"}
                                                       : std::vector<std::string>{"unilateral", "compliant"};
      const std::string word = at.value->kind == AstExpr::Kind::Name ? at.value->name : "";
      auto it = std::find(choices.begin(), choices.end(), word);
      if (it == choices.end()) {
        std::string near = word.empty() ? "" : closest_name(word, choices);
        diags_.error(at.value->loc,
                     word.empty() ? fmt::format("the {} of contact `{}` is a word", at.key, c.name)
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
    check_shape(*at.value, fmt::format("`{}` of contact `{}`", at.key, c.name), kContactShapes.at(at.key));
  }
  if (!ok) return;
  auto given = [&](const char* key) { return contact.attrs.count(key) > 0; };
  auto constant = [&](const char* key) -> std::optional<double> {
    return given(key) ? constant_of(*contact.attrs.at(key)->value) : std::nullopt;
  };
  auto error_at = [&](const char* key) { return given(key) ? contact.attrs.at(key)->value->loc : c.loc; };
  const Body& surface_body = bodies_.at(b->body);
  const char* surface_name = contact.surface == Surface::Plane ? "plane" : contact.surface == Surface::Sphere ? "sphere" : "cylinder";
  if (surface_body.particle && contact.surface != Surface::Sphere)
    diags_.error(c.loc, fmt::format("a {} on `{}`, which is a particle", surface_name, b->body),
                 fmt::format("a particle has no orientation to carry a {}: put a sphere on it (surface = sphere; "
                             "surface_radius = R), or give `{}` an inertia",
                             surface_name, b->body));
  if (contact.surface == Surface::Plane && !given("normal"))
    diags_.error(c.loc, fmt::format("the plane of contact `{}` has no normal", c.name),
                 fmt::format("give its outward normal in `{}`'s frame, e.g. normal = [0, 0, 1]", b->body));
  if (contact.surface == Surface::Cylinder && !given("axis"))
    diags_.error(c.loc, fmt::format("the cylinder of contact `{}` has no axis", c.name),
                 fmt::format("give its axis in `{}`'s frame, e.g. axis = [0, 0, 1]", b->body));
  if (contact.surface != Surface::Plane && !given("surface_radius"))
    diags_.error(c.loc, fmt::format("the {} of contact `{}` has no radius", surface_name, c.name),
                 "give it: surface_radius = R (m)");
  if (contact.surface == Surface::Plane && given("surface_radius"))
    diags_.error(contact.attrs.at("surface_radius")->loc, fmt::format("a plane has no radius (contact `{}`)", c.name),
                 "remove surface_radius, or make the surface a sphere or a cylinder");
  for (const char* key : {"radius", "surface_radius", "friction", "slip_speed", "stiffness"}) {
    auto v = constant(key);
    if (!v) continue;
    const bool positive = std::string_view(key) == "slip_speed" || std::string_view(key) == "stiffness";
    if (positive ? *v > 0 : *v >= 0) continue;
    diags_.error(error_at(key), fmt::format("the {} of contact `{}` is {}", key, c.name, *v),
                 std::string_view(key) == "friction" ? "a Coulomb coefficient is >= 0 (0: frictionless)"
                 : positive                          ? fmt::format("the {} must be > 0", key)
                                                     : fmt::format("a {} is >= 0", key));
  }
  if (auto e = constant("restitution"); e && (*e < 0 || *e > 1))
    diags_.error(error_at("restitution"), fmt::format("the restitution of contact `{}` is {}", c.name, *e),
                 "Newton's coefficient is in [0, 1]: 0 a plastic impact, 1 an elastic one");
  if (contact.strategy == ContactStrategy::Compliant) {
    if (!given("stiffness"))
      diags_.error(c.loc, fmt::format("compliant contact `{}` has no stiffness", c.name),
                   "the Hunt-Crossley force is k d^n (1 + damping): give stiffness = k (N/m^1.5 for the default exponent 1.5)");
    if (!given("restitution"))
      diags_.error(c.loc, fmt::format("compliant contact `{}` has no restitution", c.name),
                   "its damping follows from the restitution e (0 < e <= 1): give restitution = e");
    else if (auto e = constant("restitution"); e && *e == 0)
      diags_.error(error_at("restitution"), fmt::format("compliant contact `{}` has restitution 0", c.name),
                   "a Hunt-Crossley force needs unbounded damping to stop a body dead: give e > 0, or use the "
                   "unilateral strategy");
  }
  // (a unilateral contact keeps its stiffness and exponent, a compliant one its stabilisation: unused,
  // they describe the contact under the other strategy, which mbgc --contacts may choose)
  if (given("slip_speed") && !given("friction"))
    diags_.error(contact.attrs.at("slip_speed")->loc, fmt::format("contact `{}` has a slip speed but no friction", c.name),
                 "add friction = mu, or remove slip_speed");
  if (given("friction"))  // (the normal force comes through the row; friction is a load on each body)
    for (const Side* sd : {&contact.a, &contact.b})
      if (!bodies_.at(sd->body).ground) loads_[sd->body].push_back(c.name + ".friction");
  if (!diags_.has_errors()) contacts_.push_back(std::move(contact));
}

void Expander::emit_contact(const Contact& c) {
  const std::string cn = c.decl->name;
  Build B(c.decl->loc);
  auto setting = [&](const char* key, E fallback) -> E {
    auto it = c.attrs.find(key);
    return it == c.attrs.end() ? fallback : it->second->value;
  };
  param(B, cn + ".radius", setting("radius", B.num(0)));
  param(B, cn + ".restitution", setting("restitution", B.num(0)));
  const Body& a = bodies_.at(c.a.body);
  const Body& b = bodies_.at(c.b.body);
  auto [pa, va] = world_point(B, c.a);
  auto [pb, vb] = world_point(B, c.b);
  E Rb = b.ground || b.particle ? nullptr : rotation(B, c.b.body);
  auto turned = [&](E local) { return Rb ? B.op('*', Rb, local) : local; };
  E d = B.op('-', pa, pb);
  E gap, normal;
  if (c.surface == Surface::Plane) {
    E n = setting("normal", nullptr);
    property(B, cn + ".normal_b", B.op('/', n, B.call("norm", {n})));
    normal = turned(B.name(cn + ".normal_b"));
    gap = B.dot(normal, d);
  } else {
    param(B, cn + ".surface_radius", setting("surface_radius", nullptr));
    E radial = d;
    if (c.surface == Surface::Cylinder) {
      E axis = setting("axis", nullptr);
      property(B, cn + ".axis_b", B.op('/', axis, B.call("norm", {axis})));
      E ax = turned(B.name(cn + ".axis_b"));
      radial = B.op('-', d, B.op('*', B.dot(ax, d), ax));
    }
    E len = B.call("norm", {radial});
    normal = B.op('/', radial, len);
    gap = B.op('-', len, B.name(cn + ".surface_radius"));
  }
  gap = B.op('-', gap, B.name(cn + ".radius"));
  // the row: body junctions -> MTFs (d gap / d position) -> 0-junction -> CN
  E rows = B.list({gap});
  junction(B, '0', cn + ".c", 1, {}, {cn + ".cn"});
  auto frame_of = [&](const Side& s, const Body& body) {
    Frame f;
    f.ground = body.ground;
    f.particle = body.particle;
    f.body = s.body;
    return f;
  };
  rates_into(B, cn + ".ca", rows, frame_of(c.a, a), cn + ".c", true, true);
  rates_into(B, cn + ".cb", rows, frame_of(c.b, b), cn + ".c", true, true);
  std::vector<AstAttr> law = {kv("g", rows, B.loc()), kv("restitution", B.name(cn + ".restitution"), B.loc())};
  if (c.strategy == ContactStrategy::Compliant) {
    param(B, cn + ".stiffness", setting("stiffness", nullptr));
    param(B, cn + ".exponent", setting("exponent", B.num(1.5)));
    law.push_back(kv("stiffness", B.name(cn + ".stiffness"), B.loc()));
    law.push_back(kv("exponent", B.name(cn + ".exponent"), B.loc()));
  } else {
    param(B, cn + ".stabilisation", setting("stabilisation", B.num(20)));
    law.push_back(kv("stabilisation", B.name(cn + ".stabilisation"), B.loc()));
  }
  element(B, "CN", cn + ".cn", nullptr, law);
  // The push (>= 0): the CN's effort, signed so that it parts the bodies
  // (power e f into the CN is -push * g').
  E push = B.neg(B.name(cn + ".cn.e"));
  quantity_[cn + ".gap"] = gap;
  quantity_[cn + ".normal"] = normal;
  quantity_[cn + ".normal_force"] = push;
  // the contact point: on A's sphere, towards the surface
  E point = B.op('-', pa, B.op('*', B.name(cn + ".radius"), normal));
  auto spin = [&](const Body& body, const Side& s) -> E {  // world angular velocity
    if (body.ground || body.particle) return nullptr;
    return B.op('*', rotation(B, s.body), B.name(s.body + ".w.f"));
  };
  auto point_velocity = [&](E v, E w, E arm) { return w ? B.op('+', v, B.call("cross", {w, arm})) : v; };
  E slip = B.op('-', point_velocity(va, spin(a, c.a), B.op('-', point, pa)), point_velocity(vb, spin(b, c.b), B.op('-', point, pb)));
  E tangential = B.op('-', slip, B.op('*', B.dot(normal, slip), normal));
  quantity_[cn + ".slip_velocity"] = tangential;
  E friction_force = B.vec(0, 0, 0);
  if (c.attrs.count("friction")) {
    // regularised Coulomb: -mu push vt / sqrt(|vt|^2 + eps^2) on A, its opposite on B
    param(B, cn + ".friction", setting("friction", nullptr));
    param(B, cn + ".slip_speed", setting("slip_speed", B.num(1e-4)));
    E eps = B.name(cn + ".slip_speed");
    E scale = B.call("sqrt", {B.op('+', B.dot(tangential, tangential), B.op('*', eps, eps))});
    friction_force = B.op('*', B.op('/', B.neg(B.op('*', B.name(cn + ".friction"), push)), scale), tangential);
    apply_load(B, cn + ".friction.on_" + c.a.body, c.a, friction_force,
               B.call("cross", {B.op('-', point, pa), friction_force}), 1.0);
    apply_load(B, cn + ".friction.on_" + c.b.body, c.b, friction_force,
               B.call("cross", {B.op('-', point, pb), friction_force}), -1.0);
  }
  quantity_[cn + ".friction_force"] = friction_force;
  quantity_[cn + ".force"] = B.op('+', B.op('*', push, normal), friction_force);
}

}  // namespace mbgc::multibody::detail
