// ir/find_file.hpp — a file a model names (a modal-data file, a mesh), read
// into the SourceManager so that its diagnostics show its lines and the
// depfile lists it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ir/diagnostics.hpp"

namespace mbgc::ir {

enum class ReadStatus { Ok, Unreadable, TooLarge };

/// The whole of a regular file into `text`, if it is no larger than
/// kMaxFileBytes (ir/limits.hpp); `bytes` is set to its size either way.
ReadStatus read_text_file(const std::string& path, std::string& text, std::uintmax_t& bytes);

/// "the file is 300 MB; mbgc reads files of up to 256 MB": the message for ReadStatus::TooLarge.
std::string too_large_message(const std::string& path, std::uintmax_t bytes);

/// Reads `name`, looked for beside the model file that names it (at
/// `named_at`), then in each of `search_dirs` (mbgc -I); an absolute name
/// as it is. Returns its SourceManager id; else reports that `what` cannot
/// be read, with the paths tried, or that it is too large, and returns nothing.
std::optional<int> read_named_file(const std::string& name, const SourceLoc& named_at, const std::vector<std::string>& search_dirs,
                                   SourceManager& sources, Diagnostics& diags, const char* what);

}  // namespace mbgc::ir
