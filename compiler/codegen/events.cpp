// codegen/events.cpp — see events.hpp.
#include "codegen/events.hpp"

#include <fmt/format.h>

#include "codegen/identity.hpp"
#include "codegen/names.hpp"

namespace mbgc::codegen {

std::string event_mode_name(std::size_t k) { return fmt::format("mode_[{}]", k); }

/// "heaviside(t - t_off) (time event), Sf src (events.mbg:15:4)"
static std::string event_name(const ir::EventRelation& ev, const ir::Namer& names,
                              const std::function<std::string(const ir::SourceLoc&)>& where) {
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

}  // namespace mbgc::codegen
