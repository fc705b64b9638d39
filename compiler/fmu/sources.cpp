// fmu/sources.cpp — see sources.hpp.
#include "fmu/sources.hpp"

#include <fmt/format.h>

#include <sstream>

#include "fmu/toolchain.hpp"

namespace mbgc::fmu {
namespace {

bool ends_with(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

std::vector<std::string> split(const char* list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ';');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

std::vector<std::string> runtime_files() { return split(toolchain::kRuntimeSourceFiles); }

std::string source_path(const std::string& runtime_file) { return "mbgrt/" + runtime_file; }

std::vector<std::string> compiled_sources(const std::string& model_identifier) {
  std::vector<std::string> out{model_identifier + ".cpp"};
  for (const std::string& file : runtime_files())
    if (ends_with(file, ".cpp")) out.push_back(source_path(file));
  return out;
}

std::string build_description(const std::string& model_identifier) {
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiBuildDescription fmiVersion=\"3.0\">\n";
  x += fmt::format("  <BuildConfiguration modelIdentifier=\"{}\" description=\"the shared object: the model and the "
                   "mbgc runtime's FMU part, compiled as C++20 and linked with SUNDIALS\">\n",
                   model_identifier);
  x += "    <SourceFileSet language=\"C++20\">\n";
  for (const std::string& file : compiled_sources(model_identifier))
    x += fmt::format("      <SourceFile name=\"{}\"/>\n", file);
  x += "      <PreprocessorDefinition name=\"FMT_HEADER_ONLY\" value=\"1\" description=\"fmt is used header-only\"/>\n";
  x += fmt::format("      <IncludeDirectory name=\"{}\"/>\n", source_path("include"));
  x += fmt::format("      <IncludeDirectory name=\"{}\"/>\n", source_path("src"));
  x += "    </SourceFileSet>\n";
  for (const std::string& library : split(toolchain::kSundialsLibraries))
    x += fmt::format("    <Library name=\"{}\" version=\"{}\" external=\"true\" description=\"SUNDIALS, the "
                     "integrators' library (the version the FMU was built with)\"/>\n",
                     library, toolchain::kSundialsVersion);
  x += "    <Library name=\"fmt\" external=\"true\" description=\"formatting, used header-only\"/>\n";
  x += "    <Library name=\"eigen3\" external=\"true\" description=\"dense linear algebra, header-only: its include "
       "directory (Debian: /usr/include/eigen3)\"/>\n";
  x += "  </BuildConfiguration>\n</fmiBuildDescription>\n";
  return x;
}

}  // namespace mbgc::fmu
