// reduce/energy.cpp — see energy.hpp.
#include "reduce/energy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace mbgc::reduce {

using namespace mbgc::ir;

namespace {

/// e . f of bond b, the power along its direction.
Expr bond_power(const BondGraph& g, int b) {
  const Bond& bond = g.bonds[static_cast<std::size_t>(b)];
  Expr sum;
  for (int k = 0; k < bond.dim; ++k) {
    const Expr term = mul(var(bond.effort_vars[static_cast<std::size_t>(k)]), var(bond.flow_vars[static_cast<std::size_t>(k)]));
    sum = sum ? add(sum, term) : term;
  }
  return sum ? sum : constant(0);
}

/// The power into element n (out of it, for a source): its bonds' powers
/// with the element's sign convention (ir::flow_sign).
Expr element_power(const BondGraph& g, int n) {
  Expr sum;
  for (int b : g.nodes[static_cast<std::size_t>(n)].bonds) {
    Expr p = bond_power(g, b);
    if (flow_sign(g, n, b) < 0) p = neg(p);
    sum = sum ? add(sum, p) : p;
  }
  return sum ? sum : constant(0);
}

/// 1/2 x . y over a storage's components: x its states, y its bond's
/// co-variables (the flow of an I, the effort of a C) with its sign.
Expr half_dot(const BondGraph& g, int n) {
  const GraphNode& nd = g.nodes[static_cast<std::size_t>(n)];
  const int b = nd.bonds.front();
  const Bond& bond = g.bonds[static_cast<std::size_t>(b)];
  const std::vector<int>& co = nd.kind == NodeKind::I ? bond.flow_vars : bond.effort_vars;
  Expr sum;
  for (std::size_t k = 0; k < nd.state_vars.size() && k < co.size(); ++k) {
    const Expr term = mul(var(nd.state_vars[k]), var(co[k]));
    sum = sum ? add(sum, term) : term;
  }
  if (!sum) return constant(0);
  // the I's own flow is flow_sign x the bond's (efforts carry no sign)
  if (nd.kind == NodeKind::I && flow_sign(g, n, b) < 0) sum = neg(sum);
  return mul(constant(0.5), sum);
}

/// 1/2 y . V y for a storage without a state of its own (derivative
/// causality: a body's momentum that follows from its joint's rate), y its
/// bond's co-variables and V its linear law's modulus (p = I f, q = C e): a
/// scalar for every component, a diagonal or a matrix.
Expr half_quadratic(const BondGraph& g, int n) {
  const GraphNode& nd = g.nodes[static_cast<std::size_t>(n)];
  const Bond& bond = g.bonds[static_cast<std::size_t>(nd.bonds.front())];
  const std::vector<int>& co = nd.kind == NodeKind::I ? bond.flow_vars : bond.effort_vars;
  const Value& v = nd.value;
  const int d = static_cast<int>(co.size());
  auto modulus = [&](int j, int k) -> Expr {
    if (v.is_scalar()) return j == k ? v.items[0] : nullptr;
    if (v.rows == d && v.cols == d) return v.at(j, k);
    return j == k && v.length() == d ? v.items[static_cast<std::size_t>(j)] : nullptr;
  };
  Expr sum;
  for (int j = 0; j < d; ++j)
    for (int k = 0; k < d; ++k) {
      const Expr m = modulus(j, k);
      if (!m || is_zero(m)) continue;
      const Expr t = mul(m, mul(var(co[static_cast<std::size_t>(j)]), var(co[static_cast<std::size_t>(k)])));
      sum = sum ? add(sum, t) : t;
    }
  return sum ? mul(constant(0.5), sum) : constant(0);
}

/// A linear law whose modulus reads a variable or the time (a modulated
/// storage: a flexible body's geometric stiffness, which follows its spin):
/// 1/2 q.e is then not its energy's integral, and the signal that modulates
/// it carries no power in the graph.
bool modulated(const GraphNode& nd) {
  return std::any_of(nd.value.items.begin(), nd.value.items.end(), [](const Expr& x) {
    std::unordered_set<int> read;
    if (x) collect_vars(x, read);
    return x && (!read.empty() || depends_on_time(x));
  });
}

EnergyTerm term(const GraphNode& nd, Expr value, std::string what) {
  return EnergyTerm{std::move(value), nd.loc, fmt::format("{} {}: {}", node_kind_name(nd.kind), nd.name, what)};
}

}  // namespace

void energy_balance(ReducedSystem& s) {
  const BondGraph& g = s.graph;
  EnergyBalance& e = s.energy;
  e = EnergyBalance{};
  std::unordered_set<int> has_state;
  for (const StateVar& st : s.states) has_state.insert(st.node);
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    const int n = static_cast<int>(i);
    const GraphNode& nd = g.nodes[i];
    if (is_junction(nd.kind) || is_two_port(nd.kind) || nd.bonds.empty()) continue;  // they conserve it
    switch (nd.kind) {
      case NodeKind::Se:
      case NodeKind::Sf:
        // (a free joint rate's Sf keeps its effort at zero: no power)
        if (nd.law != LawForm::FreeRate) e.supplied.push_back(term(nd, element_power(g, n), "power out, e.f"));
        break;
      case NodeKind::I:
      case NodeKind::C:
        if (nd.law == LawForm::Linear && nd.bonds.size() == 1 && !modulated(nd)) {
          const bool i = nd.kind == NodeKind::I;
          if (has_state.count(n))
            e.stored.push_back(term(nd, half_dot(g, n), i ? "1/2 p.f" : "1/2 q.e"));
          else  // derivative causality
            e.stored.push_back(term(nd, half_quadratic(g, n), i ? "1/2 f.I f" : "1/2 e.C e"));
        } else if (!nd.law_rhs.empty() &&
                   std::all_of(nd.law_rhs.begin(), nd.law_rhs.end(), [](const Expr& x) { return x && is_zero(x); })) {
          // e = 0 (f = 0): a pure integrator, a body's position or a joint's
          // angle with no spring; it holds nothing and takes nothing
        } else {
          const char* why = nd.law == LawForm::Linear ? "a modulated law" : "a nonlinear law";
          e.absorbed.push_back(term(nd, element_power(g, n), fmt::format("power in, e.f ({})", why)));
          e.unwitnessed.push_back(fmt::format("{} {}: {}, counted by the power into it", node_kind_name(nd.kind), nd.name, why));
        }
        break;
      default:  // R, CN: dissipators, constraints, contacts
        e.absorbed.push_back(term(nd, element_power(g, n), "power in, e.f"));
        break;
    }
  }
  // with nothing stored as a function of the state, the balance holds by
  // construction (the junctions conserve what the powers say) and witnesses nothing
  e.available = !e.stored.empty();
  if (!e.available) e.why_not = "every storage is counted by the power into it, so the balance would hold by construction";
}

void check_energy_inputs(ReducedSystem& s) {
  EnergyBalance& e = s.energy;
  if (!e.available) return;
  std::unordered_set<int> computed;
  for (const StateVar& st : s.states) computed.insert(st.var);
  for (int a : s.algebraic) computed.insert(a);
  for (const Assignment& a : s.assignments) computed.insert(a.var);
  for (const ContactRow& c : s.contacts)
    for (int id : {c.closed, c.bias, c.damping, c.stick, c.slip1, c.slip2})
      if (id >= 0) computed.insert(id);
  // a DAE's residual() reads y' as well; stored_energy() may not (the
  // runtime evaluates it where it has no y', at an event's jump)
  std::unordered_set<int> with_rates = computed;
  for (int id : s.derivative_unknowns)
    if (id >= 0) with_rates.insert(id);
  for (const std::vector<EnergyTerm>* list : {&e.stored, &e.supplied, &e.absorbed})
    for (const EnergyTerm& t : *list) {
      std::unordered_set<int> read;
      collect_vars(t.value, read);
      for (int id : read) {
        if ((list == &e.stored ? computed : with_rates).count(id)) continue;
        e.available = false;
        e.why_not = fmt::format("{} reads `{}`, which no generated method computes", t.origin,
                                s.graph.vars[static_cast<std::size_t>(id)].name);
        return;
      }
    }
  // ... nor through the assignments the stored energy needs
  std::unordered_map<int, const Assignment*> assignment_of;
  for (const Assignment& a : s.assignments) assignment_of[a.var] = &a;
  std::unordered_set<int> seen, rates(s.derivative_unknowns.begin(), s.derivative_unknowns.end());
  std::vector<int> work;
  for (const EnergyTerm& t : e.stored) {
    std::unordered_set<int> read;
    collect_vars(t.value, read);
    work.insert(work.end(), read.begin(), read.end());
  }
  while (!work.empty()) {
    const int id = work.back();
    work.pop_back();
    if (!seen.insert(id).second) continue;
    if (rates.count(id)) {
      e.available = false;
      e.why_not = fmt::format("the stored energy reads `{}`, a rate only the residual has",
                              s.graph.vars[static_cast<std::size_t>(id)].name);
      return;
    }
    auto it = assignment_of.find(id);
    if (it == assignment_of.end()) continue;
    std::unordered_set<int> inputs;
    assignment_inputs(s, *it->second, inputs);
    work.insert(work.end(), inputs.begin(), inputs.end());
  }
}

}  // namespace mbgc::reduce
