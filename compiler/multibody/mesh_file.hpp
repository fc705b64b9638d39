// multibody/mesh_file.hpp — a body's drawn surface from a Wavefront OBJ file
// (`shape = mesh("part.obj")`): its `v x y z` vertices and `f` faces (a
// polygon is cut into a fan of triangles; normals and texture coordinates
// are ignored), in metres, body axes from the centre of mass.
#pragma once

#include <string>
#include <vector>

#include "ir/diagnostics.hpp"
#include "ir/drawing.hpp"

namespace mbgc::multibody {

/// Fills d.vertices and d.triangles; false (and an error at the file's line)
/// if the file cannot be read or is not a mesh.
bool read_mesh_file(const std::string& name, const ir::SourceLoc& named_at, const std::vector<std::string>& search_dirs,
                    ir::SourceManager& sources, ir::Diagnostics& diags, ir::Drawing& d);

}  // namespace mbgc::multibody
