// ir/drawing.hpp — how a body is drawn in an animation (mbgrt::BodyVisual's
// compile-time half): its shape in body axes, measured from the point whose
// pose the model reports (a rigid body's centre of mass, a flexible body's
// frame origin), and for a flexible body a surface with one displacement
// field per modal coordinate. The multibody layer makes one per body
// (multibody/drawing.cpp); the emitter writes it as body_visual().
//
// A surface is drawn the same way (`surface` set): a contact's plane,
// sphere, cylinder or polygon, or a tyre's road, posed like a body (the
// surface's point and frame: a plane's and a cylinder's axis along its z).
// Unbounded ones (a plane, a cylinder's length, a polygon's extrusion, a
// road) are sized by the runtime from where the bodies go in the run.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace mbgc::ir {

struct Drawing {
  enum class Shape { Box, Cylinder, Sphere, Mesh, Plane, Prism, Road };
  std::string body;  // the body's name (a surface: its contact's, or "road")
  Shape shape = Shape::Box;
  std::array<double, 3> size{0.1, 0.1, 0.1};  // box: edges along x, y, z; cylinder: radius, length (along z; 0: from the run); sphere: radius
  std::array<double, 3> centre{0, 0, 0};      // the shape's centre, body axes from the posed point (m)
  std::array<double, 3> colour{0.6, 0.6, 0.65};
  std::vector<double> vertices;                // Mesh: 3 per vertex, body axes from the posed point
  std::vector<unsigned> triangles;             // Mesh: 3 vertex indices each
  std::vector<std::vector<double>> mode_shapes;  // per modal coordinate: 3 per vertex
  bool surface = false;         // a contact surface or a tyre's road, not a body
  std::vector<double> profile;  // Prism: (x, z) corners in the x-z plane, extruded along y; Road: (x, height) points
  std::vector<std::string> covers;  // a surface: the bodies touching it, whose run its unbounded extent covers
};

}  // namespace mbgc::ir
