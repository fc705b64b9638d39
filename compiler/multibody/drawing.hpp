// multibody/drawing.hpp — the meshes flexible bodies are drawn with
// (ir/drawing.hpp): each kind of deformation fills its own from these.
#pragma once

#include <array>
#include <vector>

#include "ir/drawing.hpp"

namespace mbgc::multibody::detail {

/// A tube along body x: one rectangular section of half-widths hy, hz at
/// each x (4 vertices, corners (+y +z), (-y +z), (-y -z), (+y -z)), its
/// sides and both ends triangulated. Appends to d's vertices and triangles.
void add_tube(ir::Drawing& d, const std::vector<double>& x, double hy, double hz);

/// A square bar of half-width h from a to b (4 vertices at a, then 4 at b),
/// its sides and ends triangulated.
void add_bar(ir::Drawing& d, const std::array<double, 3>& a, const std::array<double, 3>& b, double h);

/// An octahedron of radius r around c (6 vertices: +x, -x, +y, -y, +z, -z).
void add_octahedron(ir::Drawing& d, const std::array<double, 3>& c, double r);

}  // namespace mbgc::multibody::detail
