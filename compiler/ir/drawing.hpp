// ir/drawing.hpp — how a body is drawn in an animation (mbgrt::BodyVisual's
// compile-time half): its shape in body axes, measured from the point whose
// pose the model reports (a rigid body's centre of mass, a flexible body's
// frame origin), and for a flexible body a surface with one displacement
// field per modal coordinate. The multibody layer makes one per body
// (multibody/drawing.cpp); the emitter writes it as body_visual().
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace mbgc::ir {

struct Drawing {
  enum class Shape { Box, Cylinder, Sphere, Mesh };
  std::string body;
  Shape shape = Shape::Box;
  std::array<double, 3> size{0.1, 0.1, 0.1};  // box: edges along x, y, z; cylinder: radius, length (along z); sphere: radius
  std::array<double, 3> centre{0, 0, 0};      // the shape's centre, body axes from the posed point (m)
  std::array<double, 3> colour{0.6, 0.6, 0.65};
  std::vector<double> vertices;                // Mesh: 3 per vertex, body axes from the posed point
  std::vector<unsigned> triangles;             // Mesh: 3 vertex indices each
  std::vector<std::vector<double>> mode_shapes;  // per modal coordinate: 3 per vertex
};

}  // namespace mbgc::ir
