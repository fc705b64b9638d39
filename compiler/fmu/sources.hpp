// fmu/sources.hpp — what an FMU's sources/ directory holds, so that the FMU can
// be compiled again on another platform (a source FMU): the generated model,
// the part of the runtime an FMU calls (under mbgrt/), and for FMI 3.0
// buildDescription.xml, which says how to compile them. FMI 2.0 lists the
// compiled files in modelDescription.xml instead (SourceFiles).
#pragma once

#include <string>
#include <vector>

namespace mbgc::fmu {

/// The runtime's files an FMU carries, relative to the runtime's directory
/// (src/..., include/mbgrt/...): the sources of the library mbgrt_fmu and the
/// headers they include.
std::vector<std::string> runtime_files();

/// Where a runtime file goes, relative to sources/.
std::string source_path(const std::string& runtime_file);

/// The files to compile, relative to sources/: the model's, then the runtime's.
std::vector<std::string> compiled_sources(const std::string& model_identifier);

/// sources/buildDescription.xml (FMI 3.0) for the model's shared object.
std::string build_description(const std::string& model_identifier);

}  // namespace mbgc::fmu
