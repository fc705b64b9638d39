#include "ir/find_file.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace mbgc::ir {

std::optional<int> read_named_file(const std::string& name, const SourceLoc& named_at, const std::vector<std::string>& search_dirs,
                                   SourceManager& sources, Diagnostics& diags, const char* what) {
  namespace fs = std::filesystem;
  std::vector<fs::path> tried;
  if (named_at.valid()) tried.push_back(fs::path(sources.file(named_at.file).display_path).parent_path() / name);
  for (const std::string& d : search_dirs) tried.push_back(fs::path(d) / name);
  if (fs::path(name).is_absolute()) tried = {fs::path(name)};
  for (const fs::path& p : tried) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) continue;
    std::ifstream in(p, std::ios::binary);
    if (!in) continue;
    std::ostringstream text;
    text << in.rdbuf();
    return sources.add(p.lexically_normal().string(), text.str());
  }
  std::string where;
  for (const fs::path& p : tried) where += (where.empty() ? "" : ", ") + fmt::format("`{}`", p.lexically_normal().string());
  diags.error(named_at, fmt::format("cannot read the {} \"{}\" (tried {})", what, name, where),
              "the path is relative to the model file, then to each directory given with mbgc -I");
  return std::nullopt;
}

}  // namespace mbgc::ir
