// fe/mbm_writer.hpp — writes a modal-data file (docs/modal_format.md) from
// the invariants and the attachment points of a reduced body.
#pragma once

#include <string>
#include <vector>

#include "craig_bampton.hpp"
#include "invariants.hpp"

namespace mbgc::fe {

struct NamedPoint {
  std::string name;
  Eigen::Vector3d position;  // body axes, from the frame origin
  PointMotion motion;
};

/// `comments` are written first, each line prefixed with `# `. Returns false
/// when the file cannot be written.
bool write_mbm(const std::string& path, const std::vector<std::string>& comments, const Invariants& inv,
               const std::vector<NamedPoint>& points);

}  // namespace mbgc::fe
