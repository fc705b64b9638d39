#include "ir/element_settings.hpp"

#include <fmt/format.h>

namespace mbgc::ir {

using Role = ElementSetting::Role;

const std::vector<ElementSetting>& element_settings(NodeKind k) {
  using namespace element_setting;
  static const std::vector<ElementSetting> r = {r_effort, r_flow};
  static const std::vector<ElementSetting> c = {c_effort, q0, e0};
  static const std::vector<ElementSetting> i = {i_flow, p0, f0};
  // a CN's: its rows g, then what holds them (ir::ConstraintLaw, whose fields name them)
  static const std::vector<ElementSetting> cn = [] {
    std::vector<ElementSetting> out;
    for (const ConstraintLaw::Field& f : ConstraintLaw::fields())
      out.push_back(f.member == &ConstraintLaw::g ? ElementSetting{f.key, Role::Law, LawForm::Constraint}
                                                  : ElementSetting{f.key, Role::Constraint, LawForm::Linear, f.default_value});
    return out;
  }();
  static const std::vector<ElementSetting> sf = {rate0};
  static const std::vector<ElementSetting> none;
  switch (k) {
    case NodeKind::R: return r;
    case NodeKind::C: return c;
    case NodeKind::I: return i;
    case NodeKind::CN: return cn;
    case NodeKind::Sf: return sf;
    default: return none;
  }
}

const ElementSetting* find_element_setting(NodeKind k, const std::string& key) {
  for (const ElementSetting& s : element_settings(k))
    if (key == s.key) return &s;
  return nullptr;
}

bool is_element_setting(NodeKind k, const std::string& key, Role role) {
  const ElementSetting* s = find_element_setting(k, key);
  return s && s->role == role;
}

std::vector<std::string> element_setting_keys(NodeKind k) {
  std::vector<std::string> out;
  for (const ElementSetting& s : element_settings(k)) out.emplace_back(s.key);
  return out;
}

std::string law_hint(NodeKind k, const std::string& name) {
  switch (k) {
    case NodeKind::R: return fmt::format("write R {} = resistance, or R {} {{ e = expression of f }}", name, name);
    case NodeKind::C: return fmt::format("write C {} = capacitance, or C {} {{ e = expression of q }}", name, name);
    case NodeKind::I: return fmt::format("write I {} = inertia, or I {} {{ f = expression of p }}", name, name);
    case NodeKind::CN: return fmt::format("write CN {} {{ g = position constraint }} (add stiffness/damping for a penalty)", name);
    default: return fmt::format("write {} {} = value", node_kind_name(k), name);
  }
}

}  // namespace mbgc::ir
