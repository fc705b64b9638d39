// The settings a contact and a tyre take, by name (their tables live in
// contacts.cpp and tyres.cpp). docs/language.md must name each one:
// tests/unit/language_reference_test.cpp.
#pragma once

#include <string>
#include <vector>

namespace mbgc::multibody::detail {

std::vector<std::string> contact_setting_names();
std::vector<std::string> tyre_setting_names();

}  // namespace mbgc::multibody::detail
