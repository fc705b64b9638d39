// codegen/energy.cpp — see energy.hpp.
#include "codegen/energy.hpp"

#include <fmt/format.h>

#include <optional>

#include "codegen/names.hpp"

namespace mbgc::codegen {

using namespace mbgc::ir;

namespace {

Expr sum_of(const std::vector<EnergyTerm>& terms) {
  Expr sum;
  for (const EnergyTerm& t : terms) sum = sum ? add(sum, t.value) : t.value;
  return sum ? sum : constant(0);
}

/// "Se gravity (pendulum.mbg:12:3), R damper (...)", the first few and a count.
std::string names_of(const std::vector<EnergyTerm>& terms, const Where& where) {
  constexpr std::size_t kShown = 4;
  std::string out;
  for (std::size_t i = 0; i < terms.size() && i < kShown; ++i) {
    if (i) out += ", ";
    out += terms[i].origin.substr(0, terms[i].origin.find(':'));
    out += " (" + where(terms[i].loc) + ")";
  }
  if (terms.size() > kShown) out += fmt::format(" and {} more", terms.size() - kShown);
  return terms.empty() ? "none" : out;
}

}  // namespace

Expr stored_energy_value(const ReducedSystem& s) { return sum_of(s.energy.stored); }

std::vector<Expr> power_values(const ReducedSystem& s) { return {sum_of(s.energy.supplied), sum_of(s.energy.absorbed)}; }

void add_energy_methods(CppClass& c, const ReducedSystem& s, const Where& where, std::optional<EnergyMethods> methods) {
  const EnergyBalance& e = s.energy;
  std::string note = e.available ? "" : e.why_not;
  for (const std::string& u : e.unwitnessed) note += (note.empty() ? "" : "; ") + u;
  if (!note.empty())
    c.public_methods.push_back({"What the energy balance leaves out, or why there is none.",
                                "std::string energy_note() const override",
                                {CppStmt::line(fmt::format("return {};", cpp_string(note)))}});
  if (!e.available || !methods) return;
  c.public_methods.push_back({"ENERGY WITNESS: stored_energy() and power() below (reduce/energy.hpp).",
                              "bool has_energy_balance() const override", {CppStmt::line("return true;")}});
  auto headed = [](CppFunction f, std::string comment) {
    f.body.insert(f.body.begin(), CppStmt::comment(std::move(comment)));
    return f;
  };
  c.public_methods.push_back(headed(std::move(methods->stored), fmt::format("H: the energy of {}", names_of(e.stored, where))));
  c.public_methods.push_back(headed(std::move(methods->power),
                                    fmt::format("out[0]: the power of {}; out[1]: the power into {}",
                                                names_of(e.supplied, where), names_of(e.absorbed, where))));
}

}  // namespace mbgc::codegen
