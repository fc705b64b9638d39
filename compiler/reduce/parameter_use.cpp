// reduce/parameter_use.cpp — see parameter_use.hpp.
#include "reduce/parameter_use.hpp"

#include <unordered_set>

namespace mbgc::reduce {

using namespace mbgc::ir;

std::vector<bool> parameters_read(const ReducedSystem& s) {
  std::unordered_set<int> read;
  const auto add = [&read](const Expr& e) {
    if (e) collect_params(e, read);
  };
  const auto add_all = [&add](const std::vector<Expr>& es) {
    for (const Expr& e : es) add(e);
  };
  // what the simulator computes
  for (const Assignment& a : s.assignments) add(a.value);
  for (const LinearBlock& b : s.linear_blocks) {
    add_all(b.a);
    add_all(b.b);
  }
  add_all(s.state_derivative);
  add_all(s.nominal);
  add_all(s.jacobian);
  for (const Residual& r : s.residuals) add(r.value);
  for (const StateVar& st : s.states) add(st.initial);
  for (const ConstraintRow& c : s.constraints) {
    add(c.g);
    add(c.gdot);
  }
  for (const ReducedSystem::JacobianEntry& j : s.constraint_jacobian) add(j.value);
  for (const auto* terms : {&s.energy.stored, &s.energy.supplied, &s.energy.absorbed})
    for (const EnergyTerm& t : *terms) add(t.value);
  for (const EventRelation& e : s.events) {
    add(e.step);
    add(e.arg);
  }
  for (const ContactRow& c : s.contacts) {
    for (const Expr* e : {&c.gap, &c.rate, &c.normal_force, &c.restitution, &c.friction, &c.tangent_rate[0],
                          &c.tangent_rate[1], &c.tangent_force[0], &c.tangent_force[1]})
      add(*e);
  }
  // what the bond graph still holds: outputs, signals, drawings, the elements' laws and values
  const BondGraph& g = s.graph;
  for (const Output& o : g.outputs) add(o.value);
  for (const Signal& sig : g.signals) {
    add(sig.value);
    add(sig.rate);
  }
  for (const DrawnBody& d : g.drawings) d.for_each_expr(add);
  for (const GraphNode& n : g.nodes) {
    for (const Value* v : {&n.value, &n.constraint_g, &n.initial}) add_all(v->items);
    add_all(n.law_rhs);
  }
  // through the parameters that read others (each reads only earlier ones)
  std::vector<bool> out(g.params.size(), false);
  for (std::size_t i = g.params.size(); i-- > 0;) {
    if (!read.count(static_cast<int>(i))) continue;
    out[i] = true;
    add(g.params[i].value);
  }
  return out;
}

}  // namespace mbgc::reduce
