// codegen/constraints.cpp — see constraints.hpp.
#include "codegen/constraints.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <map>
#include <string>
#include <vector>

#include "codegen/names.hpp"

namespace mbgc::codegen {

using namespace mbgc::ir;

/// Where each CN row's multipliers sit in y (lagrange rows; -1 for penalty
/// rows): lambda (its residual row is gdot = 0) and the GGL mu (g = 0). The
/// runtime needs them to hold the multipliers of redundant rows at zero.
static void multiplier_indices(CppClass& c, const ReducedSystem& s) {
  std::map<int, std::size_t> index_of;
  for (std::size_t i = 0; i < s.algebraic.size(); ++i) index_of[s.algebraic[i]] = s.states.size() + i;
  auto table = [&](const char* method, const char* doc, auto member) {
    std::vector<std::string> list;
    for (const ConstraintRow& r : s.constraints) {
      auto it = index_of.find(r.*member);
      list.push_back(it == index_of.end() ? "-1" : std::to_string(it->second));
    }
    c.public_methods.push_back(
        {doc, fmt::format("long {}(std::size_t row) const override", method),
         {CppStmt::line(fmt::format("static const long kIndex[] = {{{}}};", fmt::join(list, ", "))),
          CppStmt::line(fmt::format("return row < {} ? kIndex[row] : -1;", list.size()))}});
  };
  table("multiplier_index", "index in y of CN row `row`'s multiplier lambda (-1: penalty row)", &ConstraintRow::multiplier);
  table("stabiliser_index", "index in y of CN row `row`'s GGL multiplier mu (-1: penalty row)", &ConstraintRow::stabiliser);
}

void add_constraint_methods(CppClass& c, const ReducedSystem& s) {
  std::size_t n = s.constraints.size();
  // A model may mix strategies per joint: any lagrange row makes it a DAE
  // whose drift is what the runtime reports.
  bool enforced = std::any_of(s.constraints.begin(), s.constraints.end(),
                              [](const ConstraintRow& r) { return r.multiplier >= 0; });
  if (s.dae)
    c.public_methods.push_back({"", "std::size_t state_count() const override", {CppStmt::line(fmt::format("return {};", s.states.size()))}});
  c.public_methods.push_back({"", "std::size_t position_constraint_count() const override", {CppStmt::line(fmt::format("return {};", n))}});
  c.public_methods.push_back({"", "std::size_t velocity_constraint_count() const override", {CppStmt::line(fmt::format("return {};", n))}});
  c.public_methods.push_back({enforced ? "lagrange: the DAE enforces the constraints; the runtime reports their drift."
                                       : "penalty: the constraints are only pulled back; the runtime reports the violation.",
                              "bool constraints_enforced() const override", {CppStmt::line(enforced ? "return true;" : "return false;")}});
  if (std::any_of(s.constraints.begin(), s.constraints.end(), [](const ConstraintRow& r) { return r.cut; })) {
    std::vector<std::string> held;
    for (const ConstraintRow& r : s.constraints) held.push_back(r.cut || r.multiplier >= 0 ? "true" : "false");
    c.public_methods.push_back({"cut joints: their rows are held (Baumgarte), a penalty's only pulled back.",
                                "bool constraint_held(std::size_t row) const override",
                                {CppStmt::line(fmt::format("static const bool kHeld[] = {{{}}};", fmt::join(held, ", "))),
                                 CppStmt::line(fmt::format("return row < {} && kHeld[row];", n))}});
  }
  CppFunction names{"", "std::string constraint_name(std::size_t i) const override", {}};
  std::vector<std::string> list;
  for (const ConstraintRow& r : s.constraints) list.push_back(cpp_string(r.name + " g"));
  for (const ConstraintRow& r : s.constraints) list.push_back(cpp_string(r.name + " gdot"));
  names.body.push_back(CppStmt::line(fmt::format("static const char* const kConstraintNames[] = {{{}}};", fmt::join(list, ", "))));
  names.body.push_back(CppStmt::line(fmt::format("return i < {} ? kConstraintNames[i] : \"?\";", 2 * n)));
  c.public_methods.push_back(names);
  if (s.dae) multiplier_indices(c, s);
}

}  // namespace mbgc::codegen
