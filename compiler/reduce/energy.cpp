// reduce/energy.cpp — see energy.hpp.
#include "reduce/energy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
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

/// Entry (j, k) of a d-component linear law's modulus: a scalar for every
/// component, a diagonal or a matrix (nullptr where it is zero by shape).
Expr modulus_at(const Value& v, int d, int j, int k) {
  if (v.is_scalar()) return j == k ? v.items[0] : nullptr;
  if (v.rows == d && v.cols == d) return v.at(j, k);
  return j == k && v.length() == d ? v.items[static_cast<std::size_t>(j)] : nullptr;
}

/// 1/2 y . V y over a storage's bond co-variables y (the flow of an I, the
/// effort of a C), V(j, k) given by `entry` (nullptr: zero).
Expr half_quadratic_form(const BondGraph& g, int n, const std::function<Expr(int, int)>& entry) {
  const GraphNode& nd = g.nodes[static_cast<std::size_t>(n)];
  const Bond& bond = g.bonds[static_cast<std::size_t>(nd.bonds.front())];
  const std::vector<int>& co = nd.kind == NodeKind::I ? bond.flow_vars : bond.effort_vars;
  const int d = static_cast<int>(co.size());
  Expr sum;
  for (int j = 0; j < d; ++j)
    for (int k = 0; k < d; ++k) {
      const Expr m = entry(j, k);
      if (!m || is_zero(m)) continue;
      const Expr t = mul(m, mul(var(co[static_cast<std::size_t>(j)]), var(co[static_cast<std::size_t>(k)])));
      sum = sum ? add(sum, t) : t;
    }
  return sum ? mul(constant(0.5), sum) : constant(0);
}

/// 1/2 y . V y for a storage without a state of its own (derivative
/// causality: a body's momentum that follows from its joint's rate), V its
/// linear law's modulus (p = I f, q = C e).
Expr half_quadratic(const BondGraph& g, int n) {
  const GraphNode& nd = g.nodes[static_cast<std::size_t>(n)];
  const int d = g.bonds[static_cast<std::size_t>(nd.bonds.front())].dim;
  return half_quadratic_form(g, n, [&](int j, int k) { return modulus_at(nd.value, d, j, k); });
}

/// The rate of every C's displacement: dq/dt is its bond's flow (with the
/// C's sign), the storage law every C keeps.
std::unordered_map<int, Expr> displacement_rates(const BondGraph& g) {
  std::unordered_map<int, Expr> rate;
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    const GraphNode& nd = g.nodes[i];
    if (nd.kind != NodeKind::C || nd.bonds.size() != 1) continue;
    const int b = nd.bonds.front();
    const Bond& bond = g.bonds[static_cast<std::size_t>(b)];
    const double sign = flow_sign(g, static_cast<int>(i), b);
    for (std::size_t k = 0; k < nd.state_vars.size() && k < bond.flow_vars.size(); ++k)
      rate.emplace(nd.state_vars[k], mul(constant(sign), var(bond.flow_vars[k])));
  }
  return rate;
}

/// A modulated inertia, p = M(q) f (a flexible body's mass matrix over its
/// modal coordinates): it still holds 1/2 f.M f (= 1/2 p.f), and besides
/// the power e.f into it that energy changes by 1/2 f.(dM/dt) f through the
/// modulation, a power the balance takes out as absorbed. dM/dt = sum over
/// the variables M reads of dM/dv dv/dt, + dM/dt for the time: found when M
/// reads only C displacements (their rates are flows) and the time, else
/// nullptr (and the inertia is counted by the power into it). The power into
/// such an inertia is its whole dynamics (e = dp/dt, the accelerations);
/// this needs only velocities.
Expr modulation_power(const BondGraph& g, int n, const std::unordered_map<int, Expr>& rate) {
  const GraphNode& nd = g.nodes[static_cast<std::size_t>(n)];
  const Bond& bond = g.bonds[static_cast<std::size_t>(nd.bonds.front())];
  const int d = static_cast<int>(bond.flow_vars.size());
  std::vector<Expr> dm(static_cast<std::size_t>(d * d));
  for (int j = 0; j < d; ++j)
    for (int k = 0; k < d; ++k) {
      const Expr m = modulus_at(nd.value, d, j, k);
      if (!m) continue;
      std::unordered_set<int> read;
      collect_vars(m, read);
      Expr sum = diff_time(m);
      for (int v : read) {
        auto it = rate.find(v);
        if (it == rate.end()) return nullptr;
        sum = add(sum, mul(diff_var(m, v), it->second));
      }
      dm[static_cast<std::size_t>(j * d + k)] = sum;
    }
  return half_quadratic_form(g, n, [&](int j, int k) { return dm[static_cast<std::size_t>(j * d + k)]; });
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

/// Every variable of the motion an Se's effort may follow (the bonds' flows,
/// the inertias' momenta and the free joint rates), or, for an Sf's flow, the bonds' efforts, each
/// mapped to 0. (Positions stay: a body's pose is the C states it integrates.)
std::unordered_map<int, Expr> motion_at_rest(const BondGraph& g, NodeKind source) {
  const bool se = source == NodeKind::Se;
  std::unordered_map<int, Expr> zero;
  for (const Bond& b : g.bonds)
    for (int v : se ? b.flow_vars : b.effort_vars) zero.emplace(v, constant(0));
  if (se)  // ... and the independent joint rates of a tree in joint coordinates
    for (const GraphNode& nd : g.nodes)
      if (nd.kind == NodeKind::I || nd.law == LawForm::FreeRate)
        for (int v : nd.state_vars) zero.emplace(v, constant(0));
  return zero;
}

/// Is e defined where it was evaluated at rest: no division by a zero, no
/// zero to a power below one (a Coulomb friction's v / |v| is not, at rest).
bool defined_at_rest(const Expr& e) {
  std::unordered_set<const Node*> seen;
  std::function<bool(const Expr&)> ok = [&](const Expr& x) {
    if (!seen.insert(x.get()).second) return true;
    if (x->op == Op::Div && is_zero(x->args[1])) return false;
    if (x->op == Op::Pow && is_zero(x->args[0])) {
      double p = 0;
      if (!is_const(x->args[1], &p) || p < 1) return false;
    }
    return std::all_of(x->args.begin(), x->args.end(), ok);
  };
  return ok(e);
}

/// A source's power, split where its value follows the motion. A joint's
/// `torque = T - c * J.rate` or a force element's `damping` is written as an
/// Se but dissipates: with every flow at rest its effort is e0 (here T), and
/// e0 . f is supplied; the power of the part that follows the motion,
/// m = (e - e0) . f, is absorbed while it takes power (m < 0, here
/// -c * rate^2) and supplied while it gives (a coupling that feeds the
/// motion, like a turning vehicle's forward momentum): supplied e0.f +
/// max(m, 0), absorbed max(-m, 0), still summing to the source's e . f.
/// An Sf is split the same way over the efforts.
void source_terms(const BondGraph& g, int n, Substitution& at_rest, EnergyBalance& e) {
  const GraphNode& nd = g.nodes[static_cast<std::size_t>(n)];
  auto whole = [&](const char* what) { e.supplied.push_back(term(nd, element_power(g, n), what)); };
  if (nd.bonds.size() != 1 || nd.value.items.empty()) return whole("power out, e.f");
  const int b = nd.bonds.front();
  const Bond& bond = g.bonds[static_cast<std::size_t>(b)];
  const Expr sign = constant(flow_sign(g, n, b));
  const bool se = nd.kind == NodeKind::Se;
  Expr rest, moving;
  bool follows = false;
  for (int k = 0; k < bond.dim; ++k) {
    const Expr v = nd.value.is_scalar() ? nd.value.items[0] : nd.value.items[static_cast<std::size_t>(k)];
    const Expr v0 = at_rest(v);
    if (!defined_at_rest(v0)) return whole("power out, e.f (undefined at rest)");
    follows = follows || v0 != v;
    const Expr ek = var(bond.effort_vars[static_cast<std::size_t>(k)]);
    const Expr fk = mul(sign, var(bond.flow_vars[static_cast<std::size_t>(k)]));  // out of the source
    const Expr r = se ? mul(v0, fk) : mul(ek, v0);
    const Expr m = se ? mul(sub(ek, v0), fk) : mul(ek, sub(fk, v0));
    rest = rest ? add(rest, r) : r;
    moving = moving ? add(moving, m) : m;
  }
  if (!follows) return whole("power out, e.f");
  const char* split = se ? "e0.f + max((e - e0).f, 0)" : "e.f0 + max(e.(f - f0), 0)";
  e.supplied.push_back(term(nd, add(rest, call(Fn::Max, {moving, constant(0)})), fmt::format("power out, {}", split)));
  e.absorbed.push_back(term(nd, call(Fn::Max, {neg(moving), constant(0)}),
                            se ? "power in, max(-(e - e0).f, 0) (its value follows the motion)"
                               : "power in, max(-e.(f - f0), 0) (its value follows the motion)"));
}

}  // namespace

void energy_balance(ReducedSystem& s) {
  const BondGraph& g = s.graph;
  EnergyBalance& e = s.energy;
  e = EnergyBalance{};
  std::unordered_set<int> has_state;
  for (const StateVar& st : s.states) has_state.insert(st.node);
  const std::unordered_map<int, Expr> rates = displacement_rates(g);
  Substitution se_at_rest(motion_at_rest(g, NodeKind::Se)), sf_at_rest(motion_at_rest(g, NodeKind::Sf));
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    const int n = static_cast<int>(i);
    const GraphNode& nd = g.nodes[i];
    if (is_junction(nd.kind) || is_two_port(nd.kind) || nd.bonds.empty()) continue;  // they conserve it
    switch (nd.kind) {
      case NodeKind::Se:
      case NodeKind::Sf:
        // (a free joint rate's Sf keeps its effort at zero: no power)
        if (nd.law != LawForm::FreeRate) source_terms(g, n, nd.kind == NodeKind::Se ? se_at_rest : sf_at_rest, e);
        break;
      case NodeKind::I:
      case NodeKind::C:
        if (nd.kind == NodeKind::I && nd.law == LawForm::Linear && nd.bonds.size() == 1 && modulated(nd)) {
          if (Expr p = modulation_power(g, n, rates)) {
            if (has_state.count(n))
              e.stored.push_back(term(nd, half_dot(g, n), "1/2 p.f (a modulated law)"));
            else  // derivative causality
              e.stored.push_back(term(nd, half_quadratic(g, n), "1/2 f.M f (a modulated law)"));
            e.absorbed.push_back(term(nd, p, "power out through the modulation, 1/2 f.(dM/dt) f"));
            break;
          }
        }
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
