// multibody/joint_symbols.hpp — the names a joint writes (symbols.hpp's
// rules): its frames and settings, the fragment of either strategy (the
// constraint rows of lagrange and penalty, joint_rows.cpp; the rates of
// joint coordinates, joint_coordinates.cpp), and the quantities users read.
// The child's pose in joint coordinates is the body's (BodySym::pose_r,
// pose_q, pose_R).
#pragma once

#include <string>

#include <fmt/format.h>

#include "multibody/symbols.hpp"

namespace mbgc::multibody::detail {

/// A joint (`joint j revolute(a.p, b.q) { ... }`). Its two sides are the
/// first body's ('a') and the second's ('b').
class JointSym : public Sym {
 public:
  explicit JointSym(const std::string& joint) : Sym(joint) {}

  // ---- properties (joint_params): on side 'a' or 'b'
  /// The joint point relative to the body's centre of mass, body axes (on ground: absolute).
  Sym point(char side) const { return part(fmt::format("p{}", side), units::dim::length()); }
  /// The joint axis, normalised, body axes.
  Sym axis(char side) const { return part(fmt::format("axis_{}", side), units::Dimension::none()); }
  /// The joint frame's orientation in the body: its quaternion and its rotation matrix.
  Sym frame_q(char side) const { return part(fmt::format("f{}", side), units::Dimension::none()); }
  Sym frame_R(char side) const { return part(fmt::format("F{}", side), units::Dimension::none()); }
  /// The length that turns the angular rows (dot products of axes) into metres.
  Sym scale() const { return part("scale", units::dim::length()); }
  // a kind's own: a distance rod's length, a screw's advance per radian
  Sym length() const { return part(joint_setting::length); }
  Sym pitch() const { return part(joint_setting::pitch); }

  // ---- the rows strategies (lagrange, penalty; a cut joint in joint coordinates)
  // penalty's spring-damper; a cut joint's Baumgarte rate (rad/s)
  Sym stiffness() const { return part("stiffness"); }
  Sym damping() const { return part("damping"); }
  Sym stabilisation() const { return part(joint_setting::stabilisation); }
  Sym rows() const { return part("c"); }         // the 0-junction of the rows' rates
  Sym constraint() const { return part("cn"); }  // the CN holding them at 0
  Sym motion() const { return part("motion"); }  // the Sf of a prescribed motion's explicit rate
  /// The MTF that carries side `side`'s body flow `flow` into the rows'
  /// rates (`row_rate`) or the drive coordinate's (`drive_rate`): 't' the
  /// velocity, 'r' the angular velocity, 'e' a flexible body's modal rates.
  Sym row_rate(char side, char flow) const { return part(fmt::format("c{}{}", side, flow)); }
  Sym drive_rate(char side, char flow) const { return part(fmt::format("d{}{}", side, flow)); }
  /// The 0-junction summing the drive coordinate's rate (rows strategies).
  Sym drive_sum() const { return part("dsum"); }

  // ---- both strategies: the drive
  /// The 1-junction on the drive coordinate's rate (the angle's, else the slide's).
  Sym drive() const { return part("drive"); }
  Sym applied() const { return part("applied"); }  // the Se of the joint's `torque` or `force` on it

  // ---- joint coordinates
  /// A scalar coordinate `c` (theta, s, x, alpha, ...): the C integrating
  /// its rate, and the Sf of the rate (a state) or of the prescribed motion's.
  Sym coordinate(const std::string& c) const { return part(c); }
  Sym rate_source(const std::string& c) const { return part(c + "_rate"); }
  /// The 1-junction of coordinate `c`'s rate, where the kind names it after
  /// the coordinate (`xdot`); else drive(), slide() or turn().
  Sym rate_junction(const std::string& c) const { return part(c + "dot"); }
  Sym slide() const { return part("slide"); }  // a cylindrical joint's slide (its angle is on drive())
  Sym turn() const { return part("turn"); }    // a planar joint's rotation
  /// A ball's relative rotation: the 1-junction of its angular velocity
  /// (B's joint axes), the Sf of that rate, the C of the relative
  /// quaternion, the MTF of the quaternion's rate between them.
  Sym spin() const { return part("spin"); }
  Sym spin_rate() const { return part("spin_rate"); }
  Sym rot() const { return part("rot"); }
  Sym rot_rate() const { return part("rotrate"); }
  /// A free joint's translation (Mobilizer::float_in_child_axes): the
  /// 1-junction of its velocity (B's joint axes), the Sf of that rate, the C
  /// of the translation (A's joint axes), the MTF turning the one into the
  /// other's rate between them.
  Sym drift() const { return part("drift"); }
  Sym drift_rate() const { return part("drift_rate"); }
  Sym offset() const { return part("offset"); }
  Sym offset_rate() const { return part("offsetrate"); }
  /// The bodies' relative rotation R_PC, entry (r, c), where it is a signal.
  Sym relative_R(int r, int c) const { return part(fmt::format("Rpc{}{}", r, c)); }
  /// The k-th MTF (from 1) feeding the child's velocity sums.
  Sym feed(int k) const { return part(fmt::format("m{}", k)); }
  /// The 0-junctions of the child's angular velocity and velocity (child
  /// axes), the Sf holding a child nothing turns still, and the 0-junction
  /// of the joint point's velocity in a turning parent's axes with the
  /// bond into it from the parent's velocity junction.
  Sym w_sum() const { return part("wsum"); }
  Sym v_sum() const { return part("vsum"); }
  Sym still() const { return part("still"); }
  Sym point_velocity() const { return part("vpa"); }
  Sym parent_velocity() const { return part("parent_v"); }
  /// The bonds into the child's velocity and angular-velocity junctions:
  /// their efforts are the joint's reaction force and torque.
  Sym reaction_force() const { return part("reaction_f"); }
  Sym reaction_torque() const { return part("reaction_t"); }

  /// A quantity users read: `violation`, `force`, `torque`, `angle`, `rate`,
  /// `displacement`, `displacement_rate`.
  Sym quantity(const std::string& q) const { return part(q); }
};

}  // namespace mbgc::multibody::detail
