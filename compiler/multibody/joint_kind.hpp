// multibody/joint_kind.hpp — the whole surface of one joint type.
//
// A joint kind (revolute, prismatic, spherical, ...; one file each under
// joints/) says, for the two joint frames F on the first body A and M on the
// second body B:
//
//   settings()       what it takes besides axis, axis_a, axis_b, constraint,
//                    stiffness and damping; which of them are required;
//   rows()           its holonomic constraint rows g(X_WF, X_WM) = 0, written
//                    with the frames' world-frame expressions (thesis §7.2):
//                    what the `lagrange` and `penalty` strategies enforce;
//   mobilize()       its relative pose X_FM(q) and velocity directions: per
//                    joint coordinate a rate u_k with W_k u_k added to M's
//                    angular velocity in F and V_k u_k to the rate of M's
//                    origin in F (Drake's H_FM(q) column by column): what the
//                    `coordinates` strategy builds the tree from;
//   initial()        the relative motion its settings give at the start
//                    (q0, rate0, d0, rot0, ...), placing the child body;
//   has_angle(),     the coordinates users may read (`j.angle`, `j.rate`,
//   has_axial()      `j.displacement`) and a drive may act on.
//
// The strategies (joint_rows.cpp, joint_coordinates.cpp) and the tree
// (tree.cpp) are written once over this interface. Adding a joint type is a
// new file under joints/ and one line in joint_kind.cpp's registry.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ir/ast.hpp"
#include "multibody/settings.hpp"
#include "ir/diagnostics.hpp"
#include "multibody/build.hpp"
#include "multibody/joint_symbols.hpp"
#include "multibody/model.hpp"

namespace mbgc::multibody::detail {

/// A joint's two frames in world axes, and the row shapes every kind is built from.
struct JointFrames {
  const Build& B;
  const Joint& joint;
  const Frame& A;   // the first body's joint frame
  const Frame& Bf;  // the second body's
  E d;              // Bf.p - A.p: from A's joint point to B's
  E scale;          // `j.scale`: turns dot products of axes into metres

  /// The joint's names.
  JointSym sym() const { return JointSym(joint.decl->name); }
  /// scale * u . v: zero when u and v are perpendicular.
  E perp(const E& u, const E& v) const;
  /// The joint points coincide (3 rows).
  void point(std::vector<E>& r) const;
  /// B's joint z axis stays along A's (2 rows).
  void aligned(std::vector<E>& r) const;
  /// B's joint point stays on A's z axis (2 rows).
  void on_axis(std::vector<E>& r) const;
  /// sin(theta - angle) written without atan2 (no wrap), theta the rotation of
  /// B's x about A's z: (A.Y . B.X) cos(angle) - (A.X . B.X) sin(angle).
  E turned_by(const E& angle) const;
};

/// What a kind's mobilize() builds for the `coordinates` strategy. The
/// strategy supplies rate(): per joint coordinate a 1-junction whose flow is
/// a free rate source `Sf { rate0 }` (a state) integrated by a zero-effort C
/// into the coordinate, or, prescribed, the motion's time derivative.
class Mobilizer {
 public:
  struct Rate {
    Sym junction;          // the 1-junction carrying the rate
    E value;               // the coordinate (or the prescribed motion f(t))
    E rate;                // its rate
    E W, V;                // angular and linear velocity per unit rate, A's joint axes (null: none)
    E Wb;                  // W in B's joint axes, R^T W, where the kind knows it simply (null: R^T W is formed)
    E Vb;                  // V in B's joint axes, R^T V, likewise
  };
  Mobilizer(const Build& b, const Joint& j, bool child_particle);
  virtual ~Mobilizer() = default;

  /// A scalar coordinate `c` (JointSym::coordinate) with its rate on
  /// 1-junction `junction`, starting at q0 with rate rate0; `prescribed`:
  /// driven by the joint's motion = f(t).
  virtual Rate& rate(const Sym& junction, const std::string& c, E q0, E rate0, bool prescribed) = 0;
  /// Three rates: the relative angular velocity in B's joint frame,
  /// integrated into a relative quaternion (a ball joint); sets qrel.
  virtual void ball() = 0;
  /// Three rates: the velocity of B's joint point in B's joint axes, turned
  /// into A's by the relative rotation and integrated into the translation
  /// (a free joint's: a floating body's velocity in its own axes, as its
  /// momentum is, so that no rotation enters its inertia); sets disp. After
  /// ball(), whose rotation it needs; r0 and v0 in A's joint axes.
  virtual void float_in_child_axes(E r0, E v0) = 0;

  /// The joint's setting `key`, or `fallback`.
  E setting_or(const Setting& s, E fallback) const;
  /// The joint's setting `s`, or its default.
  E setting_or_default(const Setting& s) const;
  bool prescribed() const;  // the joint has motion = f(t)

  const Build& B;
  const Joint& joint;
  const JointSym sym;         // the joint's names
  const bool child_particle;  // the child body has no orientation
  bool child_carries = false;  // other bodies hang from the child (it is the base of a subtree)
  E zero, ex, ey, ez;
  // The relative pose of B's joint frame in A's: the translation disp (A's
  // axes) and the rotation qrel; and the coordinates users read. Kinds that
  // turn about fixed axes also give the rotation's matrix `rot` directly
  // (rot_axis_angle: no half angles, no normalisation); else it is rotq(qrel).
  E disp, qrel, rot;
  // The rotation is free (a ball joint): any frame on A serves as reference,
  // so a flexible parent's section turn need not enter it.
  bool free_rotation = false;
  E angle, angle_rate, axial, axial_rate;
};

/// The relative motion of a tree joint at the start, from its settings.
struct InitialMotion {
  E angle, angle_rate;  // about A's joint z
  E axial, axial_rate;  // along A's joint z
  E qrel;               // rotation of B's joint frame in A's
  E w_rel;              // the relative angular velocity in B's joint axes, when not about the axis (null: angle_rate)
  E v_rel;              // the relative velocity of B's point in A's joint axes, when not along the axis (null: axial_rate)
};

class JointKind {
 public:
  virtual ~JointKind() = default;
  virtual std::string_view name() const = 0;
  /// Settings besides the common ones, in the order diagnostics list them.
  virtual std::vector<const Setting*> settings() const { return {}; }
  /// Settings without a default.
  virtual std::vector<const Setting*> required() const { return {}; }
  /// A rotation coordinate about the joint axis (`j.angle`, `j.rate`, torque, motion).
  virtual bool has_angle() const { return false; }
  /// A translation along the joint axis (`j.displacement`).
  virtual bool has_axial() const { return false; }
  /// `j.displacement` exists (the axial coordinate, or a rod's length).
  virtual bool has_displacement() const { return has_axial(); }
  /// The drive acts along the axis (a force), not about it (a torque).
  bool drives_along_axis() const { return has_axial() && !has_angle(); }
  /// Its rows turn with the bodies' orientations (no particles).
  virtual bool needs_orientation() const { return true; }
  /// In joint coordinates it may move a particle (a distance rod).
  virtual bool moves_particles() const { return false; }
  /// How to set the child's initial pose through the joint (a diagnostic's hint); empty: no way.
  virtual std::string initial_settings() const { return {}; }

  /// The components (1-based) of a 3-vector setting that must be 0: an
  /// initial rate about or along a direction the joint does not move in.
  virtual std::vector<int> fixed_components(std::string_view /*key*/) const { return {}; }
  /// Reports a constant setting that makes the joint degenerate.
  virtual void check_constant(const ir::AstJoint& /*joint*/, const ir::AstAttr& /*setting*/, double /*value*/,
                              ir::Diagnostics& /*diags*/) const {}
  /// Writes the kind's own parameters (a screw's pitch, a rod's length).
  virtual void params(const Joint& /*joint*/, const std::function<void(const Sym&, E)>& /*param*/) const {}

  /// The constraint rows g = 0, appended to `rows`.
  virtual void rows(const JointFrames& f, std::vector<E>& rows) const = 0;
  /// `j.displacement` measured from the frames (rows strategy).
  virtual E displacement(const JointFrames& f) const;
  /// The relative motion in joint coordinates.
  virtual void mobilize(Mobilizer& m) const = 0;
  /// The relative motion at the start.
  virtual InitialMotion initial(const Build& B, const Joint& joint) const;
};

/// The revolute joint's kind (multibody/rotors.hpp asks for it).
const JointKind& revolute_joint();
/// The kind named `name` (nullptr: no such joint type).
const JointKind* find_joint_kind(std::string_view name);
/// Every joint type's name, sorted.
std::vector<std::string> joint_kind_names();

/// The rotation about A's joint z axis by the joint's q0 / rate0 (or its
/// prescribed motion), on the joint's drive(): revolute, cylindrical, screw.
/// Its coordinate is kTurnCoordinate (JointSym::coordinate, rate_source).
Mobilizer::Rate& turn_about_axis(Mobilizer& m);
inline constexpr const char* kTurnCoordinate = "theta";

/// A slide along A's joint z axis by the settings `q0`, `rate0` (or the
/// prescribed motion), on 1-junction `junction` (the joint's drive() or
/// slide()): prismatic, cylindrical.
Mobilizer::Rate& slide_along_axis(Mobilizer& m, const Sym& junction, const Setting& q0, const Setting& rate0,
                                  bool prescribed);

}  // namespace mbgc::multibody::detail
