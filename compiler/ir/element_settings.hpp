// ir/element_settings.hpp — what a bond-graph element takes in braces, by
// kind, declared once: a law (`R r { e = ... }`), an initial value (`C c
// { q0 = ... }`), a CN's penalty, stabilisation or contact settings. The
// multibody layer writes its elements' settings through these entries, the
// graph builder looks each one up here, and its diagnostics list the table.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ir/expanded.hpp"
#include "ir/graph.hpp"

namespace mbgc::ir {

struct ElementSetting {
  enum class Role {
    Law,         // the element's constitutive law (or a CN's constraint g)
    Initial,     // a storage's initial value, a free rate's
    Constraint,  // a CN's: penalty stiffness and damping, stabilisation, a contact's restitution, exponent, friction
  };
  const char* key;
  Role role;
  /// Role::Law: the form a law under this key gives the element.
  LawForm law = LawForm::Linear;
  /// Its value where the element needs one that is not given (a CN's: ConstraintLaw::Field).
  std::optional<double> default_value = std::nullopt;
};

/// The entries, by the element kind that takes them (a CN's: ConstraintLaw::fields()).
namespace element_setting {
using Role = ElementSetting::Role;
inline const ElementSetting r_effort{"e", Role::Law, LawForm::EffortOfFlow};   // R: e = law of f
inline const ElementSetting r_flow{"f", Role::Law, LawForm::FlowOfEffort};     // R: f = law of e
inline const ElementSetting c_effort{"e", Role::Law, LawForm::EffortOfState};  // C: e = law of q
inline const ElementSetting q0{"q0", Role::Initial};                           // C: the initial displacement
inline const ElementSetting e0{"e0", Role::Initial};                           // C: ... given as its effort
inline const ElementSetting i_flow{"f", Role::Law, LawForm::FlowOfState};      // I: f = law of p
inline const ElementSetting p0{"p0", Role::Initial};                           // I: the initial momentum
inline const ElementSetting f0{"f0", Role::Initial};                           // I: ... given as its flow
inline const ElementSetting rate0{"rate0", Role::Initial};                     // Sf: the initial rate of a free flow
}  // namespace element_setting

/// The settings elements of kind `k` take, in the order diagnostics list them.
const std::vector<ElementSetting>& element_settings(NodeKind k);

/// The setting `key` of kind `k`, or null.
const ElementSetting* find_element_setting(NodeKind k, const std::string& key);

/// Whether `key` is a setting of kind `k` in `role`.
bool is_element_setting(NodeKind k, const std::string& key, ElementSetting::Role role);

/// Their keys, in order.
std::vector<std::string> element_setting_keys(NodeKind k);

/// How to write an element of kind `k` named `name` that has neither a value nor a law.
std::string law_hint(NodeKind k, const std::string& name);

}  // namespace mbgc::ir
