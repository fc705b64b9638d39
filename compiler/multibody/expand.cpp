#include "multibody/expand.hpp"

#include "flex/beam_modes.hpp"
#include "flex/modal_file.hpp"
#include "flex/rod_modes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <fmt/format.h>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <ranges>
#include <set>
#include <tuple>

namespace mbgc::multibody {
namespace {

using namespace mbgc::ir;
using E = AstExprPtr;

// ---- building AST expressions (all carry the location of the declaration) ----------
class Build {
 public:
  explicit Build(SourceLoc loc) : loc_(loc) {}
  E num(double v) const { return make(AstExpr::Kind::Number, [&](AstExpr& e) { e.number = v; }); }
  E name(const std::string& n) const { return make(AstExpr::Kind::Name, [&](AstExpr& e) { e.name = n; }); }
  E op(char o, E a, E b) const {
    return make(AstExpr::Kind::Binary, [&](AstExpr& e) { e.op = o; e.args = {std::move(a), std::move(b)}; });
  }
  E neg(E a) const { return make(AstExpr::Kind::Unary, [&](AstExpr& e) { e.op = '-'; e.args = {std::move(a)}; }); }
  E call(const std::string& fn, std::vector<E> args) const {
    return make(AstExpr::Kind::Call, [&](AstExpr& e) { e.name = fn; e.args = std::move(args); });
  }
  E list(std::vector<E> items) const { return make(AstExpr::Kind::List, [&](AstExpr& e) { e.args = std::move(items); }); }
  E vec(double x, double y, double z) const { return list({num(x), num(y), num(z)}); }
  E at(E a, int i) const { return make(AstExpr::Kind::Index, [&](AstExpr& e) { e.args = {std::move(a), num(i)}; }); }
  E dot(E a, E b) const { return call("dot", {std::move(a), std::move(b)}); }
  const SourceLoc& loc() const { return loc_; }

 private:
  template <class F>
  E make(AstExpr::Kind k, F fill) const {
    auto e = std::make_shared<AstExpr>();
    e->kind = k;
    e->loc = loc_;
    fill(*e);
    return e;
  }
  SourceLoc loc_;
};

/// A flexible beam (`flexible = beam`): a floating frame at the beam's start
/// (x = 0, the body frame origin; x along the beam) and assumed modes of
/// bending with deflections along the body's y (the x-y plane) and z (the
/// x-z plane). Lengths and point positions are compile-time numbers (the
/// compiler integrates the modes); material and section may be parameters.
struct Beam {
  double length_m = 0;
  std::optional<flex::BeamModes> y, z;   // mode sets per bending plane
  std::optional<flex::RodModes> axial;   // stretch along x (modes_axial)
  std::optional<flex::RodModes> torsion; // twist about x (modes_torsion)
  bool geometric_stiffness = true;
  double slope_limit_rad = 0.3;          // the run stops where one mode alone tilts the beam further
  bool mean_axes = false;                // frame = buckens or tisserand: the couplings int phi dm, int x phi dm are left out
  bool tisserand = false;                // frame = tisserand: origin at the mass centre, the foreshortening moves no mass
  double origin_m = 0;                   // where along the beam the frame's origin is (frame = centre: L / 2)
  int count() const { return modal ? modal->count : offset_torsion() + (torsion ? torsion->count() : 0); }
  int offset_z() const { return y ? y->count() : 0; }  // eta = [eta_y; eta_z; eta_axial; eta_torsion]
  int offset_axial() const { return offset_z() + (z ? z->count() : 0); }
  int offset_torsion() const { return offset_axial() + (axial ? axial->count() : 0); }
  std::map<std::string, double> point_x;               // point name -> x along the beam
  /// `flexible = modal("file")`: a reduced body from a modal-data file
  /// instead of a built-in beam (then y, z are empty, and its coordinates
  /// travel in Eta::y). Its points are the file's nodes.
  std::shared_ptr<const flex::ModalData> modal;
  /// Undeformed body-frame position of each point.
  std::map<std::string, std::array<double, 3>> points() const {
    std::map<std::string, std::array<double, 3>> out;
    if (modal)
      for (const auto& [name, p] : modal->points) out[name] = p.position;
    for (const auto& [name, x] : point_x) out[name] = {x - origin_m, 0, 0};
    return out;
  }
};

struct Body {
  const AstBody* decl = nullptr;
  std::shared_ptr<Beam> beam;            // flexible beam (null: rigid)
  bool ground = false;
  bool particle = false;                 // no inertia: translation only
  std::map<std::string, E> points;       // name -> body-frame coordinates (ground: inertial)
  bool placed = false;                   // initial pose known (ground, or from a tree joint)
  std::string placed_by;                 // joint that placed it
  bool by_coordinates = false;           // its pose is a function of joint coordinates (no states of its own)
  bool points_unknown = false;           // a modal body whose file could not be read (its error is out already)
};

struct Side {
  std::string body;   // "ground" or a body name
  std::string point;  // may be empty (the frame origin)
};

struct Joint {
  const AstJoint* decl = nullptr;
  Side a, b;
  std::map<std::string, const AstAttr*> attrs;
  Strategy strategy = Strategy::Lagrange;
  bool tree = false;       // places its child (a spanning-tree joint from ground)
  bool a_is_parent = true; // tree joints: which side is the parent
};

/// `force NAME(a.P, b.Q) { force; torque; stiffness; damping; length }`: equal
/// and opposite loads on two body points (a = ground: an applied load).
struct ForceElement {
  const AstJoint* decl = nullptr;  // parsed as a joint of type "force"
  Side a, b;
  std::map<std::string, const AstAttr*> attrs;
};

const std::set<std::string> kJointTypes = {"revolute", "spherical", "cylindrical", "prismatic", "screw",
                                           "planar",   "universal", "fixed",       "distance"};

bool has_rotation_coordinate(const std::string& t) { return t == "revolute" || t == "cylindrical" || t == "screw"; }
bool has_axial_coordinate(const std::string& t) { return t == "prismatic" || t == "cylindrical" || t == "screw"; }

/// Rows and columns of a value, when they can be told from the text alone.
struct Shape {
  int rows = 1, cols = 1;
  bool operator==(const Shape& o) const { return rows == o.rows && cols == o.cols; }
  bool scalar() const { return rows == 1 && cols == 1; }
  std::string text() const {
    if (scalar()) return "a scalar";
    if (cols == 1) return fmt::format("a {}-vector", rows);
    return fmt::format("a {}x{} matrix", rows, cols);
  }
};

/// What a body or joint setting must be, and how to write it.
struct Expected {
  Shape shape;
  const char* how;
};

const std::map<std::string, Expected> kBodySettingShapes = {
    {"mass", {{1, 1}, "the mass is a scalar (kg), e.g. mass = 2"}},
    {"inertia", {{3, 3}, "the inertia tensor about the centre of mass, in body axes, is a 3x3 matrix, e.g. inertia = diag(Jx, Jy, Jz)"}},
    {"com", {{3, 1}, "the centre of mass is a body-frame position [x, y, z]"}},
    {"r0", {{3, 1}, "the initial position of the centre of mass is [x, y, z] (world frame)"}},
    {"v0", {{3, 1}, "the initial velocity of the centre of mass is [vx, vy, vz] (world frame)"}},
    {"w0", {{3, 1}, "the initial angular velocity is [wx, wy, wz] (body frame)"}},
    {"quat0", {{4, 1}, "the initial orientation is a quaternion [w, x, y, z], e.g. quat_axis_angle([0, 0, 1], 0.3)"}},
};
const std::map<std::string, Expected> kJointSettingShapes = {
    {"axis", {{3, 1}, "an axis is a direction [x, y, z] in the frames of both bodies"}},
    {"axis_a", {{3, 1}, "an axis is a direction [x, y, z] in the first body's frame"}},
    {"axis_b", {{3, 1}, "an axis is a direction [x, y, z] in the second body's frame"}},
    {"rot0", {{4, 1}, "the initial relative rotation is a quaternion [w, x, y, z], e.g. quat_axis_angle([0, 0, 1], 0.5)"}},
    {"q0", {{1, 1}, "the initial joint coordinate is a scalar, e.g. q0 = 0.3"}},
    {"rate0", {{1, 1}, "the initial joint rate is a scalar, e.g. rate0 = 0"}},
    {"d0", {{1, 1}, "the initial axial displacement is a scalar, e.g. d0 = 0.1"}},
    {"ddot0", {{1, 1}, "the initial axial rate is a scalar"}},
    {"pitch", {{1, 1}, "the pitch is a scalar (m per rad)"}},
    {"length", {{1, 1}, "the length is a scalar (m)"}},
    {"stiffness", {{1, 1}, "the penalty stiffness is a scalar"}},
    {"damping", {{1, 1}, "the penalty damping is a scalar"}},
    {"torque", {{1, 1}, "the drive torque about the joint axis is a scalar (N m)"}},
    {"force", {{1, 1}, "the drive force along the joint axis is a scalar (N)"}},
    {"motion", {{1, 1}, "a prescribed motion is a scalar function of t, e.g. motion = 0.5 * sin(t)"}},
};

/// Quantities `body.NAME` and `joint.NAME` users may read (defined in define_quantities).
const std::vector<std::string> kBodyQuantities = {"position", "velocity", "momentum", "quaternion", "rotation", "bryant",
                                                  "omega", "omega_world", "angular_momentum", "kinetic_energy",
                                                  "potential_energy"};
/// Names a flexible body's expansion adds (`arm.eta`, `arm.nu`, ...): not free for a modal body's nodes.
const std::set<std::string> kFlexibleInternalNames = {"eta", "nu", "M", "sv", "sw", "se", "etadot", "damp", "modes",
                                                      "J0", "first_moment", "mean", "stiffness", "damping",
                                                      "modal_mass", "J1", "J2", "Hw", "elastic_energy"};
/// Names a body's expansion uses for itself (`bob.mass`, `bob.v`, ...): not free for points.
const std::set<std::string> kBodyInternalNames = {"mass", "inertia", "com", "r0", "v0", "q0", "w0", "v", "m", "r",
                                                  "weight", "w", "J", "ejs", "qrate", "q"};

class Expander {
 public:
  Expander(ir::SourceManager& sources, Diagnostics& diags, const ExpandOptions& options)
      : sources_(sources), diags_(diags), search_dirs_(options.search_dirs), override_(options.constraints),
        strategy_(options.constraints.value_or(Strategy::Lagrange)) {}

  AstProgram run(const AstProgram& in) {
    collect(in);
    if (diags_.has_errors()) return {};
    if (bodies_.size() <= 1 && joints_.empty() && forces_.empty() && !gravity_) return in;  // nothing multibody here
    if (gravity_) param(Build(gravity_loc_), "gravity", gravity_);
    for (const auto& [p, v] : bodies_.at("ground").points) param(Build(v->loc), "ground." + p, v);
    find_tree();
    check_coordinates();
    if (diags_.has_errors()) return {};
    for (const std::string& name : body_order_) emit_body(bodies_.at(name));
    for (Joint& j : joints_) emit_joint(j);
    place_bodies();
    define_quantities();
    for (std::size_t k : applied_) {
      auto& el = std::get<AstElement>(generated_[k]);
      el.value = rewrite_expr(el.value);
    }
    for (const ForceElement& f : forces_) emit_force(f);
    AstProgram out;
    for (const AstStmt& s : in.stmts) {
      if (std::holds_alternative<AstBody>(s) || std::holds_alternative<AstJoint>(s) || std::holds_alternative<AstSetting>(s)) continue;
      out.stmts.push_back(rewrite_user(s));
    }
    for (AstStmt& s : generated_) out.stmts.push_back(std::move(s));
    return out;
  }

 private:
  // ---- 1. collect and check ------------------------------------------------------------
  void collect(const AstProgram& in) {
    Body ground;
    ground.ground = true;
    ground.placed = true;
    bodies_["ground"] = ground;
    for (const AstStmt& s : in.stmts) {
      if (auto* p = std::get_if<AstParam>(&s)) params_[p->name] = p->value;
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
      j->type == "force" ? add_force(*j) : add_joint(*j);
    }
  }

  /// Joints and force elements name the parts they generate (`j1.cn`, `j1.angle`):
  /// their names must differ from each other's and from the bodies'.
  bool connector_name_ok(const AstJoint& j, std::map<std::string, const AstJoint*>& seen) {
    const char* what = j.type == "force" ? "force element" : "joint";
    if (j.name == "ground") {
      diags_.error(j.loc, fmt::format("a {} cannot be named `ground`", what), "`ground` is the fixed frame: choose another name");
      return false;
    }
    if (auto b = bodies_.find(j.name); b != bodies_.end()) {
      auto& d = diags_.error(j.loc, fmt::format("{} `{}` has the name of a body", what, j.name),
                             fmt::format("bodies, joints and force elements share one namespace (`{}.angle`, `{}.position`): "
                                         "rename the {}, e.g. `{}_{}`",
                                         j.name, j.name, what, j.name, j.type == "force" ? "force" : "joint"));
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
      const char* first = it->second->type == "force" ? "force element" : "joint";
      if (std::string(first) != what) {
        auto& d = diags_.error(j.loc, fmt::format("{} `{}` has the name of a {}", what, j.name, first),
                               fmt::format("joints and force elements share one namespace (`{}.force`): rename one of them",
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
  void duplicate(const char* what, const std::string& name, const SourceLoc& at, const SourceLoc& first) {
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

  // ---- shapes and constants known from the text ---------------------------------------
  /// The shape of `e` if it follows from numbers, lists, parameters and the
  /// built-in functions; nullopt when it cannot be told here (checked later).
  std::optional<Shape> shape_of(const AstExpr& e, int depth = 0) const {
    if (depth > 50) return std::nullopt;
    auto sub = [&](std::size_t k) { return k < e.args.size() ? shape_of(*e.args[k], depth + 1) : std::nullopt; };
    switch (e.kind) {
      case AstExpr::Kind::Number: return Shape{};
      case AstExpr::Kind::Name: {
        if (e.name == "t" || e.name == "pi") return Shape{};
        auto p = params_.find(e.name);
        if (p == params_.end() || !p->second) return std::nullopt;
        return shape_of(*p->second, depth + 1);
      }
      case AstExpr::Kind::Unary: return sub(0);
      case AstExpr::Kind::String: return std::nullopt;
      case AstExpr::Kind::Index: return Shape{};
      case AstExpr::Kind::Binary: {
        auto a = sub(0), b = sub(1);
        if (!a || !b) return std::nullopt;
        switch (e.op) {
          case '+':
          case '-':
            if (a->scalar()) return b;
            if (b->scalar() || *a == *b) return a;
            return std::nullopt;
          case '*':
            if (a->scalar()) return b;
            if (b->scalar()) return a;
            if (a->cols == b->rows) return Shape{a->rows, b->cols};
            return std::nullopt;
          case '/': return a;
          case '^': return Shape{};
        }
        return std::nullopt;
      }
      case AstExpr::Kind::List: {
        if (e.args.empty()) return std::nullopt;
        auto first = sub(0);
        if (!first) return std::nullopt;
        for (std::size_t k = 1; k < e.args.size(); ++k)
          if (auto s = sub(k); !s || !(*s == *first)) return std::nullopt;
        if (first->scalar()) return Shape{static_cast<int>(e.args.size()), 1};
        if (first->cols == 1) return Shape{static_cast<int>(e.args.size()), first->rows};
        if (first->rows == 1) return Shape{static_cast<int>(e.args.size()), first->cols};
        return std::nullopt;
      }
      case AstExpr::Kind::Call: {
        static const std::set<std::string> scalar_fns = {
            "sin", "cos",  "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",      "exp", "log",
            "sqrt", "abs", "sign", "min", "max",  "step", "ramp",  "sine", "dot",  "heaviside", "norm"};
        const std::string& f = e.name;
        if (scalar_fns.count(f)) return Shape{};
        auto count = [&](std::size_t k) -> std::optional<int> {
          if (k >= e.args.size() || e.args[k]->kind != AstExpr::Kind::Number) return std::nullopt;
          double n = e.args[k]->number;
          if (n < 1 || n > 1000 || n != static_cast<int>(n)) return std::nullopt;
          return static_cast<int>(n);
        };
        if (f == "diag") return Shape{static_cast<int>(e.args.size()), static_cast<int>(e.args.size())};
        if (f == "eye") {
          if (auto n = count(0)) return Shape{*n, *n};
          return std::nullopt;
        }
        if (f == "zeros") {
          auto r = count(0);
          auto c = e.args.size() > 1 ? count(1) : std::optional<int>(1);
          if (r && c) return Shape{*r, *c};
          return std::nullopt;
        }
        if (f == "transpose") {
          auto a = sub(0);
          if (a) return Shape{a->cols, a->rows};
          return std::nullopt;
        }
        if (f == "cross" || f == "bryant") return Shape{3, 1};
        if (f == "skew" || f == "rotq") return Shape{3, 3};
        if (f == "quat_rate") return Shape{4, 3};
        if (f == "quat_mul" || f == "quat_conj" || f == "quat_axis_angle" || f == "quat_arc") return Shape{4, 1};
        return std::nullopt;
      }
    }
    return std::nullopt;
  }

  /// The value of `e` if it is a constant: numbers, parameters and + - * / ^.
  std::optional<double> constant_of(const AstExpr& e, int depth = 0) const {
    if (depth > 50) return std::nullopt;
    switch (e.kind) {
      case AstExpr::Kind::Number: return e.number;
      case AstExpr::Kind::Name: {
        auto p = params_.find(e.name);
        if (p == params_.end() || !p->second) return std::nullopt;
        return constant_of(*p->second, depth + 1);
      }
      case AstExpr::Kind::Unary: {
        auto a = constant_of(*e.args[0], depth + 1);
        if (a && e.op == '-') return -*a;
        return a;
      }
      case AstExpr::Kind::Binary: {
        auto a = constant_of(*e.args[0], depth + 1), b = constant_of(*e.args[1], depth + 1);
        if (!a || !b) return std::nullopt;
        switch (e.op) {
          case '+': return *a + *b;
          case '-': return *a - *b;
          case '*': return *a * *b;
          case '/': return *b == 0 ? std::nullopt : std::optional<double>(*a / *b);
          case '^': return std::pow(*a, *b);
        }
        return std::nullopt;
      }
      default: return std::nullopt;
    }
  }

  static bool mentions_time(const AstExpr& e) {
    if (e.kind == AstExpr::Kind::Name && e.name == "t") return true;
    for (const E& a : e.args)
      if (a && mentions_time(*a)) return true;
    return false;
  }

  /// Reports a setting whose shape is known and wrong, or that depends on time.
  void check_shape(const AstExpr& value, const std::string& what, const Expected& want, bool constant = true) {
    if (constant && mentions_time(value)) {
      diags_.error(value.loc, fmt::format("{} depends on time", what),
                   "body, joint and gravity settings are constants (parameters of the bond graph's elements); a "
                   "time-varying load is a joint's torque or force, or a force element");
      return;
    }
    auto got = shape_of(value);
    if (!got || *got == want.shape) return;
    diags_.error(value.loc, fmt::format("{} is {}, but it must be {}", what, got->text(), want.shape.text()), want.how);
  }

  void setting(const AstSetting& st) {
    if (st.key == "gravity") {
      if (gravity_) {
        auto& d = diags_.error(st.loc, "gravity is set twice", "keep one `gravity = [gx, gy, gz]`");
        d.notes.push_back({gravity_loc_, "gravity is first set here"});
      }
      check_shape(*st.value, "gravity", {{3, 1}, "gravity is an acceleration in the world frame: gravity = [gx, gy, gz] (m/s^2), e.g. [0, -9.81, 0]"});
      gravity_ = st.value;
      gravity_loc_ = st.loc;
      return;
    }
    if (st.key == "constraints") {
      auto s = strategy_of(*st.value, "constraints");
      if (s && !override_) strategy_ = *s;
      return;
    }
    diags_.error(st.loc, fmt::format("unknown model setting `{}`", st.key), "model settings are `gravity = [...]` and `constraints = lagrange|penalty|coordinates`");
  }

  /// `constraints = ...` (the model's) or `constraint = ...` (a joint's).
  std::optional<Strategy> strategy_of(const AstExpr& v, const char* key) {
    const std::string choices =
        "lagrange (multipliers: a DAE for IDA), penalty (stiff spring-dampers: an ODE) or coordinates (joint "
        "coordinates as states, for trees: an ODE)";
    const std::string how = fmt::format("write {} = {}", key, choices);
    if (v.kind == AstExpr::Kind::Name) {
      if (v.name == "lagrange") return Strategy::Lagrange;
      if (v.name == "penalty") return Strategy::Penalty;
      if (v.name == "coordinates") return Strategy::Coordinates;
      std::string near = closest_name(v.name, {"lagrange", "penalty", "coordinates"});
      diags_.error(v.loc, fmt::format("unknown constraint strategy `{}`", v.name),
                   near.empty() ? how : fmt::format("did you mean `{}`? The strategies are {}", near, choices));
      return std::nullopt;
    }
    diags_.error(v.loc, "a constraint strategy is a name: `lagrange`, `penalty` or `coordinates`", how);
    return std::nullopt;
  }

  void add_body(const AstBody& b) {
    if (b.name == "ground") {
      Body& g = bodies_["ground"];
      for (const AstAttr& a : b.attrs)
        diags_.error(a.loc, fmt::format("ground has no setting `{}`", a.key), "ground only declares points: ground { point pivot = [x, y, z] }");
      add_points(g, b, "ground");
      return;
    }
    if (auto first = bodies_.find(b.name); first != bodies_.end()) {
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
      if (a.key == "flexible") {
        add_flexible_body(body, b, a);
        return;
      }
    static const std::vector<std::string> keys = {"mass", "inertia", "com", "r0", "quat0", "v0", "w0"};
    bool has_mass = false, has_inertia = false, mass_misspelt = false;
    std::map<std::string, const AstAttr*> given;
    for (const AstAttr& a : b.attrs) {
      if (std::find(keys.begin(), keys.end(), a.key) == keys.end()) {
        std::string near = closest_name(a.key, keys);
        diags_.error(a.loc, fmt::format("body `{}` has no setting `{}`", b.name, a.key),
                     near.empty() ? fmt::format("a body takes {}", fmt::join(keys, ", ")) : fmt::format("did you mean `{}`?", near));
        mass_misspelt |= near == "mass";
        continue;
      }
      if (auto [first, fresh] = given.emplace(a.key, &a); !fresh) {
        auto& d = diags_.error(a.loc, fmt::format("`{}` of body `{}` is given twice", a.key, b.name), "keep one of them");
        d.notes.push_back({first->second->loc, "first given here"});
        continue;
      }
      has_mass |= a.key == "mass";
      has_inertia |= a.key == "inertia";
      check_shape(*a.value, fmt::format("`{}` of body `{}`", a.key, b.name), kBodySettingShapes.at(a.key));
    }
    if (!has_mass && !mass_misspelt)
      diags_.error(b.loc, fmt::format("body `{}` has no mass", b.name),
                   fmt::format("the mass is the inertance of the body's translational I element: write body {} {{ mass = ...; "
                               "inertia = ... }} (no inertia: a particle)",
                               b.name));
    if (auto m = given.find("mass"); m != given.end())
      if (auto v = constant_of(*m->second->value); v && !(*v > 0))
        diags_.error(m->second->value->loc, fmt::format("the mass of body `{}` is {}", b.name, *v),
                     "the mass is the inertance of the body's translational I element and must be positive; a massless "
                     "link between bodies is a joint (e.g. distance)");
    if (auto in = given.find("inertia"); in != given.end() && in->second->value->kind == AstExpr::Kind::Call &&
                                         in->second->value->name == "diag")
      for (const E& x : in->second->value->args)
        if (auto v = constant_of(*x); v && !(*v > 0))
          diags_.error(x->loc, fmt::format("a principal moment of inertia of body `{}` is {}", b.name, *v),
                       "the inertia tensor is the inertance of the body's rotational I element and must be positive definite");
    body.particle = !has_inertia;
    if (body.particle)
      for (const AstAttr& a : b.attrs)
        if (a.key == "com" || a.key == "quat0" || a.key == "w0")
          diags_.error(a.loc, fmt::format("body `{}` has no inertia, so it is a particle: `{}` means nothing", b.name, a.key),
                       fmt::format("a particle is a translational 1-junction only (mass, position, velocity): it has no "
                                   "orientation, centre-of-mass offset or angular-velocity junction. Give it an inertia "
                                   "(inertia = diag(Jx, Jy, Jz)) to make it a rigid body, or remove `{}`",
                                   a.key));
    add_points(body, b, b.name);
    if (body.particle && !body.points.empty())
      diags_.error(b.points.front().loc, fmt::format("particle `{}` has points", b.name),
                   "a body without inertia is a point mass: it has no orientation, so a point away from it could not "
                   "turn with it. Give it an inertia (inertia = diag(Jx, Jy, Jz)) to have points, or join the particle itself");
    bodies_[b.name] = body;
    body_order_.push_back(b.name);
  }

  // ---- 1b. flexible bodies -------------------------------------------------------------
  /// Settings of `flexible = beam`; what each one must be.
  static const std::map<std::string, std::string>& beam_settings() {
    static const std::map<std::string, std::string> keys = {
        {"flexible", "beam"},
        {"length", "the beam's length (m), a number or constant parameter"},
        {"density", "the material density (kg/m^3)"},
        {"E", "Young's modulus (Pa)"},
        {"section", "rectangle(width_y, height_z), circle(diameter) or tube(outer, inner) (m)"},
        {"area", "the section area (m^2), with Iy and Iz instead of `section`"},
        {"Iy", "the second moment of area about the body y axis (m^4): bending in the x-z plane"},
        {"Iz", "the second moment of area about the body z axis (m^4): bending in the x-y plane"},
        {"modes_xy", "the mode set of bending in the x-y plane, e.g. clamped_free(3)"},
        {"modes_xz", "the mode set of bending in the x-z plane, e.g. pinned_pinned(2)"},
        {"modes_axial", "the mode set of stretch along x, e.g. fixed_free(2)"},
        {"modes_torsion", "the mode set of twist about x, e.g. fixed_free(1)"},
        {"G", "the shear modulus (Pa), for torsion"},
        {"torsion_constant", "the section's torsion constant (m^4); circle and tube: the polar moment, rectangle: Roark's formula"},
        {"damping", "the modal damping ratio (0.01 = 1 % of critical in every mode)"},
        {"geometric_stiffness", "on or off"},
        {"slope_limit", "the largest slope (rad) one mode may give the beam before the run stops; default 0.3"},
        {"frame", "joint (fixed to the beam at x = 0), centre (to its centre section), buckens or tisserand (mean axes of free-free modes)"},
        {"r0", "the initial position of the frame origin (world)"},
        {"quat0", "the initial orientation"},
        {"v0", "the initial velocity of the frame origin (world)"},
        {"w0", "the initial angular velocity (body frame)"}};
    return keys;
  }

  /// The floating frame (thesis Ch. 5). `joint`: attached to the beam at
  /// x = 0, which the mode set must leave in place (every set but free_free).
  /// `buckens`: the mean axes, whose conditions int u dm = 0 and
  /// int r0 x u dm = 0 free-free modes satisfy (they are orthogonal to the
  /// rigid motions); those two couplings then drop out of M(eta), and the
  /// compiler says so. The default is the one the mode sets allow.
  void check_frame(Beam& beam, const AstBody& b, const AstAttr* given) {
    bool any_free = false, all_free = true;
    auto count_set = [&](bool free) {
      any_free = any_free || free;
      all_free = all_free && free;
    };
    for (const auto* modes : {&beam.y, &beam.z})
      if (*modes) count_set((*modes)->supports() == flex::Supports::FreeFree);
    for (const auto* modes : {&beam.axial, &beam.torsion})
      if (*modes) count_set((*modes)->ends() == flex::RodEnds::FreeFree);
    std::string frame = all_free && any_free ? "buckens" : "joint";
    SourceLoc loc = b.loc;
    if (given) {
      const AstExpr& v = *given->value;
      loc = v.loc;
      if (v.kind != AstExpr::Kind::Name) {
        diags_.error(v.loc, "a floating frame is a name", "write frame = joint, frame = centre, frame = buckens or frame = tisserand");
        return;
      }
      frame = v.name;
      if (frame == "principal") {
        diags_.error(v.loc, "frame = principal is not implemented",
                     "the principal-axis frame only diagonalises the inertia and makes the modal coordinates "
                     "dependent (thesis §5.2.2); write frame = joint, centre, buckens or tisserand");
        return;
      }
      if (frame != "joint" && frame != "buckens" && frame != "centre" && frame != "tisserand") {
        diags_.error(v.loc, fmt::format("unknown floating frame `{}`", frame),
                     "write frame = joint, frame = centre, frame = buckens or frame = tisserand");
        return;
      }
    }
    if (frame == "joint" && any_free) {
      diags_.error(loc, fmt::format("free-free modes move the end x = 0 of beam `{}`, so its frame cannot be fixed there", b.name),
                   all_free ? "write frame = buckens (the mean axes the free-free modes define) or frame = centre (fixed "
                              "to the section at the mass centre)"
                            : "give every mode set free_free modes with frame = buckens, or none");
      return;
    }
    if (frame == "buckens" && !all_free) {
      diags_.error(loc, fmt::format("the mean axes (frame = buckens) of beam `{}` need modes orthogonal to its rigid motions", b.name),
                   "give every mode set free_free(n) modes, or use frame = joint");
      return;
    }
    if (frame == "centre") {
      if (!all_free || beam.axial || beam.torsion) {
        diags_.error(loc, fmt::format("a frame at the mass centre of beam `{}` needs free-free bending modes", b.name),
                     beam.axial || beam.torsion ? "stretch and twist in a centre frame are not implemented yet: use frame = "
                                                  "buckens with free_free modes, or frame = joint"
                                                : "give every plane free_free(n) modes (the frame then holds the centre "
                                                  "section in place), or use frame = joint");
        return;
      }
      // the frame holds the centre section: each mode is measured from it
      beam.origin_m = beam.length_m / 2;
      for (auto* modes : {&beam.y, &beam.z})
        if (*modes) *modes = (*modes)->anchored_at(beam.origin_m);
    }
    if (frame == "tisserand" && !tisserand_allowed(beam, b, loc)) return;
    beam.mean_axes = frame == "buckens" || frame == "tisserand";
    beam.tisserand = frame == "tisserand";
    if (beam.tisserand) {
      beam.origin_m = beam.length_m / 2;
      for (auto* modes : {&beam.y, &beam.z})
        if (*modes) *modes = (*modes)->in_tisserand_frame();
    }
  }

  /// Tisserand's frame (thesis §5.2.4) asks that the deformation carry no
  /// linear and no angular momentum relative to the frame. With free-free
  /// bending modes in one plane both hold identically (5.30 with the origin
  /// at the mass centre and the foreshortening measured from its mean; 5.34
  /// because int phi_k x phi_l dm = 0 for deflections along one axis).
  /// Any other mode set makes 5.34 the nonholonomic constraint
  /// eta^T G eta' = 0, whose row G^T eta vanishes at the undeformed shape:
  /// a multiplier for it is undefined where every run starts.
  bool tisserand_allowed(const Beam& beam, const AstBody& b, const SourceLoc& loc) {
    const bool free_y = beam.y && beam.y->supports() == flex::Supports::FreeFree;
    const bool free_z = beam.z && beam.z->supports() == flex::Supports::FreeFree;
    if (beam.torsion) {
      diags_.error(loc, fmt::format("twist in Tisserand's frame of beam `{}` is not implemented", b.name),
                   "use frame = buckens (the same mean axes to first order), or leave out modes_torsion");
      return false;
    }
    std::string why;
    if (beam.axial)
      why = "stretch couples with bending in int phi_k x phi_l dm (u along x, w along y: their cross product is not zero)";
    else if (beam.y && beam.z)
      why = "with bending in two planes int phi_y,k x phi_z,l dm is not zero (a whirling beam carries angular momentum "
            "about its axis)";
    if (!why.empty()) {
      diags_.error(loc, fmt::format("Tisserand's frame of beam `{}` would be a nonholonomic constraint", b.name),
                   fmt::format("{}, so the frame's condition eta^T G eta' = 0 (thesis eq. 5.34) constrains the modes, and "
                               "its row G^T eta vanishes at the undeformed shape; use frame = buckens (the same mean "
                               "axes to first order), or free_free bending in one plane only",
                               why));
      return false;
    }
    if (!free_y && !free_z) {
      diags_.error(loc, fmt::format("Tisserand's frame (mean axes) of beam `{}` needs free-free modes", b.name),
                   "its modes must be orthogonal to the rigid motions: give the beam free_free(n) bending modes in "
                   "one plane, or use frame = joint");
      return false;
    }
    return true;
  }

  void add_flexible_body(Body& body, const AstBody& b, const AstAttr& kind) {
    const auto& keys = beam_settings();
    const AstExpr& v = *kind.value;
    if (v.kind == AstExpr::Kind::Call && v.name == "modal") {
      add_modal_body(body, b, v);
      return;
    }
    if (v.kind != AstExpr::Kind::Name || v.name != "beam") {
      diags_.error(v.loc, "unknown kind of flexible body",
                   "write flexible = beam (a uniform Euler-Bernoulli beam along the body's x axis) or flexible = "
                   "modal(\"file.mbm\") (a reduced body from an FE program, docs/modal_format.md)");
      return;
    }
    auto beam = std::make_shared<Beam>();
    std::map<std::string, const AstAttr*> given;
    std::vector<std::string> names;
    for (const auto& [k, what] : keys) names.push_back(k);
    for (const AstAttr& a : b.attrs) {
      if (!keys.count(a.key)) {
        std::string near = closest_name(a.key, names);
        const char* computed = (a.key == "mass" || a.key == "inertia" || a.key == "com")
                                   ? "a beam's mass, inertia and centre of mass follow from its length, density and section; remove it"
                                   : nullptr;
        diags_.error(a.loc, fmt::format("flexible body `{}` has no setting `{}`", b.name, a.key),
                     computed ? std::string(computed)
                     : near.empty() ? fmt::format("a beam takes {}", fmt::join(names, ", "))
                                    : fmt::format("did you mean `{}`?", near));
        continue;
      }
      record_setting(given, a, b);
    }
    auto need = [&](const char* key) -> const AstAttr* {
      auto it = given.find(key);
      if (it != given.end()) return it->second;
      diags_.error(b.loc, fmt::format("flexible body `{}` has no `{}`", b.name, key), fmt::format("give {}", keys.at(key)));
      return nullptr;
    };
    if (const AstAttr* len = need("length")) {
      auto v = constant_of(*len->value);
      if (!v || !(*v > 0))
        diags_.error(len->value->loc, fmt::format("the length of beam `{}` must be a positive constant", b.name),
                     "the compiler integrates the mode shapes over the length: write a number or a constant parameter");
      else beam->length_m = *v;
    }
    need("density");
    need("E");
    if (given.count("section") && (given.count("area") || given.count("Iy") || given.count("Iz")))
      diags_.error(given.at("section")->loc, fmt::format("beam `{}` has both `section` and section properties", b.name),
                   "give either section = rectangle(...)/circle(...)/tube(...) or area, Iy and Iz");
    else if (!given.count("section")) {
      need("area");
      need("Iy");
      need("Iz");
    } else check_section(*given.at("section")->value);
    for (const char* plane : {"modes_xy", "modes_xz"}) {
      auto it = given.find(plane);
      if (it == given.end() || beam->length_m <= 0) continue;
      const AstExpr& v = *it->second->value;
      flex::Supports sup{};
      const int n = mode_count(v);
      if (!n || !flex::supports_from_name(v.name, &sup)) {
        diags_.error(v.loc, fmt::format("`{}` of beam `{}` is not a mode set", plane, b.name),
                     "write supports(number of modes): clamped_free(3), pinned_pinned(2), clamped_pinned(2) or free_free(2); "
                     "1 to 12 modes");
        continue;
      }
      (plane[7] == 'y' ? beam->y : beam->z).emplace(sup, beam->length_m, n);
    }
    for (const char* key : {"modes_axial", "modes_torsion"}) {
      auto it = given.find(key);
      if (it == given.end() || beam->length_m <= 0) continue;
      const AstExpr& v = *it->second->value;
      flex::RodEnds ends{};
      const int n = mode_count(v);
      if (!n || !flex::rod_ends_from_name(v.name, &ends)) {
        diags_.error(v.loc, fmt::format("`{}` of beam `{}` is not a mode set", key, b.name),
                     "write ends(number of modes): fixed_free(2), fixed_fixed(2) or free_free(2); 1 to 12 modes");
        continue;
      }
      (key[6] == 'a' ? beam->axial : beam->torsion).emplace(ends, beam->length_m, n);
    }
    if (given.count("modes_torsion")) {
      need("G");
      if (!given.count("section") && !given.count("torsion_constant"))
        diags_.error(given.at("modes_torsion")->loc, fmt::format("beam `{}` twists but has no torsion constant", b.name),
                     "give torsion_constant (m^4), or a section = rectangle(...)/circle(...)/tube(...) to compute it from");
    } else {
      for (const char* key : {"G", "torsion_constant"})
        if (given.count(key))
          diags_.error(given.at(key)->loc, fmt::format("`{}` of beam `{}` is for torsion, which it has no modes of", key, b.name),
                       "give modes_torsion = fixed_free(1) (or another mode set), or remove it");
    }
    if (!given.count("modes_xy") && !given.count("modes_xz") && !given.count("modes_axial") && !given.count("modes_torsion"))
      diags_.error(b.loc, fmt::format("beam `{}` has no modes", b.name),
                   "give the assumed modes of at least one bending plane, e.g. modes_xy = clamped_free(3), or of "
                   "stretch or twist (modes_axial, modes_torsion)");
    if (auto g = given.find("geometric_stiffness"); g != given.end()) {
      const AstExpr& v = *g->second->value;
      auto flag = constant_of(v);  // 1 or 0: a parameter, so that `mbgc --set` can switch it
      if (v.kind == AstExpr::Kind::Name && (v.name == "on" || v.name == "off")) beam->geometric_stiffness = v.name == "on";
      else if (flag && (*flag == 0 || *flag == 1)) beam->geometric_stiffness = *flag == 1;
      else diags_.error(v.loc, "geometric_stiffness is `on` or `off` (or a constant 1 or 0)",
                        "on: the dynamic geometric stiffness of the axial load (spin stiffening, buckling); off: the linear "
                        "model the thesis compares against");
    }
    check_frame(*beam, b, given.count("frame") ? given.at("frame") : nullptr);
    if (auto s = given.find("slope_limit"); s != given.end()) read_slope_limit(*beam, b, *s->second);
    body.beam = beam;
    add_points(body, b, b.name);
    for (const AstPoint& p : b.points) {
      bool on_axis = false;
      if (p.value->kind == AstExpr::Kind::List && p.value->args.size() == 3) {
        auto x = constant_of(*p.value->args[0]), y = constant_of(*p.value->args[1]), z = constant_of(*p.value->args[2]);
        const double c = beam->origin_m;  // body x is measured from the frame's origin
        if (x && y && z && *y == 0 && *z == 0 && *x >= -c && *x <= beam->length_m - c) {
          on_axis = true;
          beam->point_x[p.name] = *x + c;
        }
      }
      if (!on_axis && beam->length_m > 0)
        diags_.error(p.value->loc, fmt::format("point `{}` is not on the axis of beam `{}`", p.name, b.name),
                     beam->origin_m == 0
                         ? fmt::format("points of a beam are [x, 0, 0] with x a constant from 0 to its length {} m: the "
                                       "joint there sees the beam's deflection and slope at x",
                                       beam->length_m)
                         : fmt::format("points of a beam are [x, 0, 0] with x a constant from {} to {} m (its frame is at "
                                       "the centre): the joint there sees the beam's deflection and slope at x",
                                       -beam->origin_m, beam->length_m - beam->origin_m));
    }
    bodies_[b.name] = body;
    body_order_.push_back(b.name);
  }

  /// The n of a mode set `name(n)` (n a whole constant, 1 to 12); 0 if it is not one.
  int mode_count(const AstExpr& v) const {
    if (v.kind != AstExpr::Kind::Call || v.args.size() != 1) return 0;
    auto n = constant_of(*v.args[0]);
    return n && *n >= 1 && *n <= 12 && *n == std::floor(*n) ? static_cast<int>(*n) : 0;
  }

  /// A flexible body's known setting: reported if given twice, its shape checked.
  void record_setting(std::map<std::string, const AstAttr*>& given, const AstAttr& a, const AstBody& b) {
    if (auto [first, fresh] = given.emplace(a.key, &a); !fresh) {
      auto& d = diags_.error(a.loc, fmt::format("`{}` of body `{}` is given twice", a.key, b.name), "keep one of them");
      d.notes.push_back({first->second->loc, "first given here"});
    }
    if (kBodySettingShapes.count(a.key))
      check_shape(*a.value, fmt::format("`{}` of body `{}`", a.key, b.name), kBodySettingShapes.at(a.key));
  }

  void read_slope_limit(Beam& beam, const AstBody& b, const AstAttr& a) {
    auto v = constant_of(*a.value);
    if (!v || !(*v > 0) || *v > 1.5)
      diags_.error(a.value->loc, fmt::format("the slope limit of flexible body `{}` must be a constant in (0, 1.5] rad", b.name),
                   "the modal model keeps slopes to second order: beyond about 0.3 rad its curvature is off by more "
                   "than 14 %; the default is 0.3");
    else beam.slope_limit_rad = *v;
  }

  /// `flexible = modal("file.mbm")`: a reduced body whose mass, stiffness and
  /// nodes come from a modal-data file (docs/modal_format.md). The model
  /// adds only its damping ratio, slope limit and initial state.
  void add_modal_body(Body& body, const AstBody& b, const AstExpr& v) {
    if (v.args.size() != 1 || v.args[0]->kind != AstExpr::Kind::String) {
      diags_.error(v.loc, "modal(...) takes the name of a modal-data file", "write flexible = modal(\"arm.mbm\")");
      body.points_unknown = true;
      bodies_[b.name] = body;
      body_order_.push_back(b.name);
      return;
    }
    static const std::vector<std::string> keys = {"flexible", "damping", "slope_limit", "r0", "quat0", "v0", "w0"};
    auto beam = std::make_shared<Beam>();
    beam->geometric_stiffness = false;  // a linear displacement field (format version 1)
    std::map<std::string, const AstAttr*> given;
    for (const AstAttr& a : b.attrs) {
      if (std::find(keys.begin(), keys.end(), a.key) == keys.end()) {
        const bool from_file = a.key == "mass" || a.key == "inertia" || a.key == "com" || a.key == "length" ||
                               a.key == "E" || a.key == "density" || a.key.rfind("modes", 0) == 0 || a.key == "section";
        diags_.error(a.loc, fmt::format("flexible body `{}` from a modal-data file has no setting `{}`", b.name, a.key),
                     a.key == "geometric_stiffness"
                         ? std::string("a modal-data body is linear in its modal coordinates (format version 1): no "
                                       "geometric stiffness; use flexible = beam where stress stiffening matters")
                     : a.key == "frame" ? std::string("its frame is the one its file is written in")
                     : from_file ? std::string("its mass, inertia, stiffness and modes come from the file; remove it")
                                 : fmt::format("a modal body takes {}", fmt::join(keys, ", ")));
        continue;
      }
      record_setting(given, a, b);
    }
    for (const AstPoint& p : b.points)
      diags_.error(p.loc, fmt::format("point `{}`: the points of modal body `{}` are the nodes of its file", p.name, b.name),
                   "add the node to the file (records point, shape and slope) and attach joints to it by name");
    if (auto s = given.find("slope_limit"); s != given.end()) read_slope_limit(*beam, b, *s->second);
    const AstExpr& file = *v.args[0];
    auto data = flex::read_modal_file(file.name, file.loc, search_dirs_, sources_, diags_);
    if (!data) {
      body.points_unknown = true;  // registered all the same: joints to it are not reported again
      bodies_[b.name] = body;
      body_order_.push_back(b.name);
      return;
    }
    Build B(file.loc);
    for (const auto& [name, pt] : data->points) {
      if (kBodyInternalNames.count(name) || kFlexibleInternalNames.count(name) ||
          std::find(kBodyQuantities.begin(), kBodyQuantities.end(), name) != kBodyQuantities.end()) {
        diags_.error(file.loc, fmt::format("the modal-data file names a point `{}`, which body `{}` uses for itself", name, b.name),
                     "rename the node in the file");
        continue;
      }
      body.points[name] = B.vec(pt.position[0], pt.position[1], pt.position[2]);
      point_locs_[b.name + "." + name] = file.loc;
    }
    beam->modal = std::make_shared<const flex::ModalData>(std::move(*data));
    body.beam = beam;
    bodies_[b.name] = body;
    body_order_.push_back(b.name);
  }

  void check_section(const AstExpr& v) {
    static const std::map<std::string, std::size_t> arity = {{"rectangle", 2}, {"circle", 1}, {"tube", 2}};
    auto it = v.kind == AstExpr::Kind::Call ? arity.find(v.name) : arity.end();
    if (it == arity.end() || it->second != v.args.size())
      diags_.error(v.loc, "unknown beam section",
                   "write rectangle(width_y, height_z), circle(diameter) or tube(outer_diameter, inner_diameter), in m; "
                   "or give area, Iy and Iz instead of section");
  }

  void add_points(Body& body, const AstBody& b, const std::string& owner) {
    for (const AstPoint& p : b.points) {
      if (auto first = body.points.find(p.name); first != body.points.end()) {
        auto& d = diags_.error(p.loc, fmt::format("point `{}` of `{}` is declared twice", p.name, owner), "give each point its own name");
        d.notes.push_back({point_locs_[owner + "." + p.name], "first declared here"});
        continue;
      }
      if (!body.ground && (kBodyInternalNames.count(p.name) ||
                           std::find(kBodyQuantities.begin(), kBodyQuantities.end(), p.name) != kBodyQuantities.end())) {
        diags_.error(p.loc, fmt::format("a point cannot be named `{}`", p.name),
                     fmt::format("`{}.{}` already means the body's own {}: rename the point, e.g. `{}_point`", owner, p.name,
                                 kBodyInternalNames.count(p.name) ? "setting or bond-graph element" : "quantity", p.name));
        body.points[p.name] = p.value;  // known, so that joints naming it are not reported again
        continue;
      }
      check_shape(*p.value, fmt::format("point `{}` of `{}`", p.name, owner),
                  {{3, 1}, body.ground ? "a ground point is a world position [x, y, z]"
                                       : "a point is a body-frame position [x, y, z] (the frame of the body's own axes)"});
      body.points[p.name] = p.value;
      point_locs_[owner + "." + p.name] = p.loc;
    }
  }

  std::optional<Side> side(const AstEndpoint& ep) {
    std::string body = ep.path.substr(0, ep.path.find('.'));
    std::string point = body.size() < ep.path.size() ? ep.path.substr(body.size() + 1) : "";
    auto it = bodies_.find(body);
    if (it == bodies_.end()) {
      std::vector<std::string> names;
      for (const auto& [n, x] : bodies_) names.push_back(n);
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
      if (it->second.beam && it->second.beam->modal) {
        diags_.error(ep.loc, fmt::format("modal body `{}` has no point `{}`", body, point),
                     fmt::format("its points are the nodes of {}: {}", it->second.beam->modal->path,
                                 fmt::join(std::views::keys(it->second.points), ", ")));
        return std::nullopt;
      }
      std::vector<std::string> names;
      for (const auto& [n, x] : it->second.points) names.push_back(n);
      std::string near = closest_name(point, names);
      diags_.error(ep.loc, fmt::format("`{}` has no point `{}`", body, point),
                   near.empty() ? fmt::format("declare it: point {} = [x, y, z] inside {}", point, body == "ground" ? "ground { }" : "the body") 
                                : fmt::format("did you mean `{}`?", near));
      return std::nullopt;
    }
    return Side{body, point};
  }

  void add_force(const AstJoint& f) {
    auto a = side(f.a);
    auto b = side(f.b);
    if (!a || !b) return;
    if (a->body == b->body) {
      diags_.error(f.loc, fmt::format("force `{}` acts between `{}` and itself", f.name, a->body),
                   "a force element connects two different bodies (ground for an applied load)");
      return;
    }
    ForceElement fe{&f, *a, *b, {}};
    static const std::vector<std::string> keys = {"force", "torque", "stiffness", "damping", "length"};
    for (const AstAttr& at : f.attrs) {
      if (std::find(keys.begin(), keys.end(), at.key) == keys.end()) {
        std::string near = closest_name(at.key, keys);
        diags_.error(at.loc, fmt::format("a force element has no setting `{}`", at.key),
                     near.empty() ? fmt::format("it takes {}", fmt::join(keys, ", ")) : fmt::format("did you mean `{}`?", near));
        continue;
      }
      fe.attrs[at.key] = &at;
    }
    if (fe.attrs.count("stiffness") && !fe.attrs.count("length"))
      diags_.error(fe.attrs.at("stiffness")->loc, fmt::format("the spring of `{}` has no free length", f.name),
                   "add length = L0 (m): the spring pushes the points apart below it and pulls them together above it");
    if (fe.attrs.count("length") && !fe.attrs.count("stiffness"))
      diags_.error(fe.attrs.at("length")->loc, fmt::format("`length` of `{}` needs a stiffness", f.name),
                   "add stiffness = k (N/m), or remove length");
    for (const Side* sd : {&fe.a, &fe.b}) {
      const Body& body = bodies_.at(sd->body);
      if (body.particle && fe.attrs.count("torque"))
        diags_.error(fe.attrs.at("torque")->loc, fmt::format("`{}` is a particle: a torque cannot act on it", sd->body),
                     "give the body an inertia, or remove the torque");
      if (!body.ground) loads_[sd->body].push_back(f.name);
    }
    if (!diags_.has_errors()) forces_.push_back(fe);
  }

  /// Settings whose constant value would make the joint degenerate.
  void check_joint_constant(const AstJoint& j, const AstAttr& at) {
    if (at.key == "axis" || at.key == "axis_a" || at.key == "axis_b") {
      if (at.value->kind != AstExpr::Kind::List || at.value->args.size() != 3) return;
      for (const E& x : at.value->args) {
        auto v = constant_of(*x);
        if (!v || *v != 0) return;
      }
      diags_.error(at.value->loc, fmt::format("`{}` of joint `{}` is the zero vector", at.key, j.name),
                   "an axis is a direction (it is normalised): give a nonzero vector, e.g. axis = [0, 0, 1]");
      return;
    }
    auto v = constant_of(*at.value);
    if (!v) return;
    if (at.key == "length" && !(*v > 0))
      diags_.error(at.value->loc, fmt::format("the length of distance joint `{}` is {}", j.name, *v),
                   "a distance joint keeps two points `length` apart and must be positive; points that coincide are a "
                   "spherical joint: write joint " + j.name + " spherical(...)");
    if (at.key == "pitch" && *v == 0)
      diags_.error(at.value->loc, fmt::format("the pitch of screw joint `{}` is 0", j.name),
                   "a screw advances `pitch` metres per radian; with no advance it is a revolute joint: write joint " +
                       j.name + " revolute(...)");
  }

  void add_joint(const AstJoint& j) {
    if (!kJointTypes.count(j.type)) {
      std::vector<std::string> names(kJointTypes.begin(), kJointTypes.end());
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
    joint.a = *a;
    joint.b = *b;
    joint.strategy = strategy_;
    std::vector<std::string> keys = {"axis", "axis_a", "axis_b", "constraint", "stiffness", "damping"};
    if (has_rotation_coordinate(j.type)) keys.insert(keys.end(), {"q0", "rate0", "torque", "motion"});
    if (j.type == "prismatic") keys.insert(keys.end(), {"q0", "rate0", "force", "motion"});
    if (j.type == "cylindrical") keys.insert(keys.end(), {"d0", "ddot0"});
    if (j.type == "spherical") keys.push_back("rot0");
    if (j.type == "screw") keys.push_back("pitch");
    if (j.type == "distance") keys.push_back("length");
    for (const AstAttr& at : j.attrs) {
      if (std::find(keys.begin(), keys.end(), at.key) == keys.end()) {
        std::string near = closest_name(at.key, keys);
        diags_.error(at.loc, fmt::format("a {} joint has no setting `{}`", j.type, at.key),
                     near.empty() ? fmt::format("it takes {}", fmt::join(keys, ", ")) : fmt::format("did you mean `{}`?", near));
        continue;
      }
      if (auto first = joint.attrs.find(at.key); first != joint.attrs.end()) {
        auto& d = diags_.error(at.loc, fmt::format("`{}` of joint `{}` is given twice", at.key, j.name), "keep one of them");
        d.notes.push_back({first->second->loc, "first given here"});
        continue;
      }
      if (auto want = kJointSettingShapes.find(at.key); want != kJointSettingShapes.end())
        check_shape(*at.value, fmt::format("`{}` of joint `{}`", at.key, j.name), want->second,
                    at.key != "torque" && at.key != "force" && at.key != "motion");
      check_joint_constant(j, at);
      joint.attrs[at.key] = &at;
      if (at.key == "constraint") {
        if (auto s = strategy_of(*at.value, "constraint")) joint.strategy = *s;
      }
    }
    if (joint.attrs.count("motion"))
      for (const char* drive : {"torque", "force"})
        if (auto it = joint.attrs.find(drive); it != joint.attrs.end())
          diags_.error(it->second->loc, fmt::format("joint `{}` has both a prescribed motion and a {}", j.name, drive),
                       fmt::format("with motion = f(t) a constraint row fixes the joint coordinate, so the {} only "
                                   "changes that row's multiplier and never the motion: remove it, or remove "
                                   "motion to let the {} drive the joint",
                                   drive, drive));
    for (const char* required : {"pitch", "length"})
      if (std::find(keys.begin(), keys.end(), required) != keys.end() && !joint.attrs.count(required))
        diags_.error(j.loc, fmt::format("{} joint `{}` needs `{}`", j.type, j.name, required),
                     fmt::format("write joint {} {}(...) {{ {} = ... }}", j.name, j.type, required));
    bool needs_orientation = j.type != "spherical" && j.type != "distance";
    for (const Side* s : {&joint.a, &joint.b}) {
      const Body& body = bodies_.at(s->body);
      if (body.particle && needs_orientation)
        diags_.error(j.loc, fmt::format("a {} joint needs the orientation of `{}`, which is a particle", j.type, s->body),
                     fmt::format("a particle (a body without inertia) has a translational 1-junction only, no "
                                 "angular-velocity junction for the joint's rotational rows to act on: give `{}` an "
                                 "inertia (inertia = diag(Jx, Jy, Jz)), or use a spherical or distance joint",
                                 s->body));
    }
    joints_.push_back(std::move(joint));
  }

  // ---- 2. bodies -------------------------------------------------------------------------
  E attr(const AstBody& b, const std::string& key) const {
    for (const AstAttr& a : b.attrs)
      if (a.key == key) return a.value;
    return nullptr;
  }

  void param(const Build& B, const std::string& name, E value) {
    generated_names_.insert(name);
    generated_.push_back(AstParam{name, B.loc(), std::move(value)});
  }
  void element(const Build& B, const std::string& kind, const std::string& name, E value, std::vector<AstAttr> attrs = {}) {
    generated_names_.insert(name);
    AstElement el;
    el.kind = kind;
    el.kind_loc = B.loc();
    el.name = name;
    el.loc = B.loc();
    el.value = std::move(value);
    el.attrs = std::move(attrs);
    generated_.push_back(std::move(el));
  }
  void junction(const Build& B, char type, const std::string& name, int dim, std::vector<std::string> in, std::vector<std::string> out) {
    generated_names_.insert(name);
    AstJunction j;
    j.type = type;
    j.kind_loc = B.loc();
    j.name = name;
    j.loc = B.loc();
    j.dim = dim;
    j.dim_loc = B.loc();
    for (auto& s : in) j.inputs.push_back({s, B.loc()});
    for (auto& s : out) j.outputs.push_back({s, B.loc()});
    generated_.push_back(std::move(j));
  }
  void bond(const Build& B, const std::string& from, const std::string& to, std::optional<int> dim = std::nullopt) {
    AstBond b;
    b.loc = B.loc();
    b.dim = dim;
    b.dim_loc = B.loc();
    b.from = {from, B.loc()};
    b.to = {to, B.loc()};
    generated_.push_back(std::move(b));
  }
  static AstAttr kv(const std::string& key, E value, const SourceLoc& loc) { return AstAttr{key, loc, std::move(value)}; }

  void emit_body(const Body& body) {
    const AstBody& d = *body.decl;
    const std::string& n = d.name;
    Build B(d.loc);
    if (body.beam) {
      emit_beam(body);
      return;
    }
    param(B, n + ".mass", attr(d, "mass"));
    for (const auto& [p, v] : body.points) param(B, n + "." + p, v);
    // initial pose and velocity (overwritten by place_bodies for joint-placed bodies)
    // applied loads (force elements) push into the body's junctions
    std::vector<std::string> forces_in, torques_in;
    if (gravity_) forces_in.push_back(n + ".weight");
    if (auto it = loads_.find(n); it != loads_.end())
      for (const std::string& f : it->second) {
        forces_in.push_back(f + ".on_" + n + "_f");
        if (!body.particle) torques_in.push_back(f + ".on_" + n + "_t");
      }
    // A body moved by joint coordinates has no states of its own: its inertias
    // take derivative causality and its pose is a function of the coordinates.
    const bool own_states = !body.by_coordinates;
    std::vector<std::string> v_out = {n + ".m"};
    if (own_states) v_out.push_back(n + ".r");
    junction(B, '1', n + ".v", 3, forces_in, v_out);
    std::vector<AstAttr> m_init, J_init;
    if (own_states) m_init.push_back(kv("f0", B.name(n + ".v0"), d.loc)), J_init.push_back(kv("f0", B.name(n + ".w0"), d.loc));
    element(B, "I", n + ".m", B.op('*', B.name(n + ".mass"), B.call("eye", {B.num(3)})), m_init);
    if (own_states) element(B, "C", n + ".r", nullptr, {kv("e", B.vec(0, 0, 0), d.loc), kv("q0", B.name(n + ".r0"), d.loc)});
    if (gravity_) element(B, "Se", n + ".weight", B.op('*', B.name(n + ".mass"), B.name("gravity")));
    if (body.particle) return;
    E com = attr(d, "com");
    param(B, n + ".com", com ? com : B.vec(0, 0, 0));
    param(B, n + ".inertia", attr(d, "inertia"));
    std::vector<std::string> w_out = {n + ".J", n + ".ejs"};
    if (own_states) w_out.push_back(n + ".qrate.p1");
    junction(B, '1', n + ".w", 3, torques_in, w_out);
    element(B, "I", n + ".J", B.name(n + ".inertia"), J_init);
    // Euler junction structure: torque omega x h on the body-frame junction, no power.
    element(B, "R", n + ".ejs", nullptr, {kv("e", B.call("cross", {B.name("f"), B.name(n + ".J.p")}), d.loc)});
    if (!own_states) return;
    element(B, "MTF", n + ".qrate", B.call("quat_rate", {B.name(n + ".q.q")}));
    element(B, "C", n + ".q", nullptr, {kv("e", B.list({B.num(0), B.num(0), B.num(0), B.num(0)}), d.loc), kv("q0", B.name(n + ".q0"), d.loc)});
    bond(B, n + ".qrate.p2", n + ".q", 4);
  }

  // ---- 2b. flexible beams ----------------------------------------------------------------
  // The floating frame formulation of thesis Ch. 4 in Kirchhoff form: one
  // 1-junction `n.nu` carries nu = [V; omega; eta'] (V: velocity of the frame
  // origin in body axes), an I field holds p = M(eta) nu, and R `n.ejs`
  // supplies the velocity terms of the body-frame equations
  //   P' + w x P = F,   H' + w x H + V x P = T,   p_eta' - dT/deta = Q.
  // The kinetic energy T = 1/2 nu^T M(eta) nu is that of the deflected beam
  // with the foreshortening of bending, u_x = x - 1/2 eta^T a(x) eta, kept
  // to the order that gives linear equations in eta: this is what produces
  // the dynamic geometric stiffness (thesis eqs. 3.30, 4.97) of spin, axial
  // acceleration, gravity and, through the joints' points, end loads, as
  // terms of one energy, so the model conserves it. Selector MTFs hand V (as
  // R V, world), omega and eta' to the 1-junctions `n.v`, `n.w`, `n.etadot`
  // that position, orientation, elasticity and joints attach to, as on a
  // rigid body.

  /// eta_k of beam n as an AST expression (1-based component of the modal C's state).
  static E eta_of(const Build& B, const std::string& n, int k) { return B.at(B.name(n + ".eta.q"), k + 1); }

  /// sum_ij P[i][j] x_i y_j for a parameter matrix P (1-based indexing).
  static E quadratic(const Build& B, const std::string& P, const std::vector<E>& x, const std::vector<E>& y) {
    E sum = nullptr;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t j = 0; j < y.size(); ++j) {
        E term = B.op('*', B.op('*', idx2(B, B.name(P), static_cast<int>(i) + 1, static_cast<int>(j) + 1), x[i]), y[j]);
        sum = sum ? B.op('+', sum, term) : term;
      }
    return sum ? sum : B.num(0);
  }
  /// (P x)_i, or (P^T x)_i, for a parameter matrix P.
  static E row_dot(const Build& B, const std::string& P, int i, const std::vector<E>& x, bool transposed = false) {
    E sum = nullptr;
    for (std::size_t j = 0; j < x.size(); ++j) {
      int r = transposed ? static_cast<int>(j) + 1 : i + 1, c = transposed ? i + 1 : static_cast<int>(j) + 1;
      E term = B.op('*', idx2(B, B.name(P), r, c), x[j]);
      sum = sum ? B.op('+', sum, term) : term;
    }
    return sum ? sum : B.num(0);
  }
  static E sum_of(const Build& B, const std::vector<E>& terms) {
    E sum = nullptr;
    for (const E& t : terms)
      if (t) sum = sum ? B.op('+', sum, t) : t;
    return sum ? sum : B.num(0);
  }
  static E matrix_param(const Build& B, const flex::Matrix& m) {
    std::vector<E> rows_;
    for (const auto& r : m) {
      std::vector<E> row;
      for (double x : r) row.push_back(B.num(x));
      rows_.push_back(B.list(row));
    }
    return B.list(rows_);
  }
  static E vector_param(const Build& B, const std::vector<double>& v) {
    std::vector<E> items;
    for (double x : v) items.push_back(B.num(x));
    return B.list(items);
  }

  /// The modal coordinates of each plane, as expressions (given an accessor).
  struct Eta { std::vector<E> y, z, axial, torsion; };
  Eta split_eta(const Beam& beam, const std::function<E(int)>& eta) const {
    Eta out;
    if (beam.modal) {  // no planes: every coordinate in y
      for (int i = 0; i < beam.count(); ++i) out.y.push_back(eta(i));
      return out;
    }
    for (int i = 0; i < (beam.y ? beam.y->count() : 0); ++i) out.y.push_back(eta(i));
    for (int i = 0; i < (beam.z ? beam.z->count() : 0); ++i) out.z.push_back(eta(beam.offset_z() + i));
    for (int i = 0; i < (beam.axial ? beam.axial->count() : 0); ++i) out.axial.push_back(eta(beam.offset_axial() + i));
    for (int i = 0; i < (beam.torsion ? beam.torsion->count() : 0); ++i) out.torsion.push_back(eta(beam.offset_torsion() + i));
    return out;
  }
  /// sum_k P[k] x_k for a parameter vector P (0 for no x).
  static E vec_dot(const Build& B, const std::string& P, const std::vector<E>& x) {
    std::vector<E> terms;
    for (std::size_t k = 0; k < x.size(); ++k) terms.push_back(B.op('*', B.at(B.name(P), static_cast<int>(k) + 1), x[k]));
    return sum_of(B, terms);
  }

  /// s(eta) = int u dm: the first moment about the frame origin, body axes.
  E first_moment(const Build& B, const std::string& n, const Beam& beam, const Eta& eta) const {
    if (beam.modal) return modal_first_moment(B, n, eta.y);
    E sx = B.op('*', B.name(n + ".mass"), B.op('/', B.name(n + ".length"), B.num(2)));
    if (beam.origin_m != 0) sx = B.op('*', B.name(n + ".mass"), B.op('-', B.op('/', B.name(n + ".length"), B.num(2)), B.num(beam.origin_m)));
    if (beam.tisserand) sx = B.num(0);  // the origin is the mass centre
    if (beam.geometric_stiffness && !beam.tisserand) {  // Tisserand: the foreshortening moves no mass
      E shortening = B.op('+', quadratic(B, n + ".y.load", eta.y, eta.y), quadratic(B, n + ".z.load", eta.z, eta.z));
      sx = B.op('-', sx, B.op('*', B.num(0.5), shortening));
    }
    if (!eta.axial.empty() && !beam.mean_axes) sx = B.op('+', sx, vec_dot(B, n + ".a.mean", eta.axial));
    std::vector<E> sy, sz;  // int phi dm eta: zero in mean axes
    for (std::size_t i = 0; i < eta.y.size() && !beam.mean_axes; ++i) sy.push_back(B.op('*', B.at(B.name(n + ".y.mean"), static_cast<int>(i) + 1), eta.y[i]));
    for (std::size_t i = 0; i < eta.z.size() && !beam.mean_axes; ++i) sz.push_back(B.op('*', B.at(B.name(n + ".z.mean"), static_cast<int>(i) + 1), eta.z[i]));
    return B.list({sx, sum_of(B, sy), sum_of(B, sz)});
  }

  /// d s / d eta (3 x n): the translational coupling M_V,eta, rows of scalars.
  std::vector<std::vector<E>> translation_coupling(const Build& B, const std::string& n, const Beam& beam, const Eta& eta) const {
    if (beam.modal) return modal_translation_coupling(B, n, *beam.modal);
    const int ny = static_cast<int>(eta.y.size()), nz = static_cast<int>(eta.z.size());
    std::vector<std::vector<E>> m(3, std::vector<E>(static_cast<std::size_t>(beam.count()), B.num(0)));
    for (int i = 0; i < static_cast<int>(eta.axial.size()) && !beam.mean_axes; ++i)
      m[0][static_cast<std::size_t>(beam.offset_axial() + i)] = B.at(B.name(n + ".a.mean"), i + 1);
    for (int i = 0; i < ny; ++i) {
      if (beam.geometric_stiffness && !beam.tisserand) m[0][static_cast<std::size_t>(i)] = B.neg(row_dot(B, n + ".y.load", i, eta.y));
      if (!beam.mean_axes) m[1][static_cast<std::size_t>(i)] = B.at(B.name(n + ".y.mean"), i + 1);
    }
    for (int i = 0; i < nz; ++i) {
      if (beam.geometric_stiffness && !beam.tisserand) m[0][static_cast<std::size_t>(ny + i)] = B.neg(row_dot(B, n + ".z.load", i, eta.z));
      if (!beam.mean_axes) m[2][static_cast<std::size_t>(ny + i)] = B.at(B.name(n + ".z.mean"), i + 1);
    }
    return m;
  }

  /// The V-omega blocks of M: -skew(s) at (V, omega), skew(s) at (omega, V).
  static void put_first_moment(const Build& B, std::vector<std::vector<E>>& M, E s) {
    std::vector<E> sc = {B.at(s, 1), B.at(s, 2), B.at(s, 3)};
    auto put_skew = [&](int r0, int c0, double sign) {  // sign * skew(s) at (r0, c0)
      auto v = [&](int k) { return sign > 0 ? sc[static_cast<std::size_t>(k)] : B.neg(sc[static_cast<std::size_t>(k)]); };
      M[r0 + 0][c0 + 1] = B.neg(v(2)), M[r0 + 0][c0 + 2] = v(1);
      M[r0 + 1][c0 + 0] = v(2), M[r0 + 1][c0 + 2] = B.neg(v(0));
      M[r0 + 2][c0 + 0] = B.neg(v(1)), M[r0 + 2][c0 + 1] = v(0);
    };
    put_skew(0, 3, -1);
    put_skew(3, 0, +1);
  }

  /// The generalised mass matrix M(eta), (6 + n) x (6 + n), as rows of scalars.
  std::vector<std::vector<E>> mass_matrix(const Build& B, const std::string& n, const Beam& beam, const Eta& eta) const {
    if (beam.modal) return modal_mass_matrix(B, n, *beam.modal, eta.y);
    const std::size_t ne = static_cast<std::size_t>(beam.count()), N = 6 + ne, ny = eta.y.size();
    std::vector<std::vector<E>> M(N, std::vector<E>(N, B.num(0)));
    E zero = B.num(0);
    E m = B.name(n + ".mass");
    for (int k = 0; k < 3; ++k) M[k][k] = m;
    put_first_moment(B, M, first_moment(B, n, beam, eta));
    // omega-omega: J(eta) = J0 + J1(eta) + J2(eta)
    E qy = quadratic(B, n + ".y.mass", eta.y, eta.y), qz = quadratic(B, n + ".z.mass", eta.z, eta.z);
    E qyz = quadratic(B, n + ".yz.mass", eta.y, eta.z);
    E spin = beam.geometric_stiffness ? B.op('+', quadratic(B, n + ".y.spin", eta.y, eta.y), quadratic(B, n + ".z.spin", eta.z, eta.z))
                                      : zero;
    E dy = zero, dz = zero;
    for (std::size_t i = 0; i < eta.y.size() && !beam.mean_axes; ++i) dy = B.op('+', dy, B.op('*', B.at(B.name(n + ".y.moment"), static_cast<int>(i) + 1), eta.y[i]));
    for (std::size_t i = 0; i < eta.z.size() && !beam.mean_axes; ++i) dz = B.op('+', dz, B.op('*', B.at(B.name(n + ".z.moment"), static_cast<int>(i) + 1), eta.z[i]));
    E J0 = B.name(n + ".J0");
    M[3][3] = B.op('+', idx2(B, J0, 1, 1), B.op('+', qy, qz));
    M[4][4] = B.op('+', idx2(B, J0, 2, 2), B.op('-', qz, spin));
    M[5][5] = B.op('+', idx2(B, J0, 3, 3), B.op('-', qy, spin));
    M[3][4] = M[4][3] = B.neg(dy);
    M[3][5] = M[5][3] = B.neg(dz);
    M[4][5] = M[5][4] = B.neg(qyz);
    // V-eta and omega-eta couplings, and the modal mass
    auto tc = translation_coupling(B, n, beam, eta);
    for (std::size_t r = 0; r < 3; ++r)
      for (std::size_t c = 0; c < ne; ++c) M[r][6 + c] = M[6 + c][r] = tc[r][c];
    for (std::size_t j = 0; j < eta.y.size(); ++j) {
      E cx = B.neg(row_dot(B, n + ".yz.mass", static_cast<int>(j), eta.z));
      M[3][6 + j] = M[6 + j][3] = cx;
      if (!beam.mean_axes) M[5][6 + j] = M[6 + j][5] = B.at(B.name(n + ".y.moment"), static_cast<int>(j) + 1);
    }
    for (std::size_t j = 0; j < eta.z.size(); ++j) {
      E cx = row_dot(B, n + ".yz.mass", static_cast<int>(j), eta.y, /*transposed=*/true);
      M[3][6 + ny + j] = M[6 + ny + j][3] = cx;
      if (!beam.mean_axes) M[4][6 + ny + j] = M[6 + ny + j][4] = B.neg(B.at(B.name(n + ".z.moment"), static_cast<int>(j) + 1));
    }
    for (std::size_t i = 0; i < eta.y.size(); ++i)
      for (std::size_t j = 0; j < eta.y.size(); ++j) M[6 + i][6 + j] = idx2(B, B.name(n + ".y.mass"), static_cast<int>(i) + 1, static_cast<int>(j) + 1);
    for (std::size_t i = 0; i < eta.z.size(); ++i)
      for (std::size_t j = 0; j < eta.z.size(); ++j)
        M[6 + ny + i][6 + ny + j] = idx2(B, B.name(n + ".z.mass"), static_cast<int>(i) + 1, static_cast<int>(j) + 1);
    add_stretch_and_twist(B, n, beam, eta, M);
    return M;
  }

  /// Axial and torsion modes in M(eta): the linear fields u = [chi zeta, 0, 0]
  /// (stretch) and a section turned by psi theta about x (twist), with the
  /// inertia invariants of docs/modal_format.md. Stretch changes J_yy, J_zz
  /// by 2 int x u dm + int u^2 dm, couples with bending through int u w dm,
  /// and with omega through int r x u' dm; twist couples with omega_x through
  /// the sections' polar inertia and turns a non-circular section's
  /// principal axes (J_yz). Its second-order inertia terms are left out: a
  /// linearised rotation field gets them wrong.
  void add_stretch_and_twist(const Build& B, const std::string& n, const Beam& beam, const Eta& eta,
                             std::vector<std::vector<E>>& M) const {
    const std::size_t ny = eta.y.size(), nz = eta.z.size();
    const auto oa = static_cast<std::size_t>(6 + beam.offset_axial()), ot = static_cast<std::size_t>(6 + beam.offset_torsion());
    auto plus = [&](E a, E b) { return B.op('+', a, b); };
    auto minus = [&](E a, E b) { return B.op('-', a, b); };
    if (!eta.axial.empty()) {
      E stretch = plus(B.op('*', B.num(2), vec_dot(B, n + ".a.moment", eta.axial)), quadratic(B, n + ".a.mass", eta.axial, eta.axial));
      M[4][4] = plus(M[4][4], stretch);
      M[5][5] = plus(M[5][5], stretch);
      if (ny) M[3][4] = M[4][3] = minus(M[3][4], quadratic(B, n + ".ay.mass", eta.axial, eta.y));
      if (nz) M[3][5] = M[5][3] = minus(M[3][5], quadratic(B, n + ".az.mass", eta.axial, eta.z));
      for (std::size_t k = 0; k < eta.axial.size(); ++k) {
        // omega - stretch rate: int r x [chi, 0, 0] dm = [0, int w_z chi, -int w_y chi]
        if (nz) M[4][oa + k] = M[oa + k][4] = row_dot(B, n + ".az.mass", static_cast<int>(k), eta.z);
        if (ny) M[5][oa + k] = M[oa + k][5] = B.neg(row_dot(B, n + ".ay.mass", static_cast<int>(k), eta.y));
        for (std::size_t l = 0; l < eta.axial.size(); ++l)
          M[oa + k][oa + l] = idx2(B, B.name(n + ".a.mass"), static_cast<int>(k) + 1, static_cast<int>(l) + 1);
      }
      // omega - bending rate, through the stretched position: [u, 0, 0] x phi
      for (std::size_t l = 0; l < ny; ++l)
        M[5][6 + l] = M[6 + l][5] = plus(M[5][6 + l], row_dot(B, n + ".ay.mass", static_cast<int>(l), eta.axial, /*transposed=*/true));
      for (std::size_t l = 0; l < nz; ++l)
        M[4][6 + ny + l] = M[6 + ny + l][4] = minus(M[4][6 + ny + l], row_dot(B, n + ".az.mass", static_cast<int>(l), eta.axial, /*transposed=*/true));
    }
    if (!eta.torsion.empty()) {
      M[4][5] = M[5][4] = minus(M[4][5], vec_dot(B, n + ".t.product", eta.torsion));
      for (std::size_t k = 0; k < eta.torsion.size(); ++k) {
        M[3][ot + k] = M[ot + k][3] = B.at(B.name(n + ".t.mean"), static_cast<int>(k) + 1);
        for (std::size_t l = 0; l < eta.torsion.size(); ++l)
          M[ot + k][ot + l] = idx2(B, B.name(n + ".t.mass"), static_cast<int>(k) + 1, static_cast<int>(l) + 1);
      }
    }
  }

  E rows_to_matrix(const Build& B, const std::vector<std::vector<E>>& m) const {
    std::vector<E> rows_;
    for (const auto& r : m) rows_.push_back(B.list(r));
    return B.list(rows_);
  }

  /// Modal damping 2 zeta omega_i m_i = 2 zeta sqrt(K_ii M_ii) per mode (zeta: the body's `damping`, or none).
  void modal_damping(const Build& B, const std::string& name, E zeta, int count, const std::string& K, const std::string& M) {
    std::vector<E> c;
    for (int i = 1; i <= count; ++i)
      c.push_back(B.op('*', B.op('*', B.num(2), zeta ? zeta : B.num(0)),
                       B.call("sqrt", {B.op('*', idx2(B, B.name(K), i, i), idx2(B, B.name(M), i, i))})));
    param(B, name, c.size() == 1 ? B.list({B.list({c[0]})}) : B.call("diag", c));
  }

  /// Parameters of stretch and twist: the rod modes' integrals times mu (stretch) or the sections' rho Ip (twist).
  void rod_params(const Build& B, const Body& body) {
    const AstBody& d = *body.decl;
    const std::string& n = d.name;
    const Beam& beam = *body.beam;
    E damping = attr(d, "damping"), mu = B.name(n + ".mu"), rho = B.name(n + ".density");
    if (beam.axial) {
      const flex::RodIntegrals I = flex::rod_integrals(*beam.axial);
      param(B, n + ".a.mean", B.op('*', mu, vector_param(B, I.mean)));
      param(B, n + ".a.moment", B.op('*', mu, vector_param(B, I.moment)));
      param(B, n + ".a.mass", B.op('*', mu, matrix_param(B, I.mass)));
      param(B, n + ".a.stiffness", B.op('*', B.op('*', B.name(n + ".E"), B.name(n + ".area")), matrix_param(B, I.stiffness)));
      modal_damping(B, n + ".a.damping", damping, beam.axial->count(), n + ".a.stiffness", n + ".a.mass");
      if (beam.y) param(B, n + ".ay.mass", B.op('*', mu, matrix_param(B, flex::cross_mass(*beam.axial, *beam.y))));
      if (beam.z) param(B, n + ".az.mass", B.op('*', mu, matrix_param(B, flex::cross_mass(*beam.axial, *beam.z))));
    }
    if (beam.torsion) {
      const flex::RodIntegrals I = flex::rod_integrals(*beam.torsion);
      param(B, n + ".G", attr(d, "G"));
      param(B, n + ".Ip", B.op('+', B.name(n + ".Iy"), B.name(n + ".Iz")));  // polar moment of the section
      if (E J = attr(d, "torsion_constant")) param(B, n + ".torsion_constant", J);
      else param(B, n + ".torsion_constant", torsion_constant(B, *attr(d, "section"), n));
      E rhoIp = B.op('*', rho, B.name(n + ".Ip"));
      param(B, n + ".t.mean", B.op('*', rhoIp, vector_param(B, I.mean)));
      param(B, n + ".t.mass", B.op('*', rhoIp, matrix_param(B, I.mass)));
      // a twisted section turns its principal axes: J_yz changes by -rho (Iz - Iy) theta per length
      param(B, n + ".t.product", B.op('*', B.op('*', rho, B.op('-', B.name(n + ".Iz"), B.name(n + ".Iy"))), vector_param(B, I.mean)));
      param(B, n + ".t.stiffness", B.op('*', B.op('*', B.name(n + ".G"), B.name(n + ".torsion_constant")), matrix_param(B, I.stiffness)));
      modal_damping(B, n + ".t.damping", damping, beam.torsion->count(), n + ".t.stiffness", n + ".t.mass");
    }
  }
  /// Saint-Venant torsion constant: the polar moment for circle and tube (exact);
  /// a rectangle a x b, a >= b: a b^3 (1/3 - 0.21 (b/a) (1 - b^4 / (12 a^4))) (Roark, within 0.5 %).
  E torsion_constant(const Build& B, const AstExpr& section, const std::string& n) const {
    if (section.name != "rectangle") return B.name(n + ".Ip");
    E a = B.call("max", {section.args[0], section.args[1]}), b = B.call("min", {section.args[0], section.args[1]});
    auto pw = [&](E x, double k) { return B.op('^', x, B.num(k)); };
    E bracket = B.op('-', B.num(1.0 / 3.0),
                     B.op('*', B.op('*', B.num(0.21), B.op('/', b, a)), B.op('-', B.num(1), B.op('/', pw(b, 4), B.op('*', B.num(12), pw(a, 4))))));
    return B.op('*', B.op('*', a, pw(b, 3)), bracket);
  }

  /// Parameters of a beam: section, material and the modal integrals (constants).
  void beam_params(const Build& B, const Body& body) {
    const AstBody& d = *body.decl;
    const std::string& n = d.name;
    const Beam& beam = *body.beam;
    if (beam.modal) return modal_params(B, body);
    param(B, n + ".length", B.num(beam.length_m));
    param(B, n + ".density", attr(d, "density"));
    param(B, n + ".E", attr(d, "E"));
    if (E sec = attr(d, "section")) {
      const std::string& kind = sec->name;
      E a = sec->args[0], b = sec->args.size() > 1 ? sec->args[1] : nullptr;
      auto pw = [&](E x, double k) { return B.op('^', x, B.num(k)); };
      E pi = B.name("pi");
      if (kind == "rectangle") {  // width along y, height along z
        param(B, n + ".area", B.op('*', a, b));
        param(B, n + ".Iy", B.op('/', B.op('*', a, pw(b, 3)), B.num(12)));
        param(B, n + ".Iz", B.op('/', B.op('*', b, pw(a, 3)), B.num(12)));
      } else if (kind == "circle") {
        param(B, n + ".area", B.op('/', B.op('*', pi, pw(a, 2)), B.num(4)));
        param(B, n + ".Iy", B.op('/', B.op('*', pi, pw(a, 4)), B.num(64)));
        param(B, n + ".Iz", B.name(n + ".Iy"));
      } else {  // tube(outer, inner)
        param(B, n + ".area", B.op('/', B.op('*', pi, B.op('-', pw(a, 2), pw(b, 2))), B.num(4)));
        param(B, n + ".Iy", B.op('/', B.op('*', pi, B.op('-', pw(a, 4), pw(b, 4))), B.num(64)));
        param(B, n + ".Iz", B.name(n + ".Iy"));
      }
    } else {
      param(B, n + ".area", attr(d, "area"));
      param(B, n + ".Iy", attr(d, "Iy"));
      param(B, n + ".Iz", attr(d, "Iz"));
    }
    E rho = B.name(n + ".density"), L = B.name(n + ".length");
    param(B, n + ".mu", B.op('*', rho, B.name(n + ".area")));  // mass per length, kg/m
    param(B, n + ".mass", B.op('*', B.name(n + ".mu"), L));
    // about the frame origin, undeformed: the line's x^2 moment plus the sections' own inertia
    E line = B.op('/', B.op('*', B.name(n + ".mu"), B.op('^', L, B.num(3))), B.num(3));
    if (beam.origin_m != 0) {  // int s^2 mu ds over [-c, L - c]
      const double c = beam.origin_m, hi = beam.length_m - c;
      line = B.op('*', B.name(n + ".mu"), B.num((hi * hi * hi + c * c * c) / 3));
    }
    E Iy = B.op('*', B.op('*', rho, L), B.name(n + ".Iy")), Iz = B.op('*', B.op('*', rho, L), B.name(n + ".Iz"));
    param(B, n + ".J0", B.call("diag", {B.op('+', Iy, Iz), B.op('+', line, Iy), B.op('+', line, Iz)}));
    // what the joints' code reads of every body: the reference point is the frame origin
    param(B, n + ".com", B.vec(0, 0, 0));
    param(B, n + ".inertia", B.name(n + ".J0"));
    E damping = attr(d, "damping");
    for (const auto& [plane, modes] : {std::pair{"y", &beam.y}, std::pair{"z", &beam.z}}) {
      if (!*modes) continue;
      const flex::ModalIntegrals I = flex::modal_integrals(**modes);
      const std::string p = n + "." + plane;
      E mu = B.name(n + ".mu");
      E EI = B.op('*', B.name(n + ".E"), B.name(n + (plane[0] == 'y' ? ".Iz" : ".Iy")));  // deflection along y bends about z
      if (beam.mean_axes) {
        // what the mean axes remove, and how small it is for these modes (per unit mass and length)
        double largest = 0;
        for (double x : I.mean) largest = std::max(largest, std::abs(x) / beam.length_m);
        for (double x : I.moment) largest = std::max(largest, std::abs(x) / (beam.length_m * beam.length_m));
        diags_.note(d.loc, fmt::format("beam `{}` in mean axes (frame = {}): its free-free modes along body {} are "
                                       "orthogonal to the rigid motions (int phi dm and int x phi dm are {:.1e} of m L "
                                       "and m L^2), so the compiler leaves the translational coupling `{}.mean` and the "
                                       "rotational coupling `{}.moment` out of the mass matrix",
                                       n, beam.tisserand ? "tisserand" : "buckens", plane, largest, p, p));
        if (beam.tisserand)
          diags_.note(d.loc, fmt::format("beam `{}` in Tisserand's frame: its origin is the mass centre (x = {} m along "
                                         "the beam), the foreshortening of bending is measured from its mean so it moves "
                                         "no mass (thesis eq. 5.30), and int phi x phi dm is zero for one bending plane "
                                         "(5.34): the axial-acceleration coupling `{}.load` drops out too, and the frame's "
                                         "translation decouples from rotation and modes (eqs. 5.35-5.38)",
                                         n, beam.origin_m, p));
      } else {
        param(B, p + ".mean", B.op('*', mu, vector_param(B, I.mean)));
        param(B, p + ".moment", B.op('*', mu, vector_param(B, I.moment)));
      }
      param(B, p + ".mass", B.op('*', mu, matrix_param(B, I.mass)));
      param(B, p + ".stiffness", B.op('*', EI, matrix_param(B, I.bending)));
      if (beam.geometric_stiffness) {
        if (!beam.tisserand) param(B, p + ".load", B.op('*', mu, matrix_param(B, I.load)));
        param(B, p + ".spin", B.op('*', mu, matrix_param(B, I.spin)));
      }
      modal_damping(B, p + ".damping", damping, (*modes)->count(), p + ".stiffness", p + ".mass");
    }
    if (beam.origin_m != 0 && !beam.tisserand)
      diags_.note(d.loc, fmt::format("beam `{}` with its frame at the mass centre (frame = centre, x = {} m along the beam): "
                                     "its free-free modes are measured from the section there (each mode's rigid motion "
                                     "phi(c) + phi'(c) (x - c) subtracted), so no coupling term drops out of the mass matrix",
                                     n, beam.origin_m));
    if (beam.y && beam.z) param(B, n + ".yz.mass", B.op('*', B.name(n + ".mu"), matrix_param(B, flex::cross_mass(*beam.y, *beam.z))));
    rod_params(B, body);
    for (const auto& [pt, x] : beam.point_x) {
      for (const auto& [plane, modes] : {std::pair{"y", &beam.y}, std::pair{"z", &beam.z}}) {
        if (!*modes) continue;
        std::vector<double> phi, slope;
        for (int i = 0; i < (*modes)->count(); ++i) phi.push_back((*modes)->shape(i, x)), slope.push_back((*modes)->shape(i, x, 1));
        const std::string p = n + "." + pt + "." + plane;
        param(B, p + ".shape", vector_param(B, phi));
        param(B, p + ".slope", vector_param(B, slope));
        if (beam.geometric_stiffness) param(B, p + ".shortening", matrix_param(B, flex::axial_up_to(**modes, x)));
      }
      for (const auto& [group, modes] : {std::pair{"a", &beam.axial}, std::pair{"t", &beam.torsion}}) {
        if (!*modes) continue;
        std::vector<double> chi;
        for (int i = 0; i < (*modes)->count(); ++i) chi.push_back((*modes)->shape(i, x));
        param(B, n + "." + pt + "." + group + ".shape", vector_param(B, chi));
      }
    }
  }

  // ---- 2c. bodies from modal-data files ---------------------------------------------------
  // The same floating-frame equations as a beam, with M(eta) built from the
  // file's inertia invariants (docs/modal_format.md) for the linear field
  // u = Phi(r0) eta: every coefficient is a constant the compiler computes
  // here and writes as a parameter, so the generated code reads
  // J(eta)_xy = J0_xy + J1.xy . eta + eta' J2.xy eta.

  static constexpr const char* kAxes[3] = {"x", "y", "z"};
  static bool all_zero(const flex::Matrix& m) {
    for (const auto& r : m)
      for (double x : r)
        if (x != 0) return false;
    return true;
  }
  using ModalTerms = flex::ModalMassTerms;
  static ModalTerms modal_terms(const flex::ModalData& d) { return flex::modal_mass_terms(d); }
  static std::string axes(std::size_t i, std::size_t j) { return std::string(kAxes[i]) + kAxes[j]; }

  void modal_params(const Build& B, const Body& body) {
    const std::string& n = body.decl->name;
    const flex::ModalData& d = *body.beam->modal;
    const ModalTerms t = modal_terms(d);
    param(B, n + ".mass", B.num(d.mass_kg));
    param(B, n + ".first_moment", B.vec(d.first_moment_kg_m[0], d.first_moment_kg_m[1], d.first_moment_kg_m[2]));
    param(B, n + ".J0", matrix_param(B, d.inertia_kg_m2));
    // what the joints' code reads of every body: the reference point is the frame origin
    param(B, n + ".com", B.vec(0, 0, 0));
    param(B, n + ".inertia", B.name(n + ".J0"));
    param(B, n + ".mean", matrix_param(B, d.mean_kg));
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = i; j < 3; ++j) {
        if (!all_zero(t.J1[i][j])) param(B, n + ".J1." + axes(i, j), vector_param(B, t.J1[i][j][0]));
        if (!all_zero(t.J2[i][j])) param(B, n + ".J2." + axes(i, j), matrix_param(B, t.J2[i][j]));
      }
    for (std::size_t i = 0; i < 3; ++i) {
      if (!all_zero(t.coupling[i])) param(B, n + ".coupling." + kAxes[i], vector_param(B, t.coupling[i][0]));
      if (!all_zero(t.coupling_eta[i])) param(B, n + ".coupling_eta." + kAxes[i], matrix_param(B, t.coupling_eta[i]));
    }
    param(B, n + ".modal_mass", matrix_param(B, t.modal_mass));
    param(B, n + ".stiffness", matrix_param(B, d.stiffness));
    modal_damping(B, n + ".damping", attr(*body.decl, "damping"), d.count, n + ".stiffness", n + ".modal_mass");
    for (const auto& [pt, node] : d.points) {
      param(B, n + "." + pt + ".shape", matrix_param(B, node.shape));
      param(B, n + "." + pt + ".slope", matrix_param(B, node.slope));
    }
  }

  /// s(eta) = int r0 dm + C eta.
  E modal_first_moment(const Build& B, const std::string& n, const std::vector<E>& eta) const {
    std::vector<E> s;
    for (int i = 0; i < 3; ++i) s.push_back(B.op('+', B.at(B.name(n + ".first_moment"), i + 1), row_dot(B, n + ".mean", i, eta)));
    return B.list(s);
  }
  std::vector<std::vector<E>> modal_translation_coupling(const Build& B, const std::string& n, const flex::ModalData& d) const {
    std::vector<std::vector<E>> m(3);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < d.count; ++k) m[static_cast<std::size_t>(i)].push_back(idx2(B, B.name(n + ".mean"), i + 1, k + 1));
    return m;
  }
  std::vector<std::vector<E>> modal_mass_matrix(const Build& B, const std::string& n, const flex::ModalData& d,
                                                const std::vector<E>& eta) const {
    const std::size_t ne = eta.size(), N = 6 + ne;
    const ModalTerms t = modal_terms(d);
    std::vector<std::vector<E>> M(N, std::vector<E>(N, B.num(0)));
    for (std::size_t k = 0; k < 3; ++k) M[k][k] = B.name(n + ".mass");
    put_first_moment(B, M, modal_first_moment(B, n, eta));
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = i; j < 3; ++j) {
        E J = idx2(B, B.name(n + ".J0"), static_cast<int>(i) + 1, static_cast<int>(j) + 1);
        const std::string ij = axes(i, j);
        if (!all_zero(t.J1[i][j])) J = B.op('+', J, B.dot(B.name(n + ".J1." + ij), B.list(eta)));
        if (!all_zero(t.J2[i][j])) J = B.op('+', J, quadratic(B, n + ".J2." + ij, eta, eta));
        M[3 + i][3 + j] = M[3 + j][3 + i] = J;
      }
    auto tc = modal_translation_coupling(B, n, d);
    for (std::size_t l = 0; l < ne; ++l) {
      for (std::size_t i = 0; i < 3; ++i) {
        M[i][6 + l] = M[6 + l][i] = tc[i][l];
        const std::string axis = kAxes[i];
        E c = nullptr;
        if (!all_zero(t.coupling[i])) c = B.at(B.name(n + ".coupling." + axis), static_cast<int>(l) + 1);
        if (!all_zero(t.coupling_eta[i])) {
          E more = row_dot(B, n + ".coupling_eta." + axis, static_cast<int>(l), eta, /*transposed=*/true);
          c = c ? B.op('+', c, more) : more;
        }
        if (c) M[3 + i][6 + l] = M[6 + l][3 + i] = c;
      }
      for (std::size_t k = 0; k < ne; ++k)
        M[6 + k][6 + l] = idx2(B, B.name(n + ".modal_mass"), static_cast<int>(k) + 1, static_cast<int>(l) + 1);
    }
    return M;
  }
  /// A node's deflected position (what = "shape", at = its undeformed position) or small rotation ("slope").
  E modal_point(const Build& B, const std::string& n, const std::string& pt, const char* what, std::array<double, 3> at,
                const std::vector<E>& eta) const {
    std::vector<E> v;
    for (int i = 0; i < 3; ++i) {
      E moved = row_dot(B, n + "." + pt + "." + what, i, eta);
      v.push_back(at[static_cast<std::size_t>(i)] == 0 ? moved : B.op('+', B.num(at[static_cast<std::size_t>(i)]), moved));
    }
    return B.list(v);
  }
  /// A mode's limit: where it alone turns one of the file's nodes by the slope limit.
  static std::vector<std::pair<double, std::string>> modal_file_limits(const std::string& n, const Beam& beam) {
    const flex::ModalData& d = *beam.modal;
    std::vector<std::pair<double, std::string>> limits;
    for (int k = 0; k < d.count; ++k) {
      double peak = 0;
      for (const auto& [pt, node] : d.points) {
        double r2 = 0;
        for (const auto& row : node.slope) r2 += row[static_cast<std::size_t>(k)] * row[static_cast<std::size_t>(k)];
        peak = std::max(peak, std::sqrt(r2));
      }
      limits.push_back(
          {peak > 0 ? beam.slope_limit_rad / peak : std::numeric_limits<double>::max(),
           fmt::format("mode {} of modal body `{}` (from {}) turns one of its nodes by more than {:g} rad, beyond the "
                       "small rotations of a linear modal model (`slope_limit`). Likely cause: an instability - a load "
                       "beyond what the linear model holds, or a spin faster than the body's first natural frequency "
                       "(a modal-data body has no geometric stiffness)",
                       k + 1, n, d.path, beam.slope_limit_rad)});
    }
    return limits;
  }

  /// The body-frame position of a point of a beam, deflected: [x - 1/2 eta^T a(x) eta, w_y, w_z].
  E beam_point(const Build& B, const std::string& n, const Beam& beam, const std::string& pt, const Eta& eta) const {
    if (beam.modal) return modal_point(B, n, pt, "shape", beam.modal->points.at(pt).position, eta.y);
    E x = B.num(beam.point_x.at(pt) - beam.origin_m);
    std::vector<E> wy, wz;
    for (std::size_t i = 0; i < eta.y.size(); ++i) wy.push_back(B.op('*', B.at(B.name(n + "." + pt + ".y.shape"), static_cast<int>(i) + 1), eta.y[i]));
    for (std::size_t i = 0; i < eta.z.size(); ++i) wz.push_back(B.op('*', B.at(B.name(n + "." + pt + ".z.shape"), static_cast<int>(i) + 1), eta.z[i]));
    if (beam.geometric_stiffness) {
      E a = B.op('+', quadratic(B, n + "." + pt + ".y.shortening", eta.y, eta.y), quadratic(B, n + "." + pt + ".z.shortening", eta.z, eta.z));
      x = B.op('-', x, B.op('*', B.num(0.5), a));
    }
    if (!eta.axial.empty()) x = B.op('+', x, vec_dot(B, n + "." + pt + ".a.shape", eta.axial));  // stretch
    return B.list({x, sum_of(B, wy), sum_of(B, wz)});
  }
  /// The small rotation of the section at a point (body axes): [0, -w_z', w_y'].
  E beam_slope(const Build& B, const std::string& n, const Beam& beam, const std::string& pt, const Eta& eta) const {
    if (beam.modal) return modal_point(B, n, pt, "slope", {0, 0, 0}, eta.y);
    std::vector<E> ty, tz;
    for (std::size_t i = 0; i < eta.y.size(); ++i) ty.push_back(B.op('*', B.at(B.name(n + "." + pt + ".y.slope"), static_cast<int>(i) + 1), eta.y[i]));
    for (std::size_t i = 0; i < eta.z.size(); ++i) tz.push_back(B.op('*', B.at(B.name(n + "." + pt + ".z.slope"), static_cast<int>(i) + 1), eta.z[i]));
    E twist = eta.torsion.empty() ? B.num(0) : vec_dot(B, n + "." + pt + ".t.shape", eta.torsion);
    return B.list({twist, B.neg(sum_of(B, tz)), sum_of(B, ty)});
  }
  Eta state_eta(const Build& B, const std::string& n, const Beam& beam) const {
    return split_eta(beam, [&](int k) { return eta_of(B, n, k); });
  }

  /// Where a modal coordinate leaves the model's range: the value at which
  /// that mode alone tilts the beam by its slope limit somewhere (the
  /// kinematics keep slopes to second order). A mode growing that far is
  /// almost always an instability: the run stops and says which.
  static std::vector<std::pair<double, std::string>> modal_limits(const std::string& n, const Beam& beam) {
    if (beam.modal) return modal_file_limits(n, beam);
    std::vector<std::pair<double, std::string>> limits;
    add_bending_limits(n, beam, limits);
    // stretch: the linear strain model holds to small strains; twist: to the slope limit, as bending
    for (const auto& [what, modes] : {std::pair{"stretch", &beam.axial}, std::pair{"twist", &beam.torsion}}) {
      if (!*modes) continue;
      for (int i = 0; i < (*modes)->count(); ++i) {
        const bool stretch = what[0] == 's';
        const double k = (*modes)->k_L(i) / beam.length_m, peak = std::sqrt(2.0) * (stretch ? k : 1.0);
        limits.push_back(
            {(stretch ? kStrainLimit : beam.slope_limit_rad) / peak,
             stretch ? fmt::format("axial mode {} of beam `{}` ({}) strains it by more than {:g}, beyond the small strains of "
                                   "its linear model. Likely cause: an instability, or a load far beyond the material's",
                                   i + 1, n, flex::rod_ends_name((*modes)->ends()), kStrainLimit)
                     : fmt::format("torsion mode {} of beam `{}` ({}) twists it by more than {:g} rad, beyond the small "
                                   "rotations of its linear model (`slope_limit`). Likely cause: an instability, or a torque "
                                   "far beyond the section's",
                                   i + 1, n, flex::rod_ends_name((*modes)->ends()), beam.slope_limit_rad)});
      }
    }
    return limits;
  }
  static constexpr double kStrainLimit = 0.01;
  static void add_bending_limits(const std::string& n, const Beam& beam, std::vector<std::pair<double, std::string>>& limits) {
    for (const auto& [plane, modes] : {std::pair{"y", &beam.y}, std::pair{"z", &beam.z}}) {
      if (!*modes) continue;
      for (int i = 0; i < (*modes)->count(); ++i) {
        double peak_slope = 0;
        for (int k = 0; k <= 1000; ++k)
          peak_slope = std::max(peak_slope, std::abs((*modes)->shape(i, beam.length_m * k / 1000, 1)));
        limits.push_back(
            {beam.slope_limit_rad / peak_slope,
             fmt::format("mode {} of beam `{}` ({}, bending along body {}) tilts it by more than {:g} rad, beyond the "
                         "moderate slopes the modal model holds for (`slope_limit`). Likely cause: an instability - the "
                         "beam compressed beyond its buckling load, or spinning faster than its first natural frequency "
                         "without geometric stiffness",
                         i + 1, n, flex::supports_name((*modes)->supports()), plane, beam.slope_limit_rad)});
      }
    }
  }

  void emit_beam(const Body& body) {
    const AstBody& d = *body.decl;
    const std::string& n = d.name;
    const Beam& beam = *body.beam;
    Build B(d.loc);
    beam_params(B, body);
    for (const auto& [p, v] : body.points) param(B, n + "." + p, v);
    const int ne = beam.count(), N = 6 + ne;
    Eta eta = state_eta(B, n, beam);
    Eta rest = split_eta(beam, [&](int) { return B.num(0); });
    // the I field and its velocity terms on the common junction nu = [V; omega; eta']
    std::vector<std::string> nu_in;
    if (gravity_) nu_in.push_back(n + ".weight");
    if (auto it = loads_.find(n); it != loads_.end())
      for (const std::string& f : it->second) nu_in.push_back(f + ".on_" + n);
    junction(B, '1', n + ".nu", N, nu_in, {n + ".M", n + ".ejs", n + ".sv.p1", n + ".sw.p1", n + ".se.p1"});
    E R0 = B.call("rotq", {B.name(n + ".q0")});
    E nu0 = B.call("vcat", {B.op('*', B.call("transpose", {R0}), B.name(n + ".v0")), B.name(n + ".w0"), B.call("zeros", {B.num(ne)})});
    element(B, "I", n + ".M", rows_to_matrix(B, mass_matrix(B, n, beam, eta)),
            {kv("p0", B.op('*', rows_to_matrix(B, mass_matrix(B, n, beam, rest)), nu0), d.loc)});
    std::get<AstElement>(generated_.back()).configuration_dependent = true;
    E f = B.name("f"), p = B.name(n + ".M.p");
    auto part = [&](E v, int from) { return B.list({B.at(v, from), B.at(v, from + 1), B.at(v, from + 2)}); };
    E V = part(f, 1), w = part(f, 4), P = part(p, 1), H = part(p, 4);
    auto cross = [&](E a, E b) { return B.call("cross", {std::move(a), std::move(b)}); };
    // dT/deta at constant nu (Kirchhoff): the kinetic energy's change with the beam's shape
    E T = B.op('*', B.num(0.5), B.dot(f, B.op('*', rows_to_matrix(B, mass_matrix(B, n, beam, eta)), f)));
    E dT = B.call("transpose", {B.call("jacobian", {T, B.name(n + ".eta.q")})});
    element(B, "R", n + ".ejs", nullptr,
            {kv("e", B.call("vcat", {cross(w, P), B.op('+', cross(w, H), cross(V, P)), B.neg(dT)}), d.loc)});
    if (gravity_) {
      // generalised gravity force: -dU/d(position, rotation, eta) with U = -g . (m r + R s(eta))
      E g = B.op('*', B.call("transpose", {B.call("rotq", {B.name(n + ".q.q")})}), B.name("gravity"));
      E coupling = rows_to_matrix(B, translation_coupling(B, n, beam, eta));
      element(B, "Se", n + ".weight",
              B.call("vcat", {B.op('*', B.name(n + ".mass"), g), cross(first_moment(B, n, beam, eta), g),
                              B.op('*', B.call("transpose", {coupling}), g)}));
    }
    // selectors: V (turned to world axes), omega, eta'
    E Rq = B.call("rotq", {B.name(n + ".q.q")});
    element(B, "MTF", n + ".sv", B.call("hcat", {Rq, B.call("zeros", {B.num(3), B.num(3 + ne)})}));
    element(B, "MTF", n + ".sw", B.call("hcat", {B.call("zeros", {B.num(3), B.num(3)}), B.call("eye", {B.num(3)}), B.call("zeros", {B.num(3), B.num(ne)})}));
    element(B, "MTF", n + ".se", B.call("hcat", {B.call("zeros", {B.num(ne), B.num(6)}), B.call("eye", {B.num(ne)})}));
    // position and orientation, as on a rigid body
    junction(B, '1', n + ".v", 3, {n + ".sv.p2"}, {n + ".r"});
    element(B, "C", n + ".r", nullptr, {kv("e", B.vec(0, 0, 0), d.loc), kv("q0", B.name(n + ".r0"), d.loc)});
    junction(B, '1', n + ".w", 3, {n + ".sw.p2"}, {n + ".qrate.p1"});
    element(B, "MTF", n + ".qrate", B.call("quat_rate", {B.name(n + ".q.q")}));
    element(B, "C", n + ".q", nullptr, {kv("e", B.list({B.num(0), B.num(0), B.num(0), B.num(0)}), d.loc), kv("q0", B.name(n + ".q0"), d.loc)});
    bond(B, n + ".qrate.p2", n + ".q", 4);
    // elasticity and modal damping on eta'
    std::vector<std::string> modal_out = {n + ".eta"};
    if (attr(d, "damping")) modal_out.push_back(n + ".damp");
    junction(B, '1', n + ".etadot", ne, {n + ".se.p2"}, modal_out);
    std::vector<std::vector<E>> K(static_cast<std::size_t>(ne), std::vector<E>(static_cast<std::size_t>(ne), B.num(0)));
    std::vector<std::vector<E>> D = K;
    for (int i = 0; i < (beam.modal ? ne : 0); ++i)
      for (int j = 0; j < ne; ++j) {
        K[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = idx2(B, B.name(n + ".stiffness"), i + 1, j + 1);
        D[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = idx2(B, B.name(n + ".damping"), i + 1, j + 1);
      }
    for (const auto& [plane, modes, off] : {std::tuple{"y", &beam.y, 0}, std::tuple{"z", &beam.z, beam.offset_z()}}) {
      if (!*modes) continue;
      for (int i = 0; i < (*modes)->count(); ++i)
        for (int j = 0; j < (*modes)->count(); ++j) {
          K[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.name(n + "." + plane + ".stiffness"), i + 1, j + 1);
          D[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.name(n + "." + plane + ".damping"), i + 1, j + 1);
        }
    }
    for (const auto& [group, count, off] : {std::tuple{"a", beam.axial ? beam.axial->count() : 0, beam.offset_axial()},
                                            std::tuple{"t", beam.torsion ? beam.torsion->count() : 0, beam.offset_torsion()}})
      for (int i = 0; i < count; ++i)
        for (int j = 0; j < count; ++j) {
          K[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.name(n + "." + group + ".stiffness"), i + 1, j + 1);
          D[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.name(n + "." + group + ".damping"), i + 1, j + 1);
        }
    element(B, "C", n + ".eta", nullptr,
            {kv("e", B.op('*', rows_to_matrix(B, K), B.name("q")), d.loc), kv("q0", B.call("zeros", {B.num(ne)}), d.loc)});
    std::get<AstElement>(generated_.back()).state_limits = modal_limits(n, beam);
    if (attr(d, "damping")) element(B, "R", n + ".damp", rows_to_matrix(B, D));
  }

  // ---- pose of a body: its states, or (joint coordinates) signals of its tree joint ----
  /// Centre-of-mass position, world frame.
  E position(const Build& B, const std::string& body) const {
    const Body& b = bodies_.at(body);
    if (b.ground) return B.vec(0, 0, 0);
    if (!b.by_coordinates) return B.name(body + ".r.q");
    return B.list({B.name(body + ".pose.r1"), B.name(body + ".pose.r2"), B.name(body + ".pose.r3")});
  }
  /// Orientation quaternion [w, x, y, z], body -> world.
  E quaternion(const Build& B, const std::string& body) const {
    const Body& b = bodies_.at(body);
    if (b.ground || b.particle) return B.list({B.num(1), B.num(0), B.num(0), B.num(0)});
    if (!b.by_coordinates) return B.name(body + ".q.q");
    std::vector<E> q;
    for (int k = 1; k <= 4; ++k) q.push_back(B.name(fmt::format("{}.pose.q{}", body, k)));
    return B.list(q);
  }
  /// Rotation matrix body -> world (computed once per body in coordinates).
  E rotation(const Build& B, const std::string& body) const {
    const Body& b = bodies_.at(body);
    if (b.ground || b.particle) return B.call("eye", {B.num(3)});
    if (!b.by_coordinates) return B.call("rotq", {B.name(body + ".q.q")});
    std::vector<E> rows_;
    for (int r = 1; r <= 3; ++r) {
      std::vector<E> row;
      for (int c = 1; c <= 3; ++c) row.push_back(B.name(fmt::format("{}.pose.R{}{}", body, r, c)));
      rows_.push_back(B.list(row));
    }
    return B.list(rows_);
  }
  void signal(const Build& B, const std::string& name, E value) {
    generated_names_.insert(name);
    generated_.push_back(AstSignal{name, B.loc(), std::move(value)});
  }

  // ---- 3. joints -------------------------------------------------------------------------
  /// World-frame expressions of one side of a joint.
  struct Frame {
    bool ground = false, particle = false;
    std::string body;
    E R;         // rotation body -> world (eye(3) for ground and particles)
    E p;         // joint point, world
    E local;     // joint point, body frame relative to the reference point (a beam's: deflected)
    E X, Y, Z;   // joint-frame axes, world
  };

  Frame frame(const Build& B, const Joint& j, const Side& s, const std::string& tag) {
    const Body& body = bodies_.at(s.body);
    Frame f;
    f.ground = body.ground;
    f.particle = body.particle;
    f.body = s.body;
    const std::string jn = j.decl->name;
    f.R = rotation(B, s.body);
    E local = B.name(jn + ".p" + tag);  // the point in CoM-relative body coordinates (ground: absolute)
    E turn = f.R;                       // the joint frame's rotation (a beam's section turns with its slope)
    if (body.beam && !s.point.empty()) {
      Eta eta = state_eta(B, s.body, *body.beam);
      local = beam_point(B, s.body, *body.beam, s.point, eta);
      turn = B.op('*', f.R, B.op('+', B.call("eye", {B.num(3)}), B.call("skew", {beam_slope(B, s.body, *body.beam, s.point, eta)})));
    }
    if (body.ground) f.p = local;
    else if (body.particle) f.p = position(B, s.body);
    else f.p = B.op('+', position(B, s.body), B.op('*', f.R, local));
    f.local = local;
    E F = B.op('*', turn, B.name(jn + ".F" + tag));
    f.X = B.op('*', F, B.vec(1, 0, 0));
    f.Y = B.op('*', F, B.vec(0, 1, 0));
    f.Z = B.op('*', F, B.vec(0, 0, 1));
    return f;
  }

  void joint_params(const Build& B, const Joint& j) {
    const std::string jn = j.decl->name;
    for (const auto& [s, tag] : {std::pair{&j.a, "a"}, std::pair{&j.b, "b"}}) {
      const Body& body = bodies_.at(s->body);
      E point = s->point.empty() ? B.vec(0, 0, 0) : B.name(s->body + "." + s->point);
      if (body.ground || body.particle) param(B, jn + ".p" + tag, point);
      else param(B, jn + ".p" + tag, B.op('-', point, B.name(s->body + ".com")));
      const AstAttr* ax = j.attrs.count(std::string("axis_") + tag) ? j.attrs.at(std::string("axis_") + tag)
                          : j.attrs.count("axis")                     ? j.attrs.at("axis")
                                                                      : nullptr;
      E axis = ax ? ax->value : B.vec(0, 0, 1);
      param(B, jn + ".axis_" + tag, B.op('/', axis, B.call("norm", {axis})));
      param(B, jn + ".f" + tag, B.call("quat_arc", {B.name(jn + ".axis_" + tag)}));
      param(B, jn + ".F" + tag, B.call("rotq", {B.name(jn + ".f" + tag)}));
    }
    // Length scale that turns the angular rows (dot products) into metres: the
    // radius of gyration of the lighter body, so one stiffness suits all rows.
    std::vector<E> radii;
    for (const Side* s : {&j.a, &j.b}) {
      const Body& body = bodies_.at(s->body);
      if (body.ground || body.particle) continue;
      E I = B.name(s->body + ".inertia");
      E trace = B.op('+', B.op('+', idx2(B, I, 1, 1), idx2(B, I, 2, 2)), idx2(B, I, 3, 3));
      radii.push_back(B.call("sqrt", {B.op('/', trace, B.op('*', B.num(3), B.name(s->body + ".mass")))}));
    }
    E scale = radii.empty() ? B.num(1) : radii.size() == 1 ? radii[0] : B.call("min", {radii[0], radii[1]});
    param(B, jn + ".scale", scale);
  }

  static E idx2(const Build& B, E m, int r, int c) {
    auto e = std::make_shared<AstExpr>();
    e->kind = AstExpr::Kind::Index;
    e->loc = B.loc();
    e->args = {std::move(m), B.num(r), B.num(c)};
    return e;
  }

  E attr_or(const Joint& j, const std::string& key, E fallback) const {
    auto it = j.attrs.find(key);
    return it == j.attrs.end() ? fallback : it->second->value;
  }

  /// The constraint rows g (each a scalar AST expression) of a joint.
  std::vector<E> rows(const Build& B, const Joint& j, const Frame& A, const Frame& Bf) {
    const std::string& t = j.decl->type;
    const std::string jn = j.decl->name;
    E d = B.op('-', Bf.p, A.p);
    E scale = B.name(jn + ".scale");
    auto perp = [&](E u, E v) { return B.op('*', scale, B.dot(u, v)); };
    std::vector<E> r;
    auto point = [&] { for (int k = 1; k <= 3; ++k) r.push_back(B.at(d, k)); };
    auto aligned = [&] { r.push_back(perp(A.Z, Bf.X)); r.push_back(perp(A.Z, Bf.Y)); };
    auto on_axis = [&] { r.push_back(B.dot(A.X, d)); r.push_back(B.dot(A.Y, d)); };
    if (t == "spherical") point();
    else if (t == "revolute") { point(); aligned(); }
    else if (t == "universal") {
      // The cross's arms are A's x and B's y: perpendicular when the joint
      // frames coincide (as the tree placement puts them), free to turn about
      // either arm; the twist about the shafts (the frames' z) is forbidden.
      point();
      r.push_back(perp(A.X, Bf.Y));
    }
    else if (t == "cylindrical") { on_axis(); aligned(); }
    else if (t == "prismatic") { on_axis(); aligned(); r.push_back(perp(A.X, Bf.Y)); }
    else if (t == "screw") {
      on_axis();
      aligned();
      // s = pitch * theta, written without atan2 (no wrap): pitch * sin(theta - s/pitch) = 0
      E h = B.name(jn + ".pitch");
      E phase = B.op('/', B.dot(A.Z, d), h);
      r.push_back(B.op('*', h, B.op('-', B.op('*', B.dot(A.Y, Bf.X), B.call("cos", {phase})),
                                           B.op('*', B.dot(A.X, Bf.X), B.call("sin", {phase})))));
    } else if (t == "planar") { r.push_back(B.dot(A.Z, d)); aligned(); }
    else if (t == "fixed") { point(); aligned(); r.push_back(perp(A.X, Bf.Y)); }
    else if (t == "distance") {
      E L = B.name(jn + ".length");
      r.push_back(B.op('/', B.op('-', B.dot(d, d), B.op('^', L, B.num(2))), B.op('*', B.num(2), L)));
    }
    if (auto m = j.attrs.find("motion"); m != j.attrs.end()) {
      E f = m->second->value;
      if (t == "prismatic") r.push_back(B.op('-', B.dot(A.Z, d), f));
      else  // scale * sin(theta - f(t)), again without atan2
        r.push_back(B.op('*', scale, B.op('-', B.op('*', B.dot(A.Y, Bf.X), B.call("cos", {f})),
                                              B.op('*', B.dot(A.X, Bf.X), B.call("sin", {f})))));
    }
    return r;
  }

  /// The rate of `rows` (a k-vector of position-level expressions) collected on
  /// 0-junction `sum`: one MTF per body junction, modulus d(rows)/d(position) times
  /// the map from the junction's flow to that position's rate.
  void rates_into(const Build& B, const std::string& prefix, E rows_vec, const Frame& f, const std::string& sum,
                  bool towards_sum, bool translational) {
    if (f.ground) return;
    const std::string& b = f.body;
    std::vector<std::pair<std::string, std::string>> parts;  // (MTF name, body junction)
    if (translational) {
      element(B, "MTF", prefix + "t", B.call("jacobian", {rows_vec, B.name(b + ".r.q")}));
      parts.push_back({prefix + "t", b + ".v"});
    }
    if (!f.particle) {
      element(B, "MTF", prefix + "r",
              B.op('*', B.call("jacobian", {rows_vec, B.name(b + ".q.q")}), B.call("quat_rate", {B.name(b + ".q.q")})));
      parts.push_back({prefix + "r", b + ".w"});
    }
    if (bodies_.at(b).beam) {  // the joint's point moves with the beam's deflection
      element(B, "MTF", prefix + "e", B.call("jacobian", {rows_vec, B.name(b + ".eta.q")}));
      parts.push_back({prefix + "e", b + ".etadot"});
    }
    for (const auto& [mtf, junc] : parts) {
      if (towards_sum) {
        bond(B, junc, mtf + ".p1");
        bond(B, mtf + ".p2", sum);
      } else {
        bond(B, sum, mtf + ".p2");
        bond(B, mtf + ".p1", junc);
      }
    }
  }

  void emit_joint(Joint& j) {
    const AstJoint& d = *j.decl;
    const std::string jn = d.name;
    Build B(d.loc);
    joint_params(B, j);
    if (d.type == "screw") param(B, jn + ".pitch", j.attrs.at("pitch")->value);
    if (d.type == "distance") param(B, jn + ".length", j.attrs.at("length")->value);
    Frame A = frame(B, j, j.a, "a");
    Frame Bf = frame(B, j, j.b, "b");
    frames_[jn] = {A, Bf};
    if (j.strategy == Strategy::Coordinates) {
      emit_coordinate_joint(B, j);
      return;
    }
    std::vector<E> g = rows(B, j, A, Bf);
    int k = static_cast<int>(g.size());
    E gvec = B.list(g);
    // constraint fragment: body junctions -> MTFs -> 0-junction -> CN
    junction(B, '0', jn + ".c", k, {}, {jn + ".cn"});
    rates_into(B, jn + ".ca", gvec, A, jn + ".c", true, true);
    rates_into(B, jn + ".cb", gvec, Bf, jn + ".c", true, true);
    std::vector<AstAttr> cn = {kv("g", gvec, d.loc)};
    if (j.strategy == Strategy::Penalty) {
      // Stiffness and damping from the lighter body: natural frequency 1000 rad/s, critically damped.
      std::vector<E> masses;
      for (const Frame* f : {&A, &Bf})
        if (!f->ground) masses.push_back(B.name(f->body + ".mass"));
      E m = masses.size() == 1 ? masses[0] : B.call("min", {masses[0], masses[1]});
      param(B, jn + ".stiffness", attr_or(j, "stiffness", B.op('*', m, B.num(1e6))));
      param(B, jn + ".damping", attr_or(j, "damping", B.op('*', B.num(2), B.call("sqrt", {B.op('*', m, B.name(jn + ".stiffness"))}))));
      cn.push_back(kv("stiffness", B.name(jn + ".stiffness"), d.loc));
      cn.push_back(kv("damping", B.name(jn + ".damping"), d.loc));
    }
    element(B, "CN", jn + ".cn", nullptr, cn);
    if (j.attrs.count("motion")) {
      // the prescribed motion's explicit time dependence enters the rate as a flow source
      element(B, "Sf", jn + ".motion", B.call("partial_t", {gvec}));
      bond(B, jn + ".motion", jn + ".c");
    }
    // drive port: a 1-junction whose flow is the joint coordinate's rate
    std::optional<E> coordinate = joint_coordinate(B, j, A, Bf);
    if (coordinate) {
      coordinates_[jn] = *coordinate;
      bool translational = d.type == "prismatic";
      junction(B, '1', jn + ".drive", 1, {}, {jn + ".dsum"});
      junction(B, '0', jn + ".dsum", 1, {}, {});
      E cvec = B.list({*coordinate});
      rates_into(B, jn + ".da", cvec, A, jn + ".dsum", false, translational);
      rates_into(B, jn + ".db", cvec, Bf, jn + ".dsum", false, translational);
      for (const char* key : {"torque", "force"}) {
        if (!j.attrs.count(key)) continue;
        element(B, "Se", jn + ".applied", j.attrs.at(key)->value);
        applied_.push_back(generated_.size() - 1);  // may read joint quantities (a torsion spring: -k * j.angle)
        bond(B, jn + ".applied", jn + ".drive");
      }
    }
  }

  // ---- 3b. joints in joint coordinates (constraints = coordinates) ----------------------
  /// The joint's free directions as independent rates (thesis §8.4, the
  /// minimal-variable form): per coordinate a 1-junction whose flow is a free
  /// rate source `Sf { rate0 }` (a state), with a zero-effort C integrating it
  /// into the coordinate. The child's velocity junctions get their flows from
  /// the parent's and these rates through MTFs summed on 0-junctions, so the
  /// child's inertias take derivative causality; reduce differentiates their
  /// momenta and solves the accelerations (a mass-matrix system) from the
  /// rate sources' zero-effort equations.
  void emit_coordinate_joint(const Build& B, const Joint& j) {
    const AstJoint& d = *j.decl;
    const std::string jn = d.name;
    const std::string& t = d.type;
    const bool fwd = j.a_is_parent;
    const std::string& parent = fwd ? j.a.body : j.b.body;
    const std::string& child = fwd ? j.b.body : j.a.body;
    const Body& P = bodies_.at(parent);
    E zero = B.num(0);
    const AstAttr* motion = j.attrs.count("motion") ? j.attrs.at("motion") : nullptr;
    // The relative motion of B's joint frame in A's: a translation d (A's
    // axes) and a rotation qrel. Each rate junction k adds W_k u_k to the
    // relative angular velocity and V_k u_k to the rate of d (A's axes).
    struct Rate { std::string junction; E value, rate, W, V; };
    std::vector<Rate> rates;
    rates.reserve(4);  // references returned by rate() stay valid (at most three rate junctions)
    auto rate = [&](const std::string& junction, const std::string& c, E q0, E rate0, bool prescribed) -> Rate& {
      Rate k{junction, nullptr, B.name(jn + "." + c + "_rate.f"), nullptr, nullptr};
      if (prescribed) {
        element(B, "Sf", jn + "." + c + "_rate", B.call("partial_t", {motion->value}));
        junction_(B, junction, {jn + "." + c + "_rate"});
        k.value = motion->value;
      } else {
        element(B, "Sf", jn + "." + c + "_rate", nullptr, {kv("rate0", rate0, d.loc)});
        element(B, "C", jn + "." + c, nullptr, {kv("e", zero, d.loc), kv("q0", q0, d.loc)});
        junction_(B, junction, {jn + "." + c + "_rate"}, {jn + "." + c});
        k.value = B.name(jn + "." + c + ".q");
      }
      rates.push_back(k);
      return rates.back();
    };
    E ex = B.vec(1, 0, 0), ey = B.vec(0, 1, 0), ez = B.vec(0, 0, 1);
    auto qaxis = [&](E axis, E angle) { return B.call("quat_axis_angle", {std::move(axis), std::move(angle)}); };
    auto qmul = [&](E x, E y) { return B.call("quat_mul", {std::move(x), std::move(y)}); };
    auto conj = [&](E x) { return B.call("quat_conj", {std::move(x)}); };
    E disp = B.vec(0, 0, 0);
    E qrel = B.list({B.num(1), B.num(0), B.num(0), B.num(0)});
    E angle = zero, angle_rate = zero, axial = zero, axial_rate = zero;  // J.angle, J.displacement
    if (t == "revolute" || t == "cylindrical" || t == "screw") {
      Rate& r = rate(jn + ".drive", "theta", attr_or(j, "q0", zero), attr_or(j, "rate0", zero), motion != nullptr);
      r.W = ez;
      angle = r.value, angle_rate = r.rate;
      qrel = qaxis(ez, angle);
      if (t == "screw") {
        E h = B.name(jn + ".pitch");
        r.V = B.op('*', h, ez);
        axial = B.op('*', h, angle), axial_rate = B.op('*', h, angle_rate);
        disp = B.op('*', ez, axial);
      }
    }
    if (t == "prismatic" || t == "cylindrical") {
      bool prismatic = t == "prismatic";
      Rate& r = prismatic ? rate(jn + ".drive", "s", attr_or(j, "q0", zero), attr_or(j, "rate0", zero), motion != nullptr)
                          : rate(jn + ".slide", "s", attr_or(j, "d0", zero), attr_or(j, "ddot0", zero), false);
      r.V = ez;
      axial = r.value, axial_rate = r.rate;
      disp = B.op('*', ez, axial);
    }
    if (t == "planar") {  // translation in A's x-y plane, rotation about its z
      Rate& x = rate(jn + ".xdot", "x", zero, zero, false);
      x.V = ex;
      Rate& y = rate(jn + ".ydot", "y", zero, zero, false);
      y.V = ey;
      Rate& r = rate(jn + ".turn", "theta", zero, zero, false);
      r.W = ez;
      disp = B.list({x.value, y.value, zero});
      qrel = qaxis(ez, r.value);
    }
    if (t == "universal") {  // about A's x (the cross's first arm), then about the turned y (B's y)
      Rate& a = rate(jn + ".alphadot", "alpha", zero, zero, false);
      a.W = ex;
      Rate& b = rate(jn + ".betadot", "beta", zero, zero, false);
      E qa = qaxis(ex, a.value);
      b.W = B.op('*', B.call("rotq", {qa}), ey);
      qrel = qmul(qa, qaxis(ey, b.value));
    }
    const Body& C = bodies_.at(child);
    if (t == "distance") {
      // the rod's direction: two angles as a universal joint's (about A's x,
      // then the turned y); the rod starts along A's z, the joint axis. B's
      // point moves by d = L R(alpha, beta) z; its rates are w x d.
      Rate& a = rate(jn + ".alphadot", "alpha", zero, zero, false);
      Rate& b = rate(jn + ".betadot", "beta", zero, zero, false);
      E qa = qaxis(ex, a.value);
      E arm_b = B.op('*', B.call("rotq", {qa}), ey);
      disp = B.op('*', B.op('*', B.call("rotq", {qmul(qa, qaxis(ey, b.value))}), ez), B.name(jn + ".length"));
      a.V = B.call("cross", {ex, disp});
      b.V = B.call("cross", {arm_b, disp});
    }
    if (t == "spherical" || (t == "distance" && !C.particle)) {
      // three rates: the relative angular velocity in B's joint frame,
      // integrated into the relative quaternion as a body's orientation is
      // (behind a distance rod the body turns freely as on a ball joint)
      const std::string spin = jn + ".spin";
      element(B, "Sf", jn + ".spin_rate", nullptr, {kv("rate0", B.vec(0, 0, 0), d.loc)});
      element(B, "C", jn + ".rot", nullptr,
              {kv("e", B.list({zero, zero, zero, zero}), d.loc),
               kv("q0", attr_or(j, "rot0", B.list({B.num(1), B.num(0), B.num(0), B.num(0)})), d.loc)});
      element(B, "MTF", jn + ".rotrate", B.call("quat_rate", {B.name(jn + ".rot.q")}));
      junction(B, '1', spin, 3, {jn + ".spin_rate"}, {jn + ".rotrate.p1"});
      bond(B, jn + ".rotrate.p2", jn + ".rot", 4);
      qrel = B.name(jn + ".rot.q");
      rates.push_back({spin, nullptr, B.name(jn + ".spin_rate.f"), B.call("rotq", {qrel}), nullptr});
    }
    for (const char* key : {"torque", "force"}) {
      if (!j.attrs.count(key)) continue;
      element(B, "Se", jn + ".applied", j.attrs.at(key)->value);
      applied_.push_back(generated_.size() - 1);
      bond(B, jn + ".applied", jn + ".drive");
    }
    // pose of the child as signals of the coordinates
    E Fa = B.name(jn + ".Fa");
    // A's point, moved by d; a particle's joint point is its position
    E pa = B.op('+', bodies_.at(j.a.body).particle ? B.vec(0, 0, 0) : B.name(jn + ".pa"), B.op('*', Fa, disp));
    E pb = bodies_.at(j.b.body).particle ? B.vec(0, 0, 0) : B.name(jn + ".pb");
    E fa = B.name(jn + ".fa"), fb = B.name(jn + ".fb");
    E qP = quaternion(B, parent), RP = rotation(B, parent);
    E qC = fwd ? qmul(qmul(qmul(qP, fa), qrel), conj(fb)) : qmul(qmul(qmul(qP, fb), conj(qrel)), conj(fa));
    if (!C.particle) {
      for (int k = 0; k < 4; ++k) signal(B, fmt::format("{}.pose.q{}", child, k + 1), B.at(qC, k + 1));
      E Rq = B.call("rotq", {quaternion(B, child)});
      for (int r = 1; r <= 3; ++r)
        for (int c = 1; c <= 3; ++c) signal(B, fmt::format("{}.pose.R{}{}", child, r, c), idx2(B, Rq, r, c));
    }
    E RC = rotation(B, child);
    E joint_point = B.op('+', position(B, parent), B.op('*', RP, fwd ? pa : pb));
    if (P.ground) joint_point = fwd ? pa : pb;  // ground points are absolute
    E rC = B.op('-', joint_point, B.op('*', RC, fwd ? pb : pa));
    for (int k = 0; k < 3; ++k) signal(B, fmt::format("{}.pose.r{}", child, k + 1), B.at(rC, k + 1));
    // velocities: child omega (body frame) and CoM velocity (world) as sums of MTF flows
    auto T = [&](E m) { return B.call("transpose", {std::move(m)}); };
    auto skew = [&](E x) { return B.call("skew", {std::move(x)}); };
    int fed = 0;
    auto feed = [&](const std::string& from, E modulus, const std::string& sum) {
      const std::string mtf = fmt::format("{}.m{}", jn, ++fed);
      element(B, "MTF", mtf, std::move(modulus));
      bond(B, from, mtf + ".p1");
      bond(B, mtf + ".p2", sum);
    };
    // (a particle has no angular-velocity junction: nothing turns it, nothing reads it)
    const std::string wsum = jn + ".wsum", vsum = jn + ".vsum";
    const bool parent_turns = !P.ground && !P.particle;
    E RCt_RP = B.op('*', T(RC), RP);
    if (!C.particle) {
      junction(B, '0', wsum, 3, {}, {});
      if (parent_turns) feed(parent + ".w", RCt_RP, wsum);
      for (const Rate& r : rates)
        if (r.W) feed(r.junction, fwd ? B.op('*', B.op('*', RCt_RP, Fa), r.W) : B.neg(B.op('*', Fa, r.W)), wsum);
    }
    junction(B, '0', vsum, 3, {}, {});
    if (!P.ground) feed(parent + ".v", B.call("eye", {B.num(3)}), vsum);
    if (parent_turns) feed(parent + ".w", B.neg(B.op('*', RP, skew(fwd ? pa : pb))), vsum);
    for (const Rate& r : rates)
      if (r.V) feed(r.junction, fwd ? B.op('*', B.op('*', RP, Fa), r.V) : B.neg(B.op('*', B.op('*', RC, Fa), r.V)), vsum);
    if (!C.particle) {
      feed(child + ".w", B.op('*', RC, skew(fwd ? pb : pa)), vsum);
      named_bond(B, jn + ".reaction_t", wsum, child + ".w");
    }
    named_bond(B, jn + ".reaction_f", vsum, child + ".v");
    coordinate_values_[jn] = {angle, angle_rate, axial, axial_rate};
  }

  /// A 1-junction with the given elements bonded into / out of it.
  void junction_(const Build& B, const std::string& name, std::vector<std::string> in, std::vector<std::string> out = {}) {
    junction(B, '1', name, 1, std::move(in), std::move(out));
  }
  void named_bond(const Build& B, const std::string& name, const std::string& from, const std::string& to) {
    bond(B, from, to);
    std::get<AstBond>(generated_.back()).name = name;
    generated_names_.insert(name);
  }

  std::optional<E> joint_coordinate(const Build& B, const Joint& j, const Frame& A, const Frame& Bf) {
    const std::string& t = j.decl->type;
    if (t == "prismatic") return B.dot(A.Z, B.op('-', Bf.p, A.p));
    if (has_rotation_coordinate(t)) return B.call("atan2", {B.dot(A.Y, Bf.X), B.dot(A.X, Bf.X)});
    return std::nullopt;
  }

  // ---- 4. initial conditions along a spanning tree from ground ----------------------------
  /// A spanning tree from ground, breadth first: each body is placed by the
  /// first joint that reaches it; the other joints close loops.
  void find_tree() {
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
        c.by_coordinates = j.strategy == Strategy::Coordinates;
        tree_order_.push_back(&j);
        queue.push_back(child);
      }
    }
  }

  /// The tree joints from `body` up to ground.
  std::vector<std::string> path_to_ground(std::string body) const {
    std::vector<std::string> path;
    while (body != "ground" && bodies_.at(body).placed) {
      const std::string& jn = bodies_.at(body).placed_by;
      path.push_back(jn);
      for (const Joint& j : joints_)
        if (j.decl->name == jn) body = j.a_is_parent ? j.a.body : j.b.body;
    }
    return path;
  }

  /// Joint coordinates need a tree without particles turned by joints, and constraint rows
  /// (a CN) need the position states that coordinate-driven bodies lack.
  void check_coordinates() {
    for (const Joint& j : joints_) {
      const AstJoint& d = *j.decl;
      if (j.strategy == Strategy::Coordinates && !j.tree) {
        std::vector<std::string> pa = path_to_ground(j.a.body), pb = path_to_ground(j.b.body);
        // the loop: both paths without their common part near ground
        while (!pa.empty() && !pb.empty() && pa.back() == pb.back()) pa.pop_back(), pb.pop_back();
        std::vector<std::string> loop(pa.begin(), pa.end());
        loop.insert(loop.end(), pb.rbegin(), pb.rend());
        diags_.error(d.loc, fmt::format("joint `{}` closes a kinematic loop, so its motion cannot be given by joint coordinates", d.name),
                     fmt::format("with constraints = coordinates the tree joints ({}) already set the flows of `{}` and `{}`; "
                                 "`{}` would impose a second, dependent flow on those junctions, a causal conflict no "
                                 "storage element can take. A closed loop needs constraint rows: write constraints = "
                                 "lagrange or penalty",
                                 fmt::join(loop, ", "), j.a.body, j.b.body, d.name));
        continue;
      }
      if (j.strategy == Strategy::Coordinates) {
        const Side* beam = bodies_.at(j.a.body).beam ? &j.a : bodies_.at(j.b.body).beam ? &j.b : nullptr;
        if (beam) {
          diags_.error(d.loc, fmt::format("joint `{}` joins the flexible body `{}` by joint coordinates, which is not implemented yet", d.name, beam->body),
                       "a beam's inertia field couples its frame and modal velocities; give this joint constraint rows: "
                       "constraint = lagrange or penalty (see README known limits)");
          continue;
        }
      }
      if (j.strategy == Strategy::Coordinates && d.type != "distance")
        for (const Side* s : {&j.a, &j.b})
          if (bodies_.at(s->body).particle) {
            diags_.error(d.loc, fmt::format("joint `{}` cannot move the particle `{}` by joint coordinates", d.name, s->body),
                         fmt::format("a particle has no angular-velocity junction for the joint's rotation rates to "
                                     "drive, so they would carry no inertia: give `{}` an inertia, or write "
                                     "constraints = lagrange or penalty for this model",
                                     s->body));
            break;
          }
      if (j.strategy != Strategy::Coordinates)
        for (const Side* s : {&j.a, &j.b})
          if (bodies_.at(s->body).by_coordinates) {
            diags_.error(d.loc, fmt::format("joint `{}` uses constraint rows, but `{}` moves by joint coordinates", d.name, s->body),
                         fmt::format("a constraintor CN acts through the rates of a body's position states, and `{}` has "
                                     "none (its pose is a function of joint `{}`'s coordinates): use one strategy for the "
                                     "whole model (constraints = lagrange, penalty or coordinates)",
                                     s->body, bodies_.at(s->body).placed_by));
            break;
          }
    }
  }

  void place_bodies() {
    // A body moved by joint coordinates has its pose as signals of them
    // (emit_coordinate_joint): no initial-pose parameters to compute.
    for (const Joint* j : tree_order_)
      if (j->strategy != Strategy::Coordinates) place(*j, j->a_is_parent);
    for (const std::string& n : body_order_) {
      Body& body = bodies_.at(n);
      const AstBody& d = *body.decl;
      Build B(d.loc);
      if (body.placed) {
        for (const char* key : {"r0", "quat0", "v0", "w0"})
          for (const AstAttr& a : d.attrs)
            if (a.key == key)
              diags_.error(a.loc, fmt::format("body `{}` is placed by joint `{}`, so `{}` cannot be given", n, body.placed_by, key),
                           placed_hint(body.placed_by));
        continue;
      }
      E r0 = attr(d, "r0"), v0 = attr(d, "v0");
      param(B, n + ".r0", r0 ? r0 : B.vec(0, 0, 0));
      param(B, n + ".v0", v0 ? v0 : B.vec(0, 0, 0));
      if (body.particle) continue;
      E q0 = attr(d, "quat0"), w0 = attr(d, "w0");
      param(B, n + ".q0", q0 ? q0 : B.list({B.num(1), B.num(0), B.num(0), B.num(0)}));
      param(B, n + ".w0", w0 ? w0 : B.vec(0, 0, 0));
    }
  }

  /// How to set the initial pose of a body that joint `jn` places.
  std::string placed_hint(const std::string& jn) const {
    const std::string* type = nullptr;
    for (const Joint& j : joints_)
      if (j.decl->name == jn) type = &j.decl->type;
    std::string coords;
    if (type) {
      if (*type == "revolute" || *type == "screw") coords = "q0 (angle) and rate0";
      else if (*type == "prismatic") coords = "q0 (displacement) and rate0";
      else if (*type == "cylindrical") coords = "q0, rate0 (rotation) and d0, ddot0 (sliding)";
      else if (*type == "spherical") coords = "rot0 (relative rotation)";
      else if (*type == "distance") coords = "axis (the direction of the rod from the first point)";
    }
    std::string start = fmt::format("the initial pose and velocity follow from the parent body along joint `{}`", jn);
    if (coords.empty()) return start + "; remove the setting, or join the body by another joint";
    return fmt::format("{}: give the joint's {} instead", start, coords);
  }

  /// Pose and velocity names of a placed side (ground: constants).
  struct Pose { E q, R, r, v, w; };
  Pose pose(const Build& B, const std::string& body) {
    const Body& b = bodies_.at(body);
    if (b.ground) return {B.list({B.num(1), B.num(0), B.num(0), B.num(0)}), B.call("eye", {B.num(3)}), B.vec(0, 0, 0), B.vec(0, 0, 0), B.vec(0, 0, 0)};
    E q = b.particle ? B.list({B.num(1), B.num(0), B.num(0), B.num(0)}) : B.name(body + ".q0");
    E w = b.particle ? B.vec(0, 0, 0) : B.name(body + ".w0");
    return {q, B.call("rotq", {q}), B.name(body + ".r0"), B.name(body + ".v0"), w};
  }

  /// Initial pose of the child of a tree joint from its parent and the joint coordinates.
  void place(const Joint& j, bool a_is_parent) {
    const std::string jn = j.decl->name;
    const std::string& t = j.decl->type;
    Build B(j.decl->loc);
    E zero = B.num(0);
    E angle = has_rotation_coordinate(t) ? attr_or(j, "q0", zero) : zero;
    E angle_rate = has_rotation_coordinate(t) ? attr_or(j, "rate0", zero) : zero;
    E axial = zero, axial_rate = zero;
    if (t == "prismatic") axial = attr_or(j, "q0", zero), axial_rate = attr_or(j, "rate0", zero);
    if (t == "cylindrical") axial = attr_or(j, "d0", zero), axial_rate = attr_or(j, "ddot0", zero);
    if (t == "distance") axial = B.name(jn + ".length");  // the rod starts along the joint axis
    if (t == "screw") {
      axial = B.op('*', B.name(jn + ".pitch"), angle);
      axial_rate = B.op('*', B.name(jn + ".pitch"), angle_rate);
    }
    E qrel = t == "spherical" ? attr_or(j, "rot0", B.list({B.num(1), B.num(0), B.num(0), B.num(0)}))
                              : B.call("quat_axis_angle", {B.vec(0, 0, 1), angle});
    E axis_a = B.name(jn + ".axis_a");
    E pa = B.op('+', B.name(jn + ".pa"), B.op('*', axis_a, axial));  // A's point, moved along the axis
    E pb = B.name(jn + ".pb");
    E fa = B.name(jn + ".fa"), fb = B.name(jn + ".fb");
    const std::string& child = a_is_parent ? j.b.body : j.a.body;
    const std::string& parent = a_is_parent ? j.a.body : j.b.body;
    const Body& cb = bodies_.at(child);
    Pose P = pose(B, parent);
    auto qmul = [&](E x, E y) { return B.call("quat_mul", {std::move(x), std::move(y)}); };
    auto conj = [&](E x) { return B.call("quat_conj", {std::move(x)}); };
    if (!cb.particle) {
      E q = a_is_parent ? qmul(qmul(qmul(P.q, fa), qrel), conj(fb)) : qmul(qmul(qmul(P.q, fb), conj(qrel)), conj(fa));
      param(B, child + ".q0", q);
    }
    Pose C = pose(B, child);
    auto cross = [&](E x, E y) { return B.call("cross", {std::move(x), std::move(y)}); };
    auto T = [&](E m) { return B.call("transpose", {std::move(m)}); };
    E rel_w = B.op('*', axis_a, angle_rate);   // in A's frame
    E rel_v = B.op('*', axis_a, axial_rate);   // in A's frame
    // Ground points are absolute: their "local" coordinates already are world positions.
    auto world_point = [&](const Pose& X, E local, bool ground) { return ground ? local : B.op('+', X.r, B.op('*', X.R, local)); };
    bool parent_ground = bodies_.at(parent).ground;
    if (a_is_parent) {
      E pa_world = world_point(P, pa, parent_ground);
      param(B, child + ".r0", B.op('-', pa_world, B.op('*', C.R, pb)));
      if (!cb.particle) param(B, child + ".w0", B.op('*', B.op('*', T(C.R), P.R), B.op('+', P.w, rel_w)));
      E v = B.op('+', B.op('+', P.v, B.op('*', P.R, cross(P.w, pa))), B.op('*', P.R, rel_v));
      param(B, child + ".v0", B.op('-', v, B.op('*', C.R, cross(C.w, pb))));
    } else {
      E pb_world = world_point(P, pb, parent_ground);
      param(B, child + ".r0", B.op('-', pb_world, B.op('*', C.R, pa)));
      if (!cb.particle) param(B, child + ".w0", B.op('-', B.op('*', B.op('*', T(C.R), P.R), P.w), rel_w));
      E v = B.op('+', P.v, B.op('*', P.R, cross(P.w, pb)));
      param(B, child + ".v0", B.op('-', B.op('-', v, B.op('*', C.R, cross(C.w, pa))), B.op('*', C.R, rel_v)));
    }
  }

  // ---- 5. quantities users may name ------------------------------------------------------
  // ---- 4. force elements ------------------------------------------------------------
  /// World position and velocity of a force element's point.
  std::pair<E, E> world_point(const Build& B, const Side& s) {
    const Body& body = bodies_.at(s.body);
    E local = s.point.empty() ? B.vec(0, 0, 0) : B.name(s.body + "." + s.point);
    if (body.ground) return {local, B.vec(0, 0, 0)};
    E r = position(B, s.body), v = B.name(s.body + ".v.f");
    if (body.particle) return {r, v};
    if (body.beam) {
      Eta eta = state_eta(B, s.body, *body.beam);
      return beam_point_motion(B, s.body, s.point.empty() ? B.vec(0, 0, 0) : beam_point(B, s.body, *body.beam, s.point, eta));
    }
    E R = rotation(B, s.body);
    E arm = B.op('-', local, B.name(s.body + ".com"));
    return {B.op('+', r, B.op('*', R, arm)), B.op('+', v, B.op('*', R, B.call("cross", {B.name(s.body + ".w.f"), arm})))};
  }

  /// The load on b (world force F at Q, torque T) and its opposite on a, as
  /// effort sources on the bodies' junctions: F on the centre-of-mass
  /// velocity junction, the body-frame moment arm x (R^T F) + R^T T on the
  /// angular-velocity one. A spring-damper acts along the line P -> Q.
  /// World position and velocity of a beam's point at `local` (body axes,
  /// deflected): it moves with the frame and, through the modes, on it.
  std::pair<E, E> beam_point_motion(const Build& B, const std::string& n, E local) const {
    E R = rotation(B, n);
    E rate = B.op('+', B.call("cross", {B.name(n + ".w.f"), local}),
                  B.op('*', B.call("jacobian", {local, B.name(n + ".eta.q")}), B.name(n + ".etadot.f")));
    return {B.op('+', position(B, n), B.op('*', R, local)), B.op('+', B.name(n + ".v.f"), B.op('*', R, rate))};
  }

  /// A force F (and torque T), world axes, at a beam's point as an effort on
  /// its junction nu = [V; omega; eta']: the power F.v_P + T.w_P written in
  /// nu, i.e. [R'F; P x R'F + R'T; (dP/deta)' R'F + (dtheta/deta)' R'T].
  E beam_load(const Build& B, const std::string& n, const std::string& point, E force, E torque) {
    const Beam& beam = *bodies_.at(n).beam;
    Eta eta = state_eta(B, n, beam);
    E at = point.empty() ? B.vec(0, 0, 0) : beam_point(B, n, beam, point, eta);
    E Rt = B.call("transpose", {rotation(B, n)}), F = B.op('*', Rt, force), q = B.name(n + ".eta.q");
    E moment = B.call("cross", {at, F});
    E modal = B.op('*', B.call("transpose", {B.call("jacobian", {at, q})}), F);
    if (torque) {
      E T = B.op('*', Rt, torque);
      moment = B.op('+', moment, T);
      if (!point.empty())
        modal = B.op('+', modal, B.op('*', B.call("transpose", {B.call("jacobian", {beam_slope(B, n, beam, point, eta), q})}), T));
    }
    return B.call("vcat", {F, moment, modal});
  }

  void emit_force(const ForceElement& f) {
    const std::string& fn = f.decl->name;
    Build B(f.decl->loc);
    auto user = [&](const char* key) -> E {
      auto it = f.attrs.find(key);
      return it == f.attrs.end() ? nullptr : rewrite_expr(it->second->value);
    };
    auto [pa, va] = world_point(B, f.a);
    auto [pb, vb] = world_point(B, f.b);
    E d = B.op('-', pb, pa);
    quantity_[fn + ".length"] = B.call("norm", {d});
    E force = user("force");
    if (E k = user("stiffness"), c = user("damping"); k || c) {
      if (k) param(B, fn + ".stiffness", k);
      if (c) param(B, fn + ".damping", c);
      if (E l0 = user("length")) param(B, fn + ".length0", l0);
      E len = B.call("norm", {d}), u = B.op('/', d, len);
      E tension = B.num(0);
      if (k) tension = B.op('*', B.name(fn + ".stiffness"), B.op('-', len, B.name(fn + ".length0")));
      if (c) tension = B.op('+', tension, B.op('*', B.name(fn + ".damping"), B.dot(u, B.op('-', vb, va))));
      E spring = B.neg(B.op('*', tension, u));
      force = force ? B.op('+', force, spring) : spring;
    }
    if (!force) force = B.vec(0, 0, 0);
    E torque = user("torque");
    quantity_[fn + ".force"] = force;
    if (torque) quantity_[fn + ".torque"] = torque;
    for (const auto& [s, sign] : {std::pair{&f.a, -1.0}, std::pair{&f.b, 1.0}}) {
      const Body& body = bodies_.at(s->body);
      if (body.ground) continue;
      const std::string base = fn + ".on_" + s->body;
      auto signed_ = [&](E e) { return sign < 0 ? B.neg(e) : e; };
      if (body.beam) {
        element(B, "Se", base, signed_(beam_load(B, s->body, s->point, force, torque)));
        continue;
      }
      element(B, "Se", base + "_f", signed_(force));
      if (body.particle) continue;
      E Rt = B.call("transpose", {rotation(B, s->body)});
      E local = s->point.empty() ? B.vec(0, 0, 0) : B.name(s->body + "." + s->point);
      E arm = B.op('-', local, B.name(s->body + ".com"));
      E moment = B.call("cross", {arm, B.op('*', Rt, force)});
      if (torque) moment = B.op('+', moment, B.op('*', Rt, torque));
      element(B, "Se", base + "_t", signed_(moment));
    }
  }

  void define_quantities() {
    for (const std::string& n : body_order_) {
      const Body& body = bodies_.at(n);
      Build B(body.decl->loc);
      if (body.beam) {
        beam_quantities(B, body);
        continue;
      }
      E r = position(B, n), v = B.name(n + ".v.f");
      quantity_[n + ".position"] = r;
      quantity_[n + ".velocity"] = v;
      quantity_[n + ".momentum"] = B.name(n + ".m.p");
      E ke = B.op('*', B.num(0.5), B.dot(v, B.name(n + ".m.p")));
      if (!body.particle) {
        E q = quaternion(B, n), R = rotation(B, n), w = B.name(n + ".w.f");
        quantity_[n + ".quaternion"] = q;
        quantity_[n + ".rotation"] = R;
        quantity_[n + ".bryant"] = B.call("bryant", {q});
        quantity_[n + ".omega"] = w;
        quantity_[n + ".omega_world"] = B.op('*', R, w);
        quantity_[n + ".angular_momentum"] = B.op('*', R, B.name(n + ".J.p"));
        ke = B.op('+', ke, B.op('*', B.num(0.5), B.dot(w, B.name(n + ".J.p"))));
        for (const auto& [p, x] : body.points) {
          E local = B.op('-', B.name(n + "." + p), B.name(n + ".com"));
          quantity_[n + "." + p + ".position"] = B.op('+', r, B.op('*', R, local));
          quantity_[n + "." + p + ".velocity"] = B.op('+', v, B.op('*', R, B.call("cross", {w, local})));
        }
      }
      quantity_[n + ".kinetic_energy"] = ke;
      quantity_[n + ".potential_energy"] =
          gravity_ ? B.neg(B.op('*', B.name(n + ".mass"), B.dot(B.name("gravity"), r))) : B.num(0);
    }
    for (const Joint& j : joints_) {
      const std::string jn = j.decl->name;
      Build B(j.decl->loc);
      const auto& [A, Bf] = frames_.at(jn);
      const Frame& body_side = Bf.ground ? A : Bf;
      quantity_[jn + ".violation"] = B.list(rows(B, j, A, Bf));
      if (auto cv = coordinate_values_.find(jn); cv != coordinate_values_.end()) {
        // joint coordinates: the reaction is the effort on the bonds into the
        // child's junctions (force world, torque body frame); on b, by Newton's third law
        const std::string child = j.a_is_parent ? j.b.body : j.a.body;
        E sign = B.num(j.a_is_parent ? 1 : -1);
        const std::string& t = j.decl->type;
        quantity_[jn + ".force"] = B.op('*', sign, B.name(jn + ".reaction_f.e"));
        if (!bodies_.at(child).particle)
          quantity_[jn + ".torque"] = B.op('*', sign, B.op('*', rotation(B, child), B.name(jn + ".reaction_t.e")));
        if (t == "distance") quantity_[jn + ".displacement"] = B.name(jn + ".length");
        if (has_rotation_coordinate(t)) {
          quantity_[jn + ".angle"] = cv->second.angle;
          quantity_[jn + ".rate"] = cv->second.rate;
        }
        if (has_axial_coordinate(t)) quantity_[jn + ".displacement"] = cv->second.displacement;
        continue;
      }
      // reaction on the second body (on the first, negated, if the second is ground)
      std::string side = Bf.ground ? "ca" : "cb";
      E force = Bf.ground ? B.name(jn + "." + side + "t.e1") : B.neg(B.name(jn + "." + side + "t.e1"));
      if (body_side.particle) {
        quantity_[jn + ".force"] = force;
      } else {
        E torque_body = Bf.ground ? B.name(jn + "." + side + "r.e1") : B.neg(B.name(jn + "." + side + "r.e1"));
        E lever = B.op('*', body_side.R, body_side.local);
        quantity_[jn + ".force"] = force;
        quantity_[jn + ".torque"] = B.op('-', B.op('*', body_side.R, torque_body), B.call("cross", {lever, force}));
      }
      quantity_[jn + ".violation"] = B.list(rows(B, j, A, Bf));
      const std::string& t = j.decl->type;
      E wrel = B.op('-', Bf.ground || Bf.particle ? B.vec(0, 0, 0) : B.op('*', Bf.R, B.name(Bf.body + ".w.f")),
                    A.ground || A.particle ? B.vec(0, 0, 0) : B.op('*', A.R, B.name(A.body + ".w.f")));
      if (has_rotation_coordinate(t)) {
        quantity_[jn + ".angle"] = B.call("atan2", {B.dot(A.Y, Bf.X), B.dot(A.X, Bf.X)});
        quantity_[jn + ".rate"] = B.dot(A.Z, wrel);
      }
      if (has_axial_coordinate(t) || t == "distance") {
        E dvec = B.op('-', Bf.p, A.p);
        quantity_[jn + ".displacement"] = t == "distance" ? B.call("norm", {dvec}) : B.dot(A.Z, dvec);
      }
    }
  }

  /// A beam's quantities: those of a rigid body, for its frame origin (x = 0),
  /// plus its modal coordinates, elastic energy and the deflection of its points.
  void beam_quantities(const Build& B, const Body& body) {
    const std::string& n = body.decl->name;
    const Beam& beam = *body.beam;
    Eta eta = state_eta(B, n, beam);
    E r = position(B, n), v = B.name(n + ".v.f"), q = quaternion(B, n), R = rotation(B, n), w = B.name(n + ".w.f");
    E p = B.name(n + ".M.p");
    auto part = [&](E x, int from) { return B.list({B.at(x, from), B.at(x, from + 1), B.at(x, from + 2)}); };
    quantity_[n + ".position"] = r;
    quantity_[n + ".velocity"] = v;
    quantity_[n + ".momentum"] = B.op('*', R, part(p, 1));
    quantity_[n + ".quaternion"] = q;
    quantity_[n + ".rotation"] = R;
    quantity_[n + ".bryant"] = B.call("bryant", {q});
    quantity_[n + ".omega"] = w;
    quantity_[n + ".omega_world"] = B.op('*', R, w);
    quantity_[n + ".angular_momentum"] = B.op('*', R, part(p, 4));  // about the frame origin
    quantity_[n + ".modes"] = B.name(n + ".eta.q");
    quantity_[n + ".kinetic_energy"] = B.op('*', B.num(0.5), B.dot(B.name(n + ".nu.f"), p));
    E elastic = B.op('*', B.num(0.5), B.dot(B.name(n + ".eta.q"), B.name(n + ".eta.e")));
    quantity_[n + ".elastic_energy"] = elastic;
    E gravity = gravity_ ? B.neg(B.dot(B.name("gravity"), B.op('+', B.op('*', B.name(n + ".mass"), r),
                                                                 B.op('*', R, first_moment(B, n, beam, eta)))))
                         : B.num(0);
    quantity_[n + ".potential_energy"] = B.op('+', gravity, elastic);
    for (const auto& [pt, at] : beam.points()) {
      E local = beam_point(B, n, beam, pt, eta);
      std::tie(quantity_[n + "." + pt + ".position"], quantity_[n + "." + pt + ".velocity"]) = beam_point_motion(B, n, local);
      quantity_[n + "." + pt + ".deflection"] = B.op('-', local, B.vec(at[0], at[1], at[2]));  // body axes
      quantity_[n + "." + pt + ".rotation_vector"] = beam_slope(B, n, beam, pt, eta);            // small, body axes
    }
  }

  /// `bob.positon`: a name under a body or joint that is none of its quantities,
  /// points or generated parts is a typo; say what the body or joint offers.
  void check_known(const AstExpr& e) {
    std::size_t dot = e.name.find('.');
    if (dot == std::string::npos) return;
    const std::string owner = e.name.substr(0, dot);
    const bool is_body = owner != "ground" && bodies_.count(owner);
    const bool is_joint = frames_.count(owner) > 0;
    if (!is_body && !is_joint) return;
    if (generated_names_.count(e.name)) return;
    if (std::size_t last = e.name.rfind('.'); last != dot && generated_names_.count(e.name.substr(0, last))) return;
    std::vector<std::string> offered;
    for (const auto& [q, x] : quantity_)
      if (q.compare(0, owner.size() + 1, owner + ".") == 0) offered.push_back(q.substr(owner.size() + 1));
    if (is_body)
      for (const auto& [p, x] : bodies_.at(owner).points) offered.push_back(p);
    std::string rest = e.name.substr(dot + 1);
    std::string near = closest_name(rest, offered);
    diags_.error(e.loc, fmt::format("{} `{}` has no quantity `{}`", is_body ? "body" : "joint", owner, rest),
                 near.empty() ? fmt::format("`{}` offers {}", owner, fmt::join(offered, ", "))
                              : fmt::format("did you mean `{}.{}`?", owner, near));
  }

  E rewrite_expr(const E& e) {
    if (!e) return e;
    if (e->kind == AstExpr::Kind::Name) {
      auto it = quantity_.find(e->name);
      if (it != quantity_.end()) return it->second;
      check_known(*e);
      return e;
    }
    bool changed = false;
    std::vector<E> args;
    for (const E& a : e->args) {
      args.push_back(rewrite_expr(a));
      changed |= args.back() != a;
    }
    if (!changed) return e;
    auto copy = std::make_shared<AstExpr>(*e);
    copy->args = std::move(args);
    return copy;
  }

  AstStmt rewrite_user(const AstStmt& s) {
    AstStmt out = s;
    std::visit(
        [&](auto& st) {
          using T = std::decay_t<decltype(st)>;
          if constexpr (std::is_same_v<T, AstSignal> || std::is_same_v<T, AstOutput>) {
            st.value = rewrite_expr(st.value);
          } else if constexpr (std::is_same_v<T, AstElement>) {
            st.value = rewrite_expr(st.value);
            for (AstAttr& a : st.attrs) a.value = rewrite_expr(a.value);
          }
        },
        out);
    return out;
  }

  ir::SourceManager& sources_;                // modal-data files join it (diagnostics, depfile)
  Diagnostics& diags_;
  std::vector<std::string> search_dirs_;     // mbgc -I: where modal-data files are looked for
  std::map<std::string, Body> bodies_;
  std::vector<std::string> body_order_;
  std::vector<Joint> joints_;
  std::vector<ForceElement> forces_;
  std::map<std::string, std::vector<std::string>> loads_;  // body -> force elements acting on it
  std::map<std::string, std::pair<Frame, Frame>> frames_;
  std::map<std::string, E> coordinates_;
  struct CoordinateValues { E angle, rate, displacement, displacement_rate; };
  std::map<std::string, CoordinateValues> coordinate_values_;  // coordinates joints
  std::vector<const Joint*> tree_order_;                        // tree joints, breadth first from ground
  std::map<std::string, E> quantity_;
  std::map<std::string, E> params_;                // the program's top-level parameters
  std::map<std::string, SourceLoc> point_locs_;    // "body.point" -> declaration
  std::map<std::string, SourceLoc> instances_;     // component instances (their parts are named `instance.part`)
  std::set<std::string> repeated_;                 // names reported as declared in every loop iteration
  std::set<std::string> generated_names_;          // parameters, elements and junctions expand wrote
  std::vector<std::size_t> applied_;               // generated_ indices of joint drive loads (user expressions)
  E gravity_;
  SourceLoc gravity_loc_;
  std::optional<Strategy> override_;  // mbgc --constraints
  Strategy strategy_;                  // the model-level strategy
  std::vector<AstStmt> generated_;
};

}  // namespace

AstProgram expand(const AstProgram& program, ir::SourceManager& sources, Diagnostics& diags, const ExpandOptions& options) {
  Expander x(sources, diags, options);
  return x.run(program);
}

}  // namespace mbgc::multibody
