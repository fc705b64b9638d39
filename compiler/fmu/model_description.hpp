// fmu/model_description.hpp — an FMU's modelDescription.xml, written from its
// Interface (fmu/interface.hpp): FMI 3.0 or 2.0, model exchange and
// co-simulation.
#pragma once

#include <string>
#include <vector>

#include "fmu/interface.hpp"

namespace mbgc::fmu {

enum class FmiVersion { v2, v3 };

struct Offer {
  bool model_exchange = true;
  bool co_simulation = true;
};

/// modelDescription.xml of `fmu`, with `token` its instantiation token (FMI 3)
/// or GUID (FMI 2), `generator` "mbgc VERSION"; FMI 2.0 lists `sources` (the
/// files to compile, relative to sources/) in its SourceFiles.
std::string model_description(const Interface& fmu, FmiVersion version, const Offer& offer, const std::string& token,
                              const std::string& generator, const std::vector<std::string>& sources);

}  // namespace mbgc::fmu
