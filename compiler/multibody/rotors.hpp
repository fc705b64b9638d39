// multibody/rotors.hpp — the multibody layer's third pass, after the
// spanning tree (spanning_tree.hpp): the bodies that are rotors on their
// parents (Body::rotor_joint), whose frame of equations may leave out their
// own spin.
//
// A rotor is a rigid body turning on a revolute joint in joint coordinates
// about an axis of symmetry: its inertia is the same for every angle of the
// joint (axisymmetric about the axis, the centre of mass on it), and nothing
// else about it depends on that angle (every point of it is on the axis,
// nothing else is jointed to it, no contact touches it, a tyre on it rolls
// about the same axis). Its Newton-Euler equations can then be written in a
// frame that turns with its parent, not with it (the frame of a gyrostat's
// rotor): the inertia there is constant, the joint's rotation R(theta)
// leaves the velocity and force transforms, and the Euler junction
// structure becomes Omega x h with Omega the frame's angular velocity (the
// body's less its spin), still power-free. A car's wheel is the example:
// four sines and cosines a derivative and every product with them go, and
// what the parent reads of the wheel is a constant inertia (the two-track
// car: 3,613 operations a derivative become 2,891).
//
// What a user reads of the body is unchanged: its rotation, quaternion,
// angular velocity in its own axes and its drawing add the spin back
// (Expander::attitude). mbgc --no-rotors writes every body in its own
// frame (to compare the two forms).
#pragma once

#include <string>

#include "multibody/model.hpp"

namespace mbgc::multibody::detail {

/// Marks the rotors (Body::rotor_joint); appends a line per rotor to
/// `report` (mbgc --dump causality) when it is given.
void find_rotors(Model& m, std::string* report);

}  // namespace mbgc::multibody::detail
