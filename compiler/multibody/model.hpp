// multibody/model.hpp — what the multibody layer collects from a model before
// it writes any bond graph: bodies (rigid, particle, beam, modal), the sides
// of joints and force elements, and the world-frame expressions of a joint's
// two frames.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flex/beam_modes.hpp"
#include "flex/modal_file.hpp"
#include "flex/rod_modes.hpp"
#include "ir/ast.hpp"
#include "multibody/settings.hpp"
#include "multibody/body_kind.hpp"
#include "multibody/build.hpp"
#include "multibody/deformation.hpp"
#include "multibody/expand.hpp"

namespace mbgc::multibody::detail {

class JointKind;

struct Body {
  const ir::AstBody* decl = nullptr;
  BodyKind kind = Rigid{};               // ground, a particle (no inertia), rigid, or flexible (its field)
  std::map<std::string, ir::AstExprPtr> points;  // name -> body-frame coordinates, as written (ground: inertial)
  bool placed = false;                   // initial pose known (ground, or from a tree joint)
  std::string placed_by;                 // joint that placed it
  bool by_coordinates = false;           // its pose is a function of joint coordinates (no states of its own)
  std::string tree_parent;               // by_coordinates: its parent body in the tree ("" for ground)
  bool points_unknown = false;           // a modal body whose file could not be read (its error is out already)
  std::shared_ptr<ir::Drawing> shape;    // its `shape` setting (null: drawn by default, multibody/drawing.cpp)
  std::string rotor_joint;               // a rotor (rotors.hpp): its tree joint, whose turn its frame leaves out; else ""
};

struct Side {
  std::string body;   // "ground" or a body name
  std::string point;  // may be empty (the frame origin)
};

struct Joint {
  const ir::AstJoint* decl = nullptr;
  const JointKind* kind = nullptr;  // its type (joint_kind.hpp)
  Side a, b;
  std::map<std::string, const ir::AstAttr*> attrs;
  Strategy strategy = Strategy::Auto;
  bool tree = false;       // places its child (a spanning-tree joint from ground)
  bool a_is_parent = true; // tree joints: which side is the parent
};

/// `force NAME(a.P, b.Q) { force; torque; stiffness; damping; length }`: equal
/// and opposite loads on two body points (a = ground: an applied load).
struct ForceElement {
  const ir::AstJoint* decl = nullptr;  // parsed as a joint of type "force"
  Side a, b;
  std::map<std::string, const ir::AstAttr*> attrs;
};

/// `contact NAME(a.P, b.Q) { radius; surface; normal | axis | vertices; surface_radius;
/// strategy; restitution; stiffness; exponent; friction; slip_speed;
/// stabilisation }`: a sphere of `radius` around point P of body a touching a
/// surface through point Q of body b (a plane, a sphere, a cylinder, or a
/// convex polygon in b's x-z plane extruded along its y axis). The gap
/// between them is a position-level function; the normal force acts only
/// while it is closed (see docs/notes/contact.md).
enum class Surface { Plane, Sphere, Cylinder, Polygon };
struct Contact {
  const ir::AstJoint* decl = nullptr;
  Side a, b;
  Surface surface = Surface::Plane;
  ContactStrategy strategy = ContactStrategy::Unilateral;
  std::map<std::string, const ir::AstAttr*> attrs;
};

/// `tyre NAME(wheel.centre, ground) { axis; profile; FNOMIN; ...; PTY2 }`:
/// Magic Formula road loads on a rigid wheel (tyres.cpp, docs/notes/tyre.md).
struct Tyre {
  const ir::AstJoint* decl = nullptr;
  Side wheel;
  std::map<std::string, const ir::AstAttr*> attrs;
};

/// A body's setting `s` as written (null: not given).
inline ir::AstExprPtr attr(const ir::AstBody& b, const Setting& s) {
  for (const ir::AstAttr& a : b.attrs)
    if (a.key == s.name) return a.value;
  return nullptr;
}

/// A body's setting `s` as a term to write (null: not given).
inline E body_term(const ir::AstBody& b, const Setting& s) { return term(attr(b, s)); }

/// A joint's setting `s` as given (null: not given).
inline const ir::AstAttr* given_attr(const Joint& j, const Setting& s) { return given_in(j.attrs, s); }
/// Whether a joint's setting `s` is given.
inline bool given(const Joint& j, const Setting& s) { return given_attr(j, s) != nullptr; }
/// A joint's setting `s`, or `fallback`.
inline E setting_or(const Joint& j, const Setting& s, E fallback) {
  const ir::AstAttr* at = given_attr(j, s);
  return at ? term(at->value) : fallback;
}
/// A joint's setting `s`, or its default.
inline E setting_or_default(const Joint& j, const Setting& s, const Build& B) {
  const ir::AstAttr* at = given_attr(j, s);
  return at ? term(at->value) : B.default_of(s);
}


/// World-frame expressions of one side of a joint.
struct Frame {
  BodyKind kind = Rigid{};  // its body's
  std::string body;
  E R;         // rotation body -> world (eye(3) for ground and particles)
  E p;         // joint point, world
  E local;     // joint point, body frame relative to the reference point (a beam's: deflected)
  E X, Y, Z;   // joint-frame axes, world
};

/// What the collect pass (collect.hpp) reads of a model, checked: the input
/// of the passes that write its bond graph.
struct Model {
  std::map<std::string, Body> bodies;          // by name, ground among them
  std::vector<std::string> body_order;         // as declared (ground not among them)
  std::vector<Joint> joints;
  std::vector<ForceElement> forces;
  std::vector<Contact> contacts;
  std::vector<Tyre> tyres;
  std::map<std::string, std::vector<LoadSym>> loads;  // body -> what pushes on it (force elements, friction, tyres)
  std::map<std::string, ir::AstExprPtr> params;  // the program's top-level parameters, as written
  ir::AstExprPtr gravity;                      // `gravity = [...]` as written (null: none)
  ir::SourceLoc gravity_loc;
  std::vector<const Joint*> tree_order;        // the spanning tree's joints, breadth first from ground (spanning_tree.hpp)
};

/// Pose and velocity of a placed body at the start (ground: constants).
struct Pose { E q, R, r, v, w; };

}  // namespace mbgc::multibody::detail
