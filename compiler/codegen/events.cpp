// codegen/events.cpp — see events.hpp.
#include "codegen/events.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "codegen/identity.hpp"
#include "codegen/names.hpp"

namespace mbgc::codegen {

std::string event_mode_name(std::size_t k) { return fmt::format("mode_[{}]", k); }

std::string event_name(const ir::EventRelation& ev, const ir::Namer& names,
                              const std::function<std::string(const ir::SourceLoc&)>& where) {
  if (ev.contact >= 0) return ev.origin + (ev.loc.valid() ? " (" + where(ev.loc) + ")" : std::string());
  std::string name = to_string(ev.step, names) + (ev.time_event ? " (time event)" : "");
  const std::string element = ev.origin.substr(0, ev.origin.find(':'));
  if (!element.empty()) name += ", " + element;
  if (ev.loc.valid()) name += " (" + where(ev.loc) + ")";
  return name;
}

void add_event_methods(CppClass& c, const ir::ReducedSystem& s,
                       const std::function<std::string(const ir::SourceLoc&)>& where) {
  if (s.events.empty()) return;
  const std::size_t n = s.events.size();
  const ir::Namer names = names_for_dump(s.graph);
  c.public_methods.push_back({"EVENTS: the model's discontinuities, each a step held as a mode between the zero crossings "
                              "of its argument.",
                              "std::size_t event_count() const override",
                              {CppStmt::line(fmt::format("return {};", n))}});
  CppFunction name{"", "std::string event_name(std::size_t k) const override", {}};
  name.body.push_back(CppStmt::line(fmt::format("static const char* const names[{}] = {{", n)));
  for (std::size_t k = 0; k < n; ++k) {
    name.body.push_back(CppStmt::line(fmt::format("    {},", cpp_string(event_name(s.events[k], names, where)))));
  }
  name.body.push_back(CppStmt::line("};"));
  name.body.push_back(CppStmt::line("return k < " + std::to_string(n) + " ? names[k] : std::string();"));
  c.public_methods.push_back(std::move(name));
  c.public_methods.push_back({"", "bool set_event_mode(std::size_t k, bool on) override",
                              {CppStmt::line(fmt::format("if (k >= {} || (mode_[k] != 0.0) == on) return false;", n)),
                               CppStmt::line("mode_[k] = on ? 1.0 : 0.0;"), CppStmt::line("return true;")}});
  c.private_members.push_back(CppStmt::comment("event modes: each step(x) of the model, 1 while x >= 0 (switched by the runtime at x's zero crossings)"));
  c.private_members.push_back(CppStmt::line(fmt::format("double mode_[{}] = {{}};", n)));
}

std::unordered_map<int, std::string> contact_member_names(const ir::ReducedSystem& s) {
  std::unordered_map<int, std::string> names;
  for (std::size_t k = 0; k < s.events.size(); ++k) {
    if (s.events[k].contact < 0) continue;
    const ir::ContactRow& row = s.contacts[static_cast<std::size_t>(s.events[k].contact)];
    names[s.events[k].friction ? row.stick : row.closed] = event_mode_name(k);
  }
  for (std::size_t c = 0; c < s.contacts.size(); ++c) {
    if (s.contacts[c].slip1 >= 0) names[s.contacts[c].slip1] = fmt::format("contact_slip_[{}][0]", c);
    if (s.contacts[c].slip2 >= 0) names[s.contacts[c].slip2] = fmt::format("contact_slip_[{}][1]", c);
    if (s.contacts[c].bias >= 0) names[s.contacts[c].bias] = fmt::format("contact_bias_[{}]", c);
    if (s.contacts[c].damping >= 0) names[s.contacts[c].damping] = fmt::format("contact_damping_[{}]", c);
  }
  return names;
}

void add_contact_methods(CppClass& c, const ir::ReducedSystem& s, CppFunction speeds, std::optional<CppFunction> tangents) {
  const std::size_t n = s.contacts.size();
  std::vector<std::size_t> event(n);
  std::vector<long> friction_event(n, -1);
  for (std::size_t k = 0; k < s.events.size(); ++k) {
    if (s.events[k].contact < 0) continue;
    const auto i = static_cast<std::size_t>(s.events[k].contact);
    if (s.events[k].friction) friction_event[i] = static_cast<long>(k);
    else event[i] = k;
  }
  c.public_methods.push_back({"CONTACTS: each a gap g >= 0 whose mode is an event's; the runtime switches it and applies "
                              "the impacts.",
                              "std::size_t contact_count() const override",
                              {CppStmt::line(fmt::format("return {};", n))}});
  CppFunction info{"", "mbgrt::ContactInfo contact(std::size_t c) const override", {}};
  info.body.push_back(CppStmt::line(fmt::format("static const mbgrt::ContactInfo kInfo[{}] = {{", n)));
  for (std::size_t i = 0; i < n; ++i)
    info.body.push_back(CppStmt::line(fmt::format("    {{{}, {}, 0.0, {}}},  // {}", event[i], s.contacts[i].compliant ? "true" : "false",
                                                  friction_event[i], s.contacts[i].name)));
  info.body.push_back(CppStmt::line("};"));
  info.body.push_back(CppStmt::line("mbgrt::ContactInfo r = kInfo[c];"));
  info.body.push_back(CppStmt::line("r.restitution = contact_restitution_[c];"));
  info.body.push_back(CppStmt::line("return r;"));
  c.public_methods.push_back(std::move(info));
  c.public_methods.push_back(std::move(speeds));
  if (tangents) {
    c.public_methods.push_back(std::move(*tangents));
    c.public_methods.push_back({"", "void set_contact_slip(std::size_t c, double d1, double d2) override",
                                {CppStmt::line(fmt::format("if (c >= {}) return;", n)), CppStmt::line("contact_slip_[c][0] = d1;"),
                                 CppStmt::line("contact_slip_[c][1] = d2;")}});
  }
  c.public_methods.push_back({"", "void set_contact_bias(std::size_t c, double b) override",
                              {CppStmt::line(fmt::format("if (c < {}) contact_bias_[c] = b;", n))}});
  c.public_methods.push_back({"", "void set_contact_damping(std::size_t c, double d) override",
                              {CppStmt::line(fmt::format("if (c < {}) contact_damping_[c] = d;", n))}});
  c.private_members.push_back(CppStmt::comment("contacts: restitution (per run); unilateral: the row's added normal "
                                               "acceleration (the runtime's impulse probe); "
                                               "compliant: Hunt-Crossley's chi / v-"));
  c.private_members.push_back(CppStmt::line(fmt::format("double contact_restitution_[{}] = {{}};", n)));
  c.private_members.push_back(CppStmt::line(fmt::format("double contact_bias_[{}] = {{}};", n)));
  c.private_members.push_back(CppStmt::line(fmt::format("double contact_damping_[{}] = {{}};", n)));
  if (tangents) {
    c.private_members.push_back(CppStmt::comment("unilateral contacts with friction: the slip direction while sliding (in the rows' tangent basis)"));
    c.private_members.push_back(CppStmt::line(fmt::format("double contact_slip_[{}][2] = {{}};", n)));
  }
}

void add_held_state_methods(CppClass& c, const ir::ReducedSystem& s) {
  if (s.events.empty() && s.contacts.empty()) return;
  const bool friction =
      std::any_of(s.contacts.begin(), s.contacts.end(), [](const ir::ContactRow& r) { return bool(r.friction); });
  // the members a run changes besides y, each a run of doubles
  std::vector<std::pair<std::string, std::size_t>> runs;
  if (!s.events.empty()) runs.emplace_back("mode_", s.events.size());
  if (!s.contacts.empty()) {
    runs.emplace_back("contact_bias_", s.contacts.size());
    runs.emplace_back("contact_damping_", s.contacts.size());
  }
  std::size_t size = 0;
  CppFunction get{"", "void get_held_state(double* out) const override", {}};
  CppFunction set{"", "void set_held_state(const double* in) override", {}};
  for (const auto& [member, count] : runs) {
    get.body.push_back(CppStmt::line(fmt::format("for (std::size_t k = 0; k < {}; ++k) out[{} + k] = {}[k];", count, size, member)));
    set.body.push_back(CppStmt::line(fmt::format("for (std::size_t k = 0; k < {}; ++k) {}[k] = in[{} + k];", count, member, size)));
    size += count;
  }
  if (friction) {  // the slip directions, two per contact
    const std::size_t n = s.contacts.size();
    get.body.push_back(CppStmt::line(fmt::format(
        "for (std::size_t k = 0; k < {}; ++k) out[{} + 2 * k] = contact_slip_[k][0], out[{} + 2 * k + 1] = contact_slip_[k][1];",
        n, size, size)));
    set.body.push_back(CppStmt::line(fmt::format(
        "for (std::size_t k = 0; k < {}; ++k) contact_slip_[k][0] = in[{} + 2 * k], contact_slip_[k][1] = in[{} + 2 * k + 1];",
        n, size, size)));
    size += 2 * n;
  }
  c.public_methods.push_back({"HELD STATE: what a run changes besides y (the event modes, what the runtime set of the "
                              "contacts), saved and restored with y (an FMU's state).",
                              "std::size_t held_state_size() const override",
                              {CppStmt::line(fmt::format("return {};", size))}});
  c.public_methods.push_back(std::move(get));
  c.public_methods.push_back(std::move(set));
}

}  // namespace mbgc::codegen
