// graph/element_settings.hpp — what a bond-graph element takes in braces, by
// kind, declared once: a law (`R r { e = ... }`), an initial value (`C c
// { q0 = ... }`), a CN's penalty, stabilisation or contact settings. The
// graph builder looks each setting up here, and its diagnostics list the
// table.
#pragma once

#include <string>
#include <vector>

#include "ir/expanded.hpp"
#include "ir/graph.hpp"

namespace mbgc::graph {

struct ElementSetting {
  enum class Role {
    Law,         // the element's constitutive law (or a CN's constraint g)
    Initial,     // a storage's initial value, a free rate's
    Constraint,  // a CN's: penalty stiffness and damping, stabilisation, a contact's restitution, exponent, friction
  };
  const char* key;
  Role role;
  /// Role::Law: the form a law under this key gives the element.
  ir::LawForm law = ir::LawForm::Linear;
};

/// The settings elements of kind `k` take, in the order diagnostics list them.
const std::vector<ElementSetting>& element_settings(ir::NodeKind k);

/// The setting `key` of kind `k`, or null.
const ElementSetting* find_element_setting(ir::NodeKind k, const std::string& key);

/// Whether `key` is a setting of kind `k` in `role`.
bool is_element_setting(ir::NodeKind k, const std::string& key, ElementSetting::Role role);

/// Their keys, in order.
std::vector<std::string> element_setting_keys(ir::NodeKind k);

/// How to write an element of kind `k` named `name` that has neither a value nor a law.
std::string law_hint(ir::NodeKind k, const std::string& name);

}  // namespace mbgc::graph
