// multibody/collect.cpp — collect and check bodies, joints, force elements and settings.
#include "multibody/collect.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <set>
#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

Model Collector::run(const AstProgram& in) {
  collect(in);
  return std::move(m_);
}

void Collector::collect(const AstProgram& in) {
  Body ground;
  ground.kind = Ground{};
  ground.placed = true;
  m_.bodies["ground"] = ground;
  for (const AstStmt& s : in.stmts) {
    if (auto* p = std::get_if<AstParam>(&s)) m_.params[p->name] = p->value;
    if (auto* i = std::get_if<AstInstance>(&s)) instances_[i->name] = i->loc;
  }
  for (const AstStmt& s : in.stmts) {
    if (auto* b = std::get_if<AstBody>(&s)) add_body(*b);
    else if (auto* st = std::get_if<AstSetting>(&s)) setting(*st);
  }
  std::map<std::string, const AstJoint*> connectors;  // joints and force elements by name
  for (const AstStmt& s : in.stmts) {
    auto* j = std::get_if<AstJoint>(&s);
    if (!j || !connector_name_ok(*j, connectors)) continue;
    switch (j->connector) {
      case Connector::Joint: add_joint(*j); break;
      case Connector::Force: add_force(*j); break;
      case Connector::Contact: add_contact(*j); break;
      case Connector::Tyre: add_tyre(*j); break;
    }
  }
}

/// Joints and force elements name the parts they generate (`j1.cn`, `j1.angle`):
/// their names must differ from each other's and from the bodies'.
bool Collector::connector_name_ok(const AstJoint& j, std::map<std::string, const AstJoint*>& seen) {
  const char* what = connector_noun(j.connector);
  if (j.name == "ground") {
    diags_.error(j.loc, fmt::format("a {} cannot be named `ground`", what), "`ground` is the fixed frame: choose another name");
    return false;
  }
  if (auto b = m_.bodies.find(j.name); b != m_.bodies.end()) {
    auto& d = diags_.error(j.loc, fmt::format("{} `{}` has the name of a body", what, j.name),
                           fmt::format("bodies, joints and force elements share one namespace (`{}.angle`, `{}.position`): "
                                       "rename the {}, e.g. `{}_{}`",
                                       j.name, j.name, what, j.name, connector_keyword(j.connector)));
    d.notes.push_back({b->second.decl->loc, "the body is declared here"});
    return false;
  }
  if (auto inst = instances_.find(j.name); inst != instances_.end()) {
    auto& d = diags_.error(j.loc, fmt::format("{} `{}` has the name of an instance", what, j.name),
                           fmt::format("the {}'s parts (`{}.c`, `{}.cn`, ...) would mix with the instance's: rename one of them",
                                       what, j.name, j.name));
    d.notes.push_back({inst->second, "the instance is declared here"});
    return false;
  }
  auto [it, fresh] = seen.emplace(j.name, &j);
  if (!fresh) {
    const char* first = connector_noun(it->second->connector);
    if (std::string(first) != what) {
      auto& d = diags_.error(j.loc, fmt::format("{} `{}` has the name of a {}", what, j.name, first),
                             fmt::format("joints, force elements and contacts share one namespace (`{}.force`): rename one of them",
                                         j.name));
      d.notes.push_back({it->second->loc, fmt::format("the {} is declared here", first)});
      return false;
    }
    duplicate(what, j.name, j.loc, it->second->loc);
    return false;
  }
  return true;
}

/// A second declaration of `name`; inside a loop (the same statement again) reported once.
void Collector::duplicate(const char* what, const std::string& name, const SourceLoc& at, const SourceLoc& first) {
  if (at.file == first.file && at.line == first.line && at.col == first.col) {
    if (!repeated_.insert(name).second) return;
    diags_.error(at, fmt::format("{} `{}` is declared again in every iteration of the loop", what, name),
                 fmt::format("interpolate the loop variable into the name, e.g. {}{{i}}", name));
    return;
  }
  auto& d = diags_.error(at, fmt::format("{} `{}` is declared twice", what, name),
                         fmt::format("give each {} its own name", what));
  d.notes.push_back({first, "the first one is declared here"});
}

void Collector::setting(const AstSetting& st) {
  if (st.key == "gravity") {
    if (m_.gravity) {
      auto& d = diags_.error(st.loc, "gravity is set twice", "keep one `gravity = [gx, gy, gz]`");
      d.notes.push_back({m_.gravity_loc, "gravity is first set here"});
    }
    check_shape(*st.value, "gravity", {{3, 1}, "gravity is an acceleration in the world frame: gravity = [gx, gy, gz] (m/s^2), e.g. [0, -9.81, 0]"});
    m_.gravity = st.value;
    m_.gravity_loc = st.loc;
    return;
  }
  if (st.key == "constraints") {
    auto s = strategy_of(*st.value, "constraints");
    if (s && !override_) strategy_ = *s;
    return;
  }
  diags_.error(st.loc, fmt::format("unknown model setting `{}`", st.key), "model settings are `gravity = [...]` and `constraints = auto|lagrange|penalty|coordinates`");
}

/// `constraints = ...` (the model's) or `constraint = ...` (a joint's).
std::optional<Strategy> Collector::strategy_of(const AstExpr& v, const char* key) {
  const std::string choices =
      "auto (the default: coordinates where joint coordinates can move every joint, else lagrange), lagrange "
      "(multipliers: a DAE for IDA), penalty (stiff spring-dampers: an ODE) or coordinates (joint coordinates as "
      "states on a spanning tree, its loops closed by cut joints: an ODE)";
  const std::string how = fmt::format("write {} = {}", key, choices);
  if (v.kind == AstExpr::Kind::Name) {
    if (v.name == "auto") return Strategy::Auto;
    if (v.name == "lagrange") return Strategy::Lagrange;
    if (v.name == "penalty") return Strategy::Penalty;
    if (v.name == "coordinates") return Strategy::Coordinates;
    std::string near = closest_name(v.name, {"auto", "lagrange", "penalty", "coordinates"});
    diags_.error(v.loc, fmt::format("unknown constraint strategy `{}`", v.name),
                 near.empty() ? how : fmt::format("did you mean `{}`? The strategies are {}", near, choices));
    return std::nullopt;
  }
  diags_.error(v.loc, "a constraint strategy is a name: `auto`, `lagrange`, `penalty` or `coordinates`", how);
  return std::nullopt;
}

void Collector::add_body(const AstBody& b) {
  if (b.name == "ground") {
    Body& g = m_.bodies["ground"];
    for (const AstAttr& a : b.attrs)
      diags_.error(a.loc, fmt::format("ground has no setting `{}`", a.key), "ground only declares points: ground { point pivot = [x, y, z] }");
    add_points(g, b, "ground", {});
    return;
  }
  if (auto first = m_.bodies.find(b.name); first != m_.bodies.end()) {
    duplicate("body", b.name, b.loc, first->second.decl->loc);
    return;
  }
  if (auto inst = instances_.find(b.name); inst != instances_.end()) {
    auto& d = diags_.error(b.loc, fmt::format("body `{}` has the name of an instance", b.name),
                           fmt::format("the body's parts (`{}.v`, `{}.m`, ...) would mix with the instance's: rename one of them",
                                       b.name, b.name));
    d.notes.push_back({inst->second, "the instance is declared here"});
  }
  Body body;
  body.decl = &b;
  for (const AstAttr& a : b.attrs)
    if (a.key == beam_setting::flexible.name) {
      add_flexible_body(body, b, a);
      return;
    }
  static const std::vector<std::string> keys = setting_names(body_setting::kAll);
  bool has_mass = false, has_inertia = false, mass_misspelt = false;
  std::map<std::string, const AstAttr*> given;
  for (const AstAttr& a : b.attrs) {
    if (std::find(keys.begin(), keys.end(), a.key) == keys.end()) {
      std::string near = closest_name(a.key, keys);
      diags_.error(a.loc, fmt::format("body `{}` has no setting `{}`", b.name, a.key),
                   near.empty() ? fmt::format("a body takes {}", fmt::join(keys, ", ")) : fmt::format("did you mean `{}`?", near));
      mass_misspelt |= near == body_setting::mass.name;
      continue;
    }
    if (auto [first, fresh] = given.emplace(a.key, &a); !fresh) {
      auto& d = diags_.error(a.loc, fmt::format("`{}` of body `{}` is given twice", a.key, b.name), "keep one of them");
      d.notes.push_back({first->second->loc, "first given here"});
      continue;
    }
    if (a.key == body_setting::shape.name) {
      body.shape = read_shape(b, *a.value);
      continue;
    }
    has_mass |= a.key == body_setting::mass.name;
    has_inertia |= a.key == body_setting::inertia.name;
    check_shape(*a.value, fmt::format("`{}` of body `{}`", a.key, b.name), *find_setting(body_setting::kAll, a.key)->expected);
  }
  if (!has_mass && !mass_misspelt)
    diags_.error(b.loc, fmt::format("body `{}` has no mass", b.name),
                 fmt::format("the mass is the inertance of the body's translational I element: write body {} {{ mass = ...; "
                             "inertia = ... }} (no inertia: a particle)",
                             b.name));
  if (auto m = given.find(body_setting::mass.name); m != given.end())
    if (auto v = constants_.constant_of(*m->second->value); v && !(*v > 0))
      diags_.error(m->second->value->loc, fmt::format("the mass of body `{}` is {}", b.name, *v),
                   "the mass is the inertance of the body's translational I element and must be positive; a massless "
                   "link between bodies is a joint (e.g. distance)");
  if (auto in = given.find(body_setting::inertia.name); in != given.end() && in->second->value->kind == AstExpr::Kind::Call &&
                                       in->second->value->name == "diag")
    for (const auto& x : in->second->value->args)
      if (auto v = constants_.constant_of(*x); v && !(*v > 0))
        diags_.error(x->loc, fmt::format("a principal moment of inertia of body `{}` is {}", b.name, *v),
                     "the inertia tensor is the inertance of the body's rotational I element and must be positive definite");
  if (!has_inertia) body.kind = Particle{};
  if (body.kind.particle())
    for (const AstAttr& a : b.attrs)
      if (find_setting({&body_setting::com, &body_setting::quat0, &body_setting::w0}, a.key))
        diags_.error(a.loc, fmt::format("body `{}` has no inertia, so it is a particle: `{}` means nothing", b.name, a.key),
                     fmt::format("a particle is a translational 1-junction only (mass, position, velocity): it has no "
                                 "orientation, centre-of-mass offset or angular-velocity junction. Give it an inertia "
                                 "(inertia = diag(Jx, Jy, Jz)) to make it a rigid body, or remove `{}`",
                                 a.key));
  add_points(body, b, b.name, BodySym::parts());
  if (body.kind.particle() && !body.points.empty())
    diags_.error(b.points.front().loc, fmt::format("particle `{}` has points", b.name),
                 "a body without inertia is a point mass: it has no orientation, so a point away from it could not "
                 "turn with it. Give it an inertia (inertia = diag(Jx, Jy, Jz)) to have points, or join the particle itself");
  m_.bodies[b.name] = body;
  m_.body_order.push_back(b.name);
}

void Collector::add_points(Body& body, const AstBody& b, const std::string& owner, const std::set<std::string>& reserved) {
  for (const AstPoint& p : b.points) {
    if (auto first = body.points.find(p.name); first != body.points.end()) {
      auto& d = diags_.error(p.loc, fmt::format("point `{}` of `{}` is declared twice", p.name, owner), "give each point its own name");
      d.notes.push_back({point_locs_[BodySym(owner).point(p.name).str()], "first declared here"});
      continue;
    }
    const bool quantity = !body.kind.ground() && BodySym::quantities().count(p.name);
    if (quantity || reserved.count(p.name)) {
      diags_.error(p.loc, fmt::format("a point cannot be named `{}`", p.name),
                   fmt::format("`{}.{}` already means the body's own {}: rename the point, e.g. `{}_point`", owner, p.name,
                               quantity ? "quantity" : "setting or bond-graph element", p.name));
      body.points[p.name] = p.value;  // known, so that joints naming it are not reported again
      continue;
    }
    check_shape(*p.value, fmt::format("point `{}` of `{}`", p.name, owner),
                {{3, 1}, body.kind.ground() ? "a ground point is a world position [x, y, z]"
                                     : "a point is a body-frame position [x, y, z] (the frame of the body's own axes)"});
    body.points[p.name] = p.value;
    point_locs_[BodySym(owner).point(p.name).str()] = p.loc;
  }
}

std::optional<Side> Collector::side(const AstEndpoint& ep) {
  std::string body = ep.path.substr(0, ep.path.find('.'));
  std::string point = body.size() < ep.path.size() ? ep.path.substr(body.size() + 1) : "";
  auto it = m_.bodies.find(body);
  if (it == m_.bodies.end()) {
    std::vector<std::string> names;
    for (const auto& [n, x] : m_.bodies) names.push_back(n);
    std::string near = closest_name(body, names);
    SourceLoc at = ep.loc;
    at.length = static_cast<int>(body.size());
    diags_.error(at, fmt::format("no body named `{}`", body),
                 near.empty() ? fmt::format("declare it: body {} {{ mass = ...; inertia = ... }}, or join one of: {}", body,
                                            fmt::join(names, ", "))
                              : fmt::format("did you mean `{}`?", near));
    return std::nullopt;
  }
  if (!point.empty() && it->second.points_unknown) return Side{body, point};
  if (!point.empty() && !it->second.points.count(point)) {
    std::vector<std::string> names;
    for (const auto& [n, x] : it->second.points) names.push_back(n);
    if (it->second.kind.field() && !it->second.kind.field()->point_file().empty()) {
      diags_.error(ep.loc, fmt::format("modal body `{}` has no point `{}`", body, point),
                   fmt::format("its points are the nodes of {}: {}", it->second.kind.field()->point_file(), fmt::join(names, ", ")));
      return std::nullopt;
    }
    std::string near = closest_name(point, names);
    diags_.error(ep.loc, fmt::format("`{}` has no point `{}`", body, point),
                 near.empty() ? fmt::format("declare it: point {} = [x, y, z] inside {}", point, body == "ground" ? "ground { }" : "the body") 
                              : fmt::format("did you mean `{}`?", near));
    return std::nullopt;
  }
  return Side{body, point};
}

bool Collector::collect_settings(const AstJoint& c, const std::vector<std::string>& keys,
                                std::map<std::string, const AstAttr*>& attrs, const std::string& unknown_hint) {
  bool ok = true;
  for (const AstAttr& at : c.attrs) {
    if (std::find(keys.begin(), keys.end(), at.key) == keys.end()) {
      std::string near = closest_name(at.key, keys);
      diags_.error(at.loc, fmt::format("a {} has no setting `{}`", connector_noun(c.connector), at.key),
                   near.empty() ? unknown_hint : fmt::format("did you mean `{}`?", near));
      ok = false;
      continue;
    }
    if (auto first = attrs.find(at.key); first != attrs.end()) {
      auto& d = diags_.error(at.loc, fmt::format("`{}` of {} `{}` is given twice", at.key, connector_noun(c.connector), c.name),
                             "keep one of them");
      d.notes.push_back({first->second->loc, "first given here"});
      ok = false;
      continue;
    }
    attrs[at.key] = &at;
  }
  return ok;
}

void Collector::add_force(const AstJoint& f) {
  auto a = side(f.a);
  auto b = side(f.b);
  if (!a || !b) return;
  if (a->body == b->body) {
    diags_.error(f.loc, fmt::format("force `{}` acts between `{}` and itself", f.name, a->body),
                 "a force element connects two different bodies (ground for an applied load)");
    return;
  }
  ForceElement fe{&f, *a, *b, {}};
  static const std::vector<std::string> keys = setting_names(force_setting::kAll);
  collect_settings(f, keys, fe.attrs, fmt::format("it takes {}", fmt::join(keys, ", ")));
  const auto* stiffness = given_in(fe.attrs, force_setting::stiffness);
  const auto* length = given_in(fe.attrs, force_setting::length);
  if (stiffness && !length)
    diags_.error(stiffness->loc, fmt::format("the spring of `{}` has no free length", f.name),
                 "add length = L0 (m): the spring pushes the points apart below it and pulls them together above it");
  if (length && !stiffness)
    diags_.error(length->loc, fmt::format("`length` of `{}` needs a stiffness", f.name),
                 "add stiffness = k (N/m), or remove length");
  for (const Side* sd : {&fe.a, &fe.b}) {
    const Body& body = m_.bodies.at(sd->body);
    if (const auto* torque = given_in(fe.attrs, force_setting::torque); body.kind.particle() && torque)
      diags_.error(torque->loc, fmt::format("`{}` is a particle: a torque cannot act on it", sd->body),
                   "give the body an inertia, or remove the torque");
    if (!body.kind.ground()) m_.loads[sd->body].push_back(ForceSym(f.name));
  }
  if (!diags_.has_errors()) m_.forces.push_back(fe);
}

/// Settings whose constant value would make the joint degenerate.
void Collector::check_joint_constant(const JointKind& kind, const AstJoint& j, const AstAttr& at) {
  if (at.key == joint_setting::axis.name || at.key == joint_setting::axis_a.name || at.key == joint_setting::axis_b.name) {
    if (at.value->kind != AstExpr::Kind::List || at.value->args.size() != 3) return;
    for (const auto& x : at.value->args) {
      auto v = constants_.constant_of(*x);
      if (!v || *v != 0) return;
    }
    diags_.error(at.value->loc, fmt::format("`{}` of joint `{}` is the zero vector", at.key, j.name),
                 "an axis is a direction (it is normalised): give a nonzero vector, e.g. axis = [0, 0, 1]");
    return;
  }
  if (auto v = constants_.constant_of(*at.value)) kind.check_constant(j, at, *v, diags_);
  const std::vector<int> fixed = kind.fixed_components(at.key);
  if (fixed.empty() || at.value->kind != AstExpr::Kind::List || at.value->args.size() != 3) return;
  for (int c : fixed) {
    auto v = constants_.constant_of(*at.value->args[static_cast<std::size_t>(c - 1)]);
    if (v && *v == 0) continue;
    diags_.error(at.value->args[static_cast<std::size_t>(c - 1)]->loc,
                 fmt::format("component {} of `{}` of {} joint `{}` must be 0", c, at.key, kind.name(), j.name),
                 fmt::format("the joint does not move that way; its initial rates: {}", kind.initial_settings()));
  }
}

void Collector::add_joint(const AstJoint& j) {
  const JointKind* kind = find_joint_kind(j.type);
  if (!kind) {
    std::vector<std::string> names = joint_kind_names();
    std::string near = closest_name(j.type, names);
    diags_.error(j.type_loc, fmt::format("unknown joint type `{}`", j.type),
                 near.empty() ? fmt::format("joint types: {}", fmt::join(names, ", ")) : fmt::format("did you mean `{}`?", near));
    return;
  }
  auto a = side(j.a);
  auto b = side(j.b);
  if (!a || !b) return;
  if (a->body == b->body) {
    diags_.error(j.loc, fmt::format("joint `{}` connects `{}` to itself", j.name, a->body),
                 a->body == "ground"
                     ? "ground points never move, so a joint between two of them constrains nothing: join a body to ground"
                     : "both ends would move with the same rigid body, so the joint's constraint rows could never change "
                       "and its constraintor CN would act on nothing: connect two different bodies (or a body and ground)");
    return;
  }
  Joint joint;
  joint.decl = &j;
  joint.kind = kind;
  joint.a = *a;
  joint.b = *b;
  joint.strategy = strategy_;
  std::vector<const Setting*> settings = joint_setting::kCommon;
  for (const Setting* s : kind->settings()) settings.push_back(s);
  const std::vector<std::string> keys = setting_names(settings);
  std::set<std::string> meant;  // settings a misspelt one was taken for: not reported missing too
  for (const AstAttr& at : j.attrs) {
    auto found = std::find_if(settings.begin(), settings.end(), [&](const Setting* s) { return at.key == s->name; });
    if (found == settings.end()) {
      std::string near = closest_name(at.key, keys);
      diags_.error(at.loc, fmt::format("a {} joint has no setting `{}`", j.type, at.key),
                   near.empty() ? fmt::format("it takes {}", fmt::join(keys, ", ")) : fmt::format("did you mean `{}`?", near));
      meant.insert(near);
      continue;
    }
    if (auto first = joint.attrs.find(at.key); first != joint.attrs.end()) {
      auto& d = diags_.error(at.loc, fmt::format("`{}` of joint `{}` is given twice", at.key, j.name), "keep one of them");
      d.notes.push_back({first->second->loc, "first given here"});
      continue;
    }
    const Setting& setting = **found;
    if (setting.expected)
      check_shape(*at.value, fmt::format("`{}` of joint `{}`", at.key, j.name), *setting.expected, setting.constant);
    check_joint_constant(*kind, j, at);
    joint.attrs[at.key] = &at;
    if (&setting == &joint_setting::constraint) {
      if (auto s = strategy_of(*at.value, setting.name)) joint.strategy = *s;
    }
  }
  if (given(joint, joint_setting::motion))
    for (const Setting* drive : {&joint_setting::torque, &joint_setting::force})
      if (const AstAttr* load = given_attr(joint, *drive))
        diags_.error(load->loc, fmt::format("joint `{}` has both a prescribed motion and a {}", j.name, drive->name),
                     fmt::format("with motion = f(t) a constraint row fixes the joint coordinate, so the {} only "
                                 "changes that row's multiplier and never the motion: remove it, or remove "
                                 "motion to let the {} drive the joint",
                                 drive->name, drive->name));
  for (const Setting* required : kind->required())
    if (!given(joint, *required) && !meant.count(required->name))
      diags_.error(j.loc, fmt::format("{} joint `{}` needs `{}`", j.type, j.name, required->name),
                   fmt::format("write joint {} {}(...) {{ {} = ... }}", j.name, j.type, required->name));
  for (const Side* s : {&joint.a, &joint.b}) {
    const Body& body = m_.bodies.at(s->body);
    if (body.kind.particle() && kind->needs_orientation())
      diags_.error(j.loc, fmt::format("a {} joint needs the orientation of `{}`, which is a particle", j.type, s->body),
                   fmt::format("a particle (a body without inertia) has a translational 1-junction only, no "
                               "angular-velocity junction for the joint's rotational rows to act on: give `{}` an "
                               "inertia (inertia = diag(Jx, Jy, Jz)), or use a spherical or distance joint",
                               s->body));
  }
  m_.joints.push_back(std::move(joint));
}

}  // namespace mbgc::multibody::detail
