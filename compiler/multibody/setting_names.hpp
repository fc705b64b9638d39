// The settings a contact and a tyre take, by name (their tables live in
// contacts.cpp and tyres.cpp). docs/language.md must name each one:
// tests/unit/language_reference_test.cpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "units/unit.hpp"

namespace mbgc::multibody::detail {

std::vector<std::string> contact_setting_names();
std::vector<std::string> tyre_setting_names();
/// The dimension of a tyre's setting (none: a coefficient; nullopt: no such setting).
std::optional<units::Dimension> tyre_setting_dimension(const std::string& name);
/// The default of a Magic Formula coefficient (nullopt: not one).
std::optional<double> tyre_coefficient_default(const std::string& name);

}  // namespace mbgc::multibody::detail
