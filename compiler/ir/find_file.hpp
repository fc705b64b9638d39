// ir/find_file.hpp — a file a model names (a modal-data file, a mesh), read
// into the SourceManager so that its diagnostics show its lines and the
// depfile lists it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ir/diagnostics.hpp"

namespace mbgc::ir {

/// Reads `name`, looked for beside the model file that names it (at
/// `named_at`), then in each of `search_dirs` (mbgc -I); an absolute name
/// as it is. Returns its SourceManager id; else reports that `what` cannot
/// be read, with the paths tried, and returns nothing.
std::optional<int> read_named_file(const std::string& name, const SourceLoc& named_at, const std::vector<std::string>& search_dirs,
                                   SourceManager& sources, Diagnostics& diags, const char* what);

}  // namespace mbgc::ir
