#include "ir/find_file.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "ir/limits.hpp"

namespace mbgc::ir {

ReadStatus read_text_file(const std::string& path, std::string& text, std::uintmax_t& bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  bytes = 0;
  if (!fs::is_regular_file(path, ec)) return ReadStatus::Unreadable;
  bytes = fs::file_size(path, ec);
  if (ec) return ReadStatus::Unreadable;
  if (bytes > kMaxFileBytes) return ReadStatus::TooLarge;
  std::ifstream in(path, std::ios::binary);
  if (!in) return ReadStatus::Unreadable;
  std::ostringstream all;
  all << in.rdbuf();
  text = all.str();
  return ReadStatus::Ok;
}

std::string too_large_message(const std::string& path, std::uintmax_t bytes) {
  constexpr double kMB = 1024.0 * 1024.0;
  return fmt::format("`{}` is {:.0f} MB; mbgc reads files of up to {:.0f} MB", path, static_cast<double>(bytes) / kMB,
                     static_cast<double>(kMaxFileBytes) / kMB);
}

std::optional<int> read_named_file(const std::string& name, const SourceLoc& named_at, const std::vector<std::string>& search_dirs,
                                   SourceManager& sources, Diagnostics& diags, const char* what) {
  namespace fs = std::filesystem;
  std::vector<fs::path> tried;
  if (named_at.valid()) tried.push_back(fs::path(sources.file(named_at.file).display_path).parent_path() / name);
  for (const std::string& d : search_dirs) tried.push_back(fs::path(d) / name);
  if (fs::path(name).is_absolute()) tried = {fs::path(name)};
  for (const fs::path& p : tried) {
    std::string text;
    std::uintmax_t bytes = 0;
    const ReadStatus status = read_text_file(p.string(), text, bytes);
    if (status == ReadStatus::Unreadable) continue;
    if (status == ReadStatus::TooLarge) {
      diags.error(named_at, too_large_message(p.lexically_normal().string(), bytes),
                  fmt::format("is `{}` the {} you meant? Files this large are not written by hand", name, what));
      return std::nullopt;
    }
    return sources.add(p.lexically_normal().string(), std::move(text));
  }
  std::string where;
  for (const fs::path& p : tried) where += (where.empty() ? "" : ", ") + fmt::format("`{}`", p.lexically_normal().string());
  diags.error(named_at, fmt::format("cannot read the {} \"{}\" (tried {})", what, name, where),
              "the path is relative to the model file, then to each directory given with mbgc -I");
  return std::nullopt;
}

}  // namespace mbgc::ir
