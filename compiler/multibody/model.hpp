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
#include "multibody/build.hpp"
#include "multibody/expand.hpp"

namespace mbgc::multibody::detail {

class JointKind;

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
  const ir::AstBody* decl = nullptr;
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
  const ir::AstJoint* decl = nullptr;
  const JointKind* kind = nullptr;  // its type (joint_kind.hpp)
  Side a, b;
  std::map<std::string, const ir::AstAttr*> attrs;
  Strategy strategy = Strategy::Lagrange;
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

/// A joint's setting `key`, or `fallback`.
inline E setting_or(const Joint& j, const std::string& key, E fallback) {
  auto it = j.attrs.find(key);
  return it == j.attrs.end() ? fallback : it->second->value;
}

/// The modal coordinates of a flexible body, split by plane and kind, as expressions.
struct Eta { std::vector<E> y, z, axial, torsion; };

/// World-frame expressions of one side of a joint.
struct Frame {
  bool ground = false, particle = false;
  std::string body;
  E R;         // rotation body -> world (eye(3) for ground and particles)
  E p;         // joint point, world
  E local;     // joint point, body frame relative to the reference point (a beam's: deflected)
  E X, Y, Z;   // joint-frame axes, world
};

/// Pose and velocity of a placed body at the start (ground: constants).
struct Pose { E q, R, r, v, w; };

}  // namespace mbgc::multibody::detail
