// fe/mesh.hpp — the FE model's nodes as mbgc-reduce reads them, and the
// places of the reduced body that joints and loads attach to.
//
// Node file: one node per line, `ID x y z` (m), `#` comments. Its order is
// the DOF order of the matrices: node k (0-based, in file order) owns DOFs
// d k .. d k + d - 1, with d = --dofs-per-node:
//   d = 3: translations x, y, z (solid elements);
//   d = 6: translations x, y, z, then small rotations about x, y, z (beams, shells).
#pragma once

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "ir/diagnostics.hpp"

namespace mbgc::fe {

struct Mesh {
  int dofs_per_node = 6;
  std::vector<long long> ids;            // as the file names them
  std::vector<Eigen::Vector3d> position;  // m, the FE model's axes
  std::unordered_map<long long, int> index_of;
  long dofs() const { return static_cast<long>(ids.size()) * dofs_per_node; }
  bool has_rotations() const { return dofs_per_node == 6; }
};

std::optional<Mesh> read_nodes(const std::string& path, int dofs_per_node, ir::SourceManager& sources,
                               ir::Diagnostics& diags);

/// A named place of the reduced body: one node, or several tied rigidly to
/// their centroid (like an RBE2 element: a solid's face carrying a joint).
/// An interface gets constraint modes (its 6 DOFs are boundary DOFs of the
/// reduction); a plain point only reports the motion there.
struct Attachment {
  std::string name;
  std::vector<int> nodes;  // indices into Mesh
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  bool interface = true;
};

/// Parses `NAME=ID[,ID...]` or `NAME=@FILE` (a node set: IDs in FILE) (a command-line value) against the mesh. Errors
/// (unknown node, a node named twice, a rigid set that cannot carry a
/// rotation) go to `diags`.
std::optional<Attachment> parse_attachment(const std::string& spec, bool interface, const Mesh& mesh,
                                           ir::Diagnostics& diags);

}  // namespace mbgc::fe
