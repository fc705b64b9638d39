// fe/matrix_market.hpp — reads an FE program's mass or stiffness matrix from
// a Matrix Market file (`coordinate real|integer symmetric|general`), the
// usual exchange format, and checks that it is square, of the expected size,
// finite and symmetric. Errors point at the file's line like a model's.
//
// Eigen has a reader (unsupported/Eigen/SparseExtra, loadMarket) but it only
// says true or false; a user with a bad file needs the line.
#pragma once

#include <Eigen/SparseCore>
#include <optional>
#include <string>

#include "ir/diagnostics.hpp"

namespace mbgc::fe {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, long>;

/// Reads `path` (`what` names it in messages: "mass matrix"). `size` is the
/// number of DOFs the node file implies; the matrix must be size x size.
/// Both triangles are stored in the result. Duplicate entries are summed, as
/// an FE assembly does.
std::optional<SparseMatrix> read_matrix_market(const std::string& path, const char* what, long size,
                                               ir::SourceManager& sources, ir::Diagnostics& diags);

}  // namespace mbgc::fe
