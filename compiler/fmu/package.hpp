// fmu/package.hpp — the last step of mbgc --fmu: the FMU archive. The
// generated source is compiled into a shared object with the C++ compiler
// mbgc was built with (or $CXX), linked with the runtime's FMU library
// (libmbgrt_fmu.a) and SUNDIALS' static libraries, and zipped with
// modelDescription.xml and the sources (fmu/sources.hpp) with minizip.
#pragma once

#include <string>

#include "fmu/model_description.hpp"

namespace mbgc::fmu {

struct Package {
  std::string model_identifier;   ///< the shared object's name
  std::string source;             ///< the generated C++ (model class and entry), token sealed
  std::string model_description;  ///< modelDescription.xml
  FmiVersion version = FmiVersion::v3;
};

/// Builds `package` into the FMU file `path`. Returns an empty string on
/// success, else what went wrong (the compiler's messages included).
std::string write_fmu(const Package& package, const std::string& path);

}  // namespace mbgc::fmu
