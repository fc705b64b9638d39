// reduce/slice.cpp — see slice.hpp.
#include "reduce/slice.hpp"

#include <fmt/format.h>

#include <map>
#include <set>
#include <unordered_set>

namespace mbgc::ir {

void assignment_inputs(const ReducedSystem& s, const Assignment& a, std::unordered_set<int>& out) {
  if (a.block < 0) {
    collect_vars(a.value, out);
    return;
  }
  const LinearBlock& lb = s.linear_blocks[static_cast<std::size_t>(a.block)];
  std::vector<Expr> all(lb.a);
  all.insert(all.end(), lb.b.begin(), lb.b.end());
  collect_vars(all, out);
  for (int u : lb.unknowns) out.erase(u);
}

}  // namespace mbgc::ir

namespace mbgc::reduce {

using namespace mbgc::ir;

void slice(ReducedSystem& s) {
  std::map<int, int> assignment_of;
  for (std::size_t i = 0; i < s.assignments.size(); ++i) assignment_of[s.assignments[i].var] = static_cast<int>(i);
  auto needed_by = [&](const std::vector<Expr>& roots) {
    std::set<int> need;
    std::vector<int> work;
    std::unordered_set<int> root_vars;
    collect_vars(roots, root_vars);  // one walk over all roots: they share sub-expressions
    for (int id : root_vars) {
      auto it = assignment_of.find(id);
      if (it != assignment_of.end() && need.insert(it->second).second) work.push_back(it->second);
    }
    std::set<int> blocks_read;
    while (!work.empty()) {
      int i = work.back();
      work.pop_back();
      const Assignment& a = s.assignments[static_cast<std::size_t>(i)];
      if (a.block >= 0 && !blocks_read.insert(a.block).second) continue;  // same inputs as its first unknown
      std::unordered_set<int> inputs;
      assignment_inputs(s, a, inputs);
      for (int id : inputs) {
        auto it = assignment_of.find(id);
        if (it != assignment_of.end() && need.insert(it->second).second) work.push_back(it->second);
      }
    }
    return std::vector<int>(need.begin(), need.end());  // assignment order = sorted order
  };
  std::vector<Expr> deriv_roots = s.state_derivative;
  for (const Residual& r : s.residuals) deriv_roots.push_back(r.value);
  std::vector<Expr> energy_roots, power_roots;
  if (s.energy.available) {
    for (const EnergyTerm& t : s.energy.stored) energy_roots.push_back(t.value);
    for (const EnergyTerm& t : s.energy.supplied) power_roots.push_back(t.value);
    for (const EnergyTerm& t : s.energy.absorbed) power_roots.push_back(t.value);
  }
  std::vector<Expr> output_roots;
  for (const Output& o : s.graph.outputs) output_roots.push_back(o.value);
  std::vector<Expr> drawing_roots;
  for (const DrawnBody& d : s.graph.drawings) d.for_each_expr([&](const Expr& e) { drawing_roots.push_back(e); });
  std::vector<Expr> constraint_roots;
  for (const ConstraintRow& row : s.constraints) {
    constraint_roots.push_back(row.gdot);
    constraint_roots.push_back(row.g);  // (a cut joint's g reads the tree's pose signals)
  }
  std::vector<Expr> constraint_jacobian_roots;
  for (const ReducedSystem::JacobianEntry& e : s.constraint_jacobian) constraint_jacobian_roots.push_back(e.value);
  std::vector<Expr> event_roots;
  for (const EventRelation& ev : s.events) event_roots.push_back(ev.arg);
  std::vector<Expr> contact_roots, tangent_roots;
  for (const ContactRow& c : s.contacts) {
    contact_roots.push_back(c.rate);
    for (const Expr& x : c.tangent_rate)
      if (x) tangent_roots.push_back(x);
    for (const Expr& x : c.tangent_force)
      if (x) tangent_roots.push_back(x);
  }
  s.for_derivative = needed_by(deriv_roots);
  std::vector<Expr> position_roots;  // (the q of a C: UnknownRole::position, codegen/identity.cpp)
  for (std::size_t i = 0; i < s.states.size() && !s.dae; ++i)
    if (is_position_state(s, i)) position_roots.push_back(s.state_derivative[i]);
  s.for_position_rates = needed_by(position_roots);
  s.for_outputs = needed_by(output_roots);
  s.for_drawings = needed_by(drawing_roots);
  s.for_jacobian = needed_by(s.jacobian);
  s.for_constraints = needed_by(constraint_roots);
  s.for_constraint_jacobian = needed_by(constraint_jacobian_roots);
  s.for_events = needed_by(event_roots);
  s.for_contacts = needed_by(contact_roots);
  s.for_tangents = needed_by(tangent_roots);
  s.for_energy = needed_by(energy_roots);
  s.for_power = needed_by(power_roots);
  const std::vector<std::vector<int>*> slices = {&s.for_derivative,  &s.for_position_rates, &s.for_outputs,  &s.for_jacobian,
                                                 &s.for_constraints, &s.for_constraint_jacobian,
                                                 &s.for_events,      &s.for_contacts, &s.for_tangents, &s.for_drawings,
                                                 &s.for_energy,      &s.for_power};
  std::set<int> used;
  for (const std::vector<int>* sl : slices) used.insert(sl->begin(), sl->end());
  // Drop what nobody needs; renumber the slices.
  std::vector<Assignment> kept;
  std::map<int, int> renumber;
  for (std::size_t i = 0; i < s.assignments.size(); ++i) {
    if (!used.count(static_cast<int>(i))) continue;
    renumber[static_cast<int>(i)] = static_cast<int>(kept.size());
    kept.push_back(s.assignments[i]);
  }
  std::size_t dropped = s.assignments.size() - kept.size();
  s.assignments = std::move(kept);
  for (std::vector<int>* sl : slices)
    for (int& i : *sl) i = renumber.at(i);
  s.log.push_back(fmt::format("dead-equation removal: {} assignment{} nothing needs removed", dropped, dropped == 1 ? "" : "s"));
}

}  // namespace mbgc::reduce
