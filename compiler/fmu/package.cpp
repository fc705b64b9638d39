// fmu/package.cpp — see package.hpp.
#include "fmu/package.hpp"

#include <fmt/format.h>
#include <unistd.h>
#include <zip.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "fmu/sources.hpp"
#include "fmu/toolchain.hpp"

namespace mbgc::fmu {
namespace {

namespace fs = std::filesystem;

struct Toolchain {
  std::string compiler;
  fs::path include, library, runtime_sources;
  std::vector<std::string> static_libraries;
};

/// Where the compiler, the runtime's headers and its FMU library are: the
/// build tree's when this mbgc runs from it, else the installation's.
Toolchain find_toolchain() {
  Toolchain t;
  const char* cxx = std::getenv("CXX");
  t.compiler = cxx && *cxx ? cxx : toolchain::kCompiler;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && fs::equivalent(exe, toolchain::kBuildExecutable, ec)) {
    t.include = toolchain::kBuildInclude;
    t.library = toolchain::kBuildLibrary;
    t.runtime_sources = toolchain::kBuildRuntimeSources;
  } else {
    const fs::path bin = ec ? fs::path(".") : exe.parent_path();
    t.include = (bin / toolchain::kInstalledInclude).lexically_normal();
    t.library = (bin / toolchain::kInstalledLibrary).lexically_normal();
    t.runtime_sources = (bin / toolchain::kInstalledRuntimeSources).lexically_normal();
  }
  std::stringstream libs(toolchain::kStaticLibraries);
  for (std::string lib; std::getline(libs, lib, ';');)
    if (!lib.empty()) t.static_libraries.push_back(lib);
  return t;
}

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool write_file(const fs::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  return f && (f << text) && f.flush();
}

std::string read_file(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// A temporary directory, removed with this object.
class TemporaryDirectory {
 public:
  TemporaryDirectory() {
    std::string pattern = (fs::temp_directory_path() / "mbgc-fmu-XXXXXX").string();
    if (::mkdtemp(pattern.data())) path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// The archive `path` holding `entries` (name in the archive, contents).
std::string zip_files(const fs::path& path, const std::vector<std::pair<std::string, std::string>>& entries) {
  zipFile zip = zipOpen64(path.c_str(), APPEND_STATUS_CREATE);
  if (!zip) return fmt::format("cannot create `{}`", path.string());
  std::string error;
  for (const auto& [name, contents] : entries) {
    zip_fileinfo info{};
    // a fixed date: the same model gives the same archive
    info.tmz_date = {0, 0, 0, 1, 0, 2020};
    if (zipOpenNewFileInZip64(zip, name.c_str(), &info, nullptr, 0, nullptr, 0, nullptr, Z_DEFLATED,
                              Z_DEFAULT_COMPRESSION, contents.size() > 0xffffffffu) != ZIP_OK ||
        zipWriteInFileInZip(zip, contents.data(), static_cast<unsigned>(contents.size())) != ZIP_OK ||
        zipCloseFileInZip(zip) != ZIP_OK) {
      error = fmt::format("cannot write `{}` into `{}`", name, path.string());
      break;
    }
  }
  if (zipClose(zip, nullptr) != ZIP_OK && error.empty()) error = fmt::format("cannot finish `{}`", path.string());
  return error;
}

}  // namespace

std::string write_fmu(const Package& p, const std::string& path) {
  const Toolchain tc = find_toolchain();
  if (!fs::exists(tc.library))
    return fmt::format("the runtime's FMU library `{}` is missing (build the target mbgrt_fmu, or install mbgc)",
                       tc.library.string());
  TemporaryDirectory tmp;
  if (tmp.path().empty()) return "cannot create a temporary directory";
  const fs::path source = tmp.path() / (p.model_identifier + ".cpp");
  const fs::path object = tmp.path() / (p.model_identifier + ".so");
  const fs::path exports = tmp.path() / "exports.map";
  const fs::path log = tmp.path() / "compiler.log";
  // The runtime's FMU library whole (nothing in the model's source calls the
  // FMI functions, so the linker would take none of them from the archive);
  // exported: the FMI functions and nothing else, the runtime and SUNDIALS
  // stay inside.
  if (!write_file(source, p.source) || !write_file(exports, "{\n  global: fmi2*; fmi3*;\n  local: *;\n};\n"))
    return fmt::format("cannot write into `{}`", tmp.path().string());
  std::string command = fmt::format("{} -std=c++17 -O3 -DNDEBUG -fno-math-errno -fno-trapping-math -fPIC -shared -fvisibility=hidden -I{} {} -o {} {}",
                                    quoted(tc.compiler), quoted(tc.include.string()), quoted(source.string()),
                                    quoted(object.string()), "-Wl,--whole-archive " + quoted(tc.library.string()) + " -Wl,--no-whole-archive");
  for (const std::string& lib : tc.static_libraries) command += " " + quoted(lib);
  command += fmt::format(" -pthread -Wl,--version-script={} -Wl,--no-undefined > {} 2>&1", quoted(exports.string()),
                         quoted(log.string()));
  if (std::system(command.c_str()) != 0)
    return fmt::format("the C++ compiler failed on the FMU's source:\n{}\n{}", command, read_file(log));
  const std::string platform = p.version == FmiVersion::v3 ? "x86_64-linux" : "linux64";
  std::vector<std::pair<std::string, std::string>> entries{
      {"modelDescription.xml", p.model_description},
      {fmt::format("binaries/{}/{}.so", platform, p.model_identifier), read_file(object)},
      {fmt::format("sources/{}.cpp", p.model_identifier), p.source},
  };
  if (p.version == FmiVersion::v3) entries.emplace_back("sources/buildDescription.xml", build_description(p.model_identifier));
  for (const std::string& file : runtime_files()) {
    const fs::path from = tc.runtime_sources / file;
    if (!fs::is_regular_file(from))
      return fmt::format("the runtime's source `{}` is missing (the FMU's sources/ holds it)", from.string());
    entries.emplace_back("sources/" + source_path(file), read_file(from));
  }
  // written beside the target, then renamed over it: never a partial FMU
  const std::string partial = path + ".mbgc-tmp-" + std::to_string(::getpid());
  if (std::string error = zip_files(partial, entries); !error.empty()) {
    std::remove(partial.c_str());
    return error;
  }
  std::error_code ec;
  fs::rename(partial, path, ec);
  if (ec) {
    std::remove(partial.c_str());
    return fmt::format("cannot write `{}`", path);
  }
  return {};
}

}  // namespace mbgc::fmu
