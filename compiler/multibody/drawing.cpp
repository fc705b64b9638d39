// multibody/drawing.cpp — how bodies are drawn (--animate): the `shape`
// setting, the default shape of a body without one, and the pose each
// drawing follows, written as an ExpandedOutput with its Drawing (ir/drawing.hpp);
// and the surfaces bodies touch (contacts' surfaces, tyres' roads), drawn
// after the bodies the same way.
#include "multibody/drawing.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>

#include <fmt/format.h>

#include "multibody/collect.hpp"
#include "multibody/expander.hpp"
#include "multibody/mesh_file.hpp"

namespace mbgc::multibody::detail {

void add_tube(ir::Drawing& d, const std::vector<double>& x, double hy, double hz) {
  const auto base = static_cast<unsigned>(d.vertices.size() / 3);
  static constexpr double kCorner[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (double xk : x)
    for (const auto& c : kCorner) d.vertices.insert(d.vertices.end(), {xk, c[0] * hy, c[1] * hz});
  auto v = [&](std::size_t k, unsigned c) { return base + static_cast<unsigned>(4 * k) + c % 4; };
  for (std::size_t k = 0; k + 1 < x.size(); ++k)
    for (unsigned c = 0; c < 4; ++c)
      d.triangles.insert(d.triangles.end(), {v(k, c), v(k + 1, c), v(k + 1, c + 1), v(k, c), v(k + 1, c + 1), v(k, c + 1)});
  const std::size_t last = x.size() - 1;
  d.triangles.insert(d.triangles.end(), {v(0, 0), v(0, 2), v(0, 1), v(0, 0), v(0, 3), v(0, 2)});
  d.triangles.insert(d.triangles.end(), {v(last, 0), v(last, 1), v(last, 2), v(last, 0), v(last, 2), v(last, 3)});
}

void add_bar(ir::Drawing& d, const std::array<double, 3>& a, const std::array<double, 3>& b, double h) {
  // two unit vectors across the bar: u from the axis and the world axis least along it, w = axis x u
  std::array<double, 3> axis{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  if (!(length > 0)) return;
  for (double& c : axis) c /= length;
  std::size_t least = 0;
  for (std::size_t k = 1; k < 3; ++k)
    if (std::abs(axis[k]) < std::abs(axis[least])) least = k;
  std::array<double, 3> e{};
  e[least] = 1;
  auto cross = [](const std::array<double, 3>& p, const std::array<double, 3>& q) {
    return std::array<double, 3>{p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
  };
  std::array<double, 3> u = cross(axis, e);
  const double nu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (double& c : u) c /= nu;
  const std::array<double, 3> w = cross(axis, u);
  const auto base = static_cast<unsigned>(d.vertices.size() / 3);
  static constexpr double kCorner[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (const auto* end : {&a, &b})
    for (const auto& c : kCorner)
      for (std::size_t k = 0; k < 3; ++k) d.vertices.push_back((*end)[k] + h * (c[0] * u[k] + c[1] * w[k]));
  auto v = [&](unsigned end, unsigned c) { return base + 4 * end + c % 4; };
  for (unsigned c = 0; c < 4; ++c) d.triangles.insert(d.triangles.end(), {v(0, c), v(1, c), v(1, c + 1), v(0, c), v(1, c + 1), v(0, c + 1)});
  d.triangles.insert(d.triangles.end(), {v(0, 0), v(0, 2), v(0, 1), v(0, 0), v(0, 3), v(0, 2)});
  d.triangles.insert(d.triangles.end(), {v(1, 0), v(1, 1), v(1, 2), v(1, 0), v(1, 2), v(1, 3)});
}

void add_octahedron(ir::Drawing& d, const std::array<double, 3>& c, double r) {
  const auto base = static_cast<unsigned>(d.vertices.size() / 3);
  for (int axis = 0; axis < 3; ++axis)
    for (double s : {1.0, -1.0}) {
      std::array<double, 3> p = c;
      p[static_cast<std::size_t>(axis)] += s * r;
      d.vertices.insert(d.vertices.end(), p.begin(), p.end());
    }
  // faces: one per octant, (x, y, z) vertices counter-clockwise seen from outside
  for (unsigned xs : {0u, 1u})
    for (unsigned ys : {2u, 3u})
      for (unsigned zs : {4u, 5u}) {
        const bool flip = (xs + ys + zs) % 2 == 0;  // an even number of negative axes keeps the order
        if (flip) d.triangles.insert(d.triangles.end(), {base + xs, base + ys, base + zs});
        else d.triangles.insert(d.triangles.end(), {base + xs, base + zs, base + ys});
      }
}

namespace {

/// Distinct colours for bodies in declaration order (linear RGB).
std::array<double, 3> palette(std::size_t i) {
  static constexpr std::array<std::array<double, 3>, 8> kColours = {{{0.80, 0.25, 0.15},
                                                                     {0.15, 0.40, 0.80},
                                                                     {0.20, 0.65, 0.25},
                                                                     {0.85, 0.60, 0.10},
                                                                     {0.55, 0.25, 0.70},
                                                                     {0.10, 0.65, 0.65},
                                                                     {0.75, 0.35, 0.55},
                                                                     {0.45, 0.45, 0.45}}};
  return kColours[i % kColours.size()];
}

const std::vector<std::string> kShapeKinds = {"box", "cylinder", "sphere", "mesh"};

/// Colours of drawn contact surfaces (linear RGB): muted tints, each unlike
/// the bodies' palette and the others; a road is dark grey.
std::array<double, 3> surface_colour(std::size_t i) {
  static constexpr std::array<std::array<double, 3>, 4> kColours = {{{0.50, 0.47, 0.40},
                                                                     {0.38, 0.45, 0.52},
                                                                     {0.44, 0.52, 0.38},
                                                                     {0.52, 0.40, 0.46}}};
  return kColours[i % kColours.size()];
}
constexpr std::array<double, 3> kRoadColour = {0.10, 0.10, 0.11};

/// A rotation (rows) whose third column is the unit vector n: the frame of a
/// plane with normal n (its x-y plane) or of a cylinder along n. Its x axis
/// is the world's (the body's) x projected onto the plane, or y where n is
/// along x: n = z gives the identity.
std::array<std::array<double, 3>, 3> frame_along(const std::array<double, 3>& n) {
  std::array<double, 3> x = std::abs(n[0]) < 0.9 ? std::array<double, 3>{1, 0, 0} : std::array<double, 3>{0, 1, 0};
  const double along = x[0] * n[0] + x[1] * n[1] + x[2] * n[2];
  for (std::size_t k = 0; k < 3; ++k) x[k] -= along * n[k];
  const double length = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  for (double& c : x) c /= length;
  const std::array<double, 3> y = {n[1] * x[2] - n[2] * x[1], n[2] * x[0] - n[0] * x[2], n[0] * x[1] - n[1] * x[0]};
  return {{{x[0], y[0], n[0]}, {x[1], y[1], n[1]}, {x[2], y[2], n[2]}}};
}

}  // namespace

/// `shape = box(a, b, c) | cylinder(radius, length) | sphere(radius) |
/// mesh("file.obj")`, centred on the centre of mass (a mesh: its own
/// coordinates, body axes from the centre of mass). Errors go to diags_.
std::shared_ptr<Drawing> Collector::read_shape(const AstBody& b, const AstExpr& v) {
  const std::string how = "write shape = box(a, b, c), cylinder(radius, length), sphere(radius) or mesh(\"file.obj\")";
  if (v.kind != AstExpr::Kind::Call) {
    diags_.error(v.loc, fmt::format("the shape of body `{}` is not one of the shapes", b.name), how);
    return nullptr;
  }
  if (std::find(kShapeKinds.begin(), kShapeKinds.end(), v.name) == kShapeKinds.end()) {
    const std::string near = closest_name(v.name, kShapeKinds);
    diags_.error(v.loc, fmt::format("body `{}` has no shape `{}`", b.name, v.name),
                 near.empty() ? how : fmt::format("did you mean `{}`?", near));
    return nullptr;
  }
  auto d = std::make_shared<Drawing>();
  if (v.name == "mesh") {
    if (v.args.size() != 1 || v.args[0]->kind != AstExpr::Kind::String) {
      diags_.error(v.loc, "mesh(...) takes the name of a Wavefront OBJ file", "write shape = mesh(\"wheel.obj\")");
      return nullptr;
    }
    d->shape = Drawing::Shape::Mesh;
    if (!read_mesh_file(v.args[0]->name, v.args[0]->loc, search_dirs_, sources_, diags_, *d)) return nullptr;
    return d;
  }
  const std::size_t want = v.name == "box" ? 3 : v.name == "cylinder" ? 2 : 1;
  const char* what = v.name == "box" ? "three edge lengths (m)" : v.name == "cylinder" ? "a radius and a length (m)" : "a radius (m)";
  if (v.args.size() != want) {
    diags_.error(v.loc, fmt::format("{}(...) takes {}, not {} argument{}", v.name, what, v.args.size(), v.args.size() == 1 ? "" : "s"),
                 how);
    return nullptr;
  }
  d->shape = v.name == "box" ? Drawing::Shape::Box : v.name == "cylinder" ? Drawing::Shape::Cylinder : Drawing::Shape::Sphere;
  for (std::size_t k = 0; k < want; ++k) {
    auto x = constants_.constant_of(*v.args[k]);
    if (!x || !std::isfinite(*x) || !(*x > 0)) {
      diags_.error(v.args[k]->loc,
                   x ? fmt::format("a dimension of body `{}`'s {} is {}", b.name, v.name, *x)
                     : fmt::format("a dimension of body `{}`'s {} is not a number known when compiling", b.name, v.name),
                   "a shape's dimensions are positive lengths in metres, numbers or parameters with a literal value");
      return nullptr;
    }
    d->size[k] = *x;
  }
  return d;
}

/// A rigid body without a shape: a box around its points and its centre of
/// mass (at least 5 % of the largest edge thick), or with no points the box
/// of the same inertia, a_i = sqrt(6 (tr J - 2 J_ii) / m). A particle: a ball.
Drawing Expander::default_drawing(const Body& body, double scale) const {
  Drawing d;
  if (body.kind.particle()) {
    d.shape = Drawing::Shape::Sphere;
    d.size = {0.03 * scale, 0, 0};
    return d;
  }
  const std::array<double, 3> com = [&] {
    const ir::AstExprPtr c = attr(*body.decl, body_setting::com);
    const std::vector<double> fallback = body_setting::com.by_default.numbers();
    auto p = c ? constants_.constant_point(*c)
               : std::optional<std::array<double, 3>>(std::array<double, 3>{fallback.at(0), fallback.at(1), fallback.at(2)});
    return p.value_or(std::array<double, 3>{});
  }();
  std::array<double, 3> lo{}, hi{};  // around the centre of mass
  bool any = false;
  for (const auto& [name, x] : body.points)
    if (auto p = constants_.constant_point(*x)) {
      any = true;
      for (std::size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], (*p)[k] - com[k]), hi[k] = std::max(hi[k], (*p)[k] - com[k]);
    }
  std::array<double, 3> edge{};
  for (std::size_t k = 0; k < 3; ++k) edge[k] = hi[k] - lo[k], d.centre[k] = 0.5 * (hi[k] + lo[k]);
  if (!any) {  // the box of the same inertia
    const ir::AstExprPtr in = attr(*body.decl, body_setting::inertia), m = attr(*body.decl, body_setting::mass);
    auto mass = m ? constants_.constant_of(*m) : std::nullopt;
    if (in && mass && *mass > 0 && in->kind == AstExpr::Kind::Call && in->name == "diag" && in->args.size() == 3) {
      std::array<double, 3> J{};
      bool ok = true;
      for (std::size_t k = 0; k < 3; ++k) {
        auto v = constants_.constant_of(*in->args[k]);
        ok = ok && v.has_value();
        J[k] = v.value_or(0);
      }
      const double trace = J[0] + J[1] + J[2];
      for (std::size_t k = 0; ok && k < 3; ++k) edge[k] = std::sqrt(std::max(0.0, 6 * (trace - 2 * J[k]) / *mass));
    }
  }
  const double largest = std::max({edge[0], edge[1], edge[2], 0.05 * scale});
  for (std::size_t k = 0; k < 3; ++k) d.size[k] = std::max(edge[k], 0.05 * largest);
  return d;
}

/// The length the model's geometry spans (its points and initial positions), for default sizes.
double Expander::model_scale() const {
  double scale = 0;
  for (const auto& [n, body] : m_.bodies) {
    if (const ir::AstExprPtr r0 = body.decl ? attr(*body.decl, body_setting::r0) : nullptr)
      if (auto v = constants_.constant_point(*r0)) scale = std::max({scale, std::abs((*v)[0]), std::abs((*v)[1]), std::abs((*v)[2])});
    for (const auto& [p, x] : body.points)
      if (auto v = constants_.constant_point(*x)) scale = std::max({scale, std::abs((*v)[0]), std::abs((*v)[1]), std::abs((*v)[2])});
    if (body.kind.field())
      for (const auto& [p, x] : body.kind.field()->points()) scale = std::max({scale, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
  }
  return scale > 0 ? scale : 1.0;
}

void Expander::draw_bodies() {
  const double scale = model_scale();
  std::size_t index = 0;
  for (const std::string& n : m_.body_order) {
    const Body& body = m_.bodies.at(n);
    if (body.kind.ground() || body.points_unknown) continue;
    Build B(body.decl->loc, symbols_);
    auto d = std::make_shared<Drawing>(body.kind.field() ? body.kind.field()->drawing(scale) : body.shape ? *body.shape : default_drawing(body, scale));
    d->body = n;
    d->colour = palette(index++);
    E R = body.kind.particle() ? B.call("eye", {B.num(3)}) : attitude(B, n);
    // (member by member: GCC 12 at -O3 took the braced form's shared_ptr for uninitialised, -Wmaybe-uninitialized)
    ir::ExpandedOutput out;
    out.name = BodySym(n).drawing().str();
    out.loc = B.loc();
    out.value = B.call("hcat", {R, position(B, n)});
    out.drawing = d;
    if (body.kind.field()) out.modes = B.ref(FlexibleSym(n).eta().displacement());
    generated_.push_back(std::move(out));
  }
  draw_surfaces();
}

/// The surfaces bodies touch, each posed by its surface point and the
/// frame of the body carrying it: a contact's plane (its x-y plane, the
/// normal along z), sphere, cylinder (along z) or polygon (in its x-z
/// plane), and the road of the tyres (world z = h(x); tyres on the same
/// profile share it). A surface whose dimensions are not numbers known when
/// compiling is not drawn (like a body's shape, a drawing is compile-time data).
void Expander::draw_surfaces() {
  std::size_t index = 0;
  // (`drawn`: the name of the output posing it)
  auto add = [&](std::shared_ptr<Drawing> d, const Sym& drawn, const Side& on, const std::array<std::array<double, 3>, 3>* turn,
                 const SourceLoc& loc) {
    Build B(loc, symbols_);
    const Body& body = m_.bodies.at(on.body);
    E R = rotation(B, on.body);
    if (turn) {
      std::vector<E> rows;
      for (const auto& row : *turn) rows.push_back(B.list({B.num(row[0]), B.num(row[1]), B.num(row[2])}));
      R = !body.kind.turns() ? B.list(rows) : B.op('*', R, B.list(rows));
    }
    d->surface = true;
    generated_.push_back(ir::ExpandedOutput{drawn.str(), B.loc(), B.call("hcat", {R, world_point(B, on).first}), std::nullopt, d, nullptr});
  };
  for (const Contact& c : m_.contacts) {
    if (m_.bodies.at(c.b.body).points_unknown) continue;
    auto d = std::make_shared<Drawing>();
    d->body = c.decl->name;
    d->colour = surface_colour(index++);
    if (!m_.bodies.at(c.a.body).kind.ground()) d->covers.push_back(c.a.body);
    auto number = [&](const Setting& s) -> std::optional<double> {
      const AstAttr* given = given_in(c.attrs, s);
      return given ? constants_.drawn_number(*given->value) : std::nullopt;
    };
    auto direction = [&](const Setting& s) -> std::optional<std::array<double, 3>> {
      const AstExpr& v = *given_in(c.attrs, s)->value;
      if (v.kind != AstExpr::Kind::List || v.args.size() != 3) return std::nullopt;
      std::array<double, 3> n{};
      for (std::size_t k = 0; k < 3; ++k) {
        auto x = constants_.drawn_number(*v.args[k]);
        if (!x) return std::nullopt;
        n[k] = *x;
      }
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(length > 0) || !std::isfinite(length)) return std::nullopt;
      for (double& x : n) x /= length;
      return n;
    };
    std::array<std::array<double, 3>, 3> turn{};
    bool turned = false;
    if (c.surface == Surface::Plane) {
      auto n = direction(contact_setting::normal);
      if (!n) continue;
      d->shape = Drawing::Shape::Plane;
      turn = frame_along(*n), turned = true;
    } else if (c.surface == Surface::Polygon) {
      d->shape = Drawing::Shape::Prism;
      const AstExpr& vertices = *given_in(c.attrs, contact_setting::vertices)->value;
      for (const auto& p : vertices.args)
        for (const auto& x : p->args)
          if (auto v = constants_.drawn_number(*x)) d->profile.push_back(*v);
      if (d->profile.size() != 2 * vertices.args.size()) continue;
    } else {
      auto r = number(contact_setting::surface_radius);
      if (!r || !(*r > 0)) continue;
      d->size = {*r, 0, 0};  // a cylinder's length: from the run
      d->shape = c.surface == Surface::Sphere ? Drawing::Shape::Sphere : Drawing::Shape::Cylinder;
      if (c.surface == Surface::Cylinder) {
        auto axis = direction(contact_setting::axis);
        if (!axis) continue;
        turn = frame_along(*axis), turned = true;
      }
    }
    add(d, ContactSym(c.decl->name).drawing(), c.b, turned ? &turn : nullptr, c.decl->loc);
  }
  std::vector<std::vector<double>> roads;  // each distinct profile once ({}: flat)
  std::vector<std::shared_ptr<Drawing>> road_drawings;  // (a road's wheels join its drawing until the end)
  for (const Tyre& t : m_.tyres) {
    std::vector<double> profile;
    if (const AstAttr* given = given_in(t.attrs, tyre_setting::profile)) {
      for (const auto& p : given->value->args)
        for (const auto& x : p->args)
          if (auto v = constants_.drawn_number(*x)) profile.push_back(*v);
      if (profile.size() != 2 * given->value->args.size()) continue;
    }
    if (auto same = std::find(roads.begin(), roads.end(), profile); same != roads.end()) {
      road_drawings[static_cast<std::size_t>(same - roads.begin())]->covers.push_back(t.wheel.body);
      continue;
    }
    roads.push_back(profile);
    auto d = std::make_shared<Drawing>();
    road_drawings.push_back(d);
    d->covers.push_back(t.wheel.body);
    const RoadSym road(roads.size());
    d->body = road.str();
    d->shape = Drawing::Shape::Road;
    d->colour = kRoadColour;
    d->profile = std::move(profile);
    add(d, road.drawing(), Side{"ground", ""}, nullptr, t.decl->loc);
  }
}

}  // namespace mbgc::multibody::detail
