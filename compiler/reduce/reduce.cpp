#include "reduce/reduce.hpp"

#include "mbgrt/integrators.hpp"
#include "reduce/constraint_jacobian.hpp"
#include "reduce/events.hpp"
#include "reduce/forward_diff.hpp"
#include "reduce/energy.hpp"
#include "reduce/nominal.hpp"
#include "reduce/slice.hpp"
#include "reduce/sparsity.hpp"
#include "reduce/tree_elimination.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <functional>
#include <map>
#include <set>

namespace mbgc::reduce {
namespace {

using namespace mbgc::ir;

class Reducer {
 public:
  Reducer(EquationSystem& sys, ReducedSystem& out, Diagnostics& diags, bool energy_witness)
      : sys_(sys), out_(out), diags_(diags), energy_witness_(energy_witness) {}

  void run() {
    out_.graph = std::move(sys_.graph);
    out_.causality = std::move(sys_.causality);
    out_.states = sys_.states;
    out_.constraints = std::move(sys_.constraints);
    out_.contacts = std::move(sys_.contacts);
    eqs_ = std::move(sys_.equations);
    for (const StateVar& s : out_.states) known_.insert(s.var);
    for (const ContactRow& c : out_.contacts) {
      for (int id : {c.closed, c.bias, c.damping, c.stick, c.slip1, c.slip2})
        if (id >= 0) known_.insert(id);  // discrete: the runtime sets them
      if (!c.compliant) collect_vars(c.normal_force, contact_multipliers_);
      if (c.friction)
        for (const Expr& f : c.tangent_force) collect_vars(f, contact_multipliers_);
    }
    for (const Signal& s : out_.graph.signals)
      if (s.rate) rate_of_[s.var] = s.rate;
    if (!check_each_unknown_once()) return;
    if (energy_witness_)
      energy_balance(out_);  // in the graph's variables: alias elimination resolves it
    else
      out_.energy.why_not = "compiled without it (mbgc --no-energy-witness)";
    eliminate_aliases();
    if (!expand_derivatives()) return;
    sort_and_solve();
    if (diags_.has_errors()) return;
    differentiate_for_jacobian();
    steps_for_time_kinks(out_);
    differentiate_constraints();
    out_.events = find_events(out_);
    check_energy_inputs(out_);
    slice(out_);
  }

 private:
  const Variable& v(int id) const { return out_.graph.vars[static_cast<std::size_t>(id)]; }

  bool check_each_unknown_once() {
    std::map<int, int> count;
    for (const Equation& e : eqs_) ++count[e.unknown];
    for (const auto& [var, c] : count) {
      if (c > 1) {
        diags_.error(v(var).loc, fmt::format("internal error: `{}` is computed by {} equations", v(var).name, c),
                     "please report this model to the mbgc developers");
        return false;
      }
    }
    return true;
  }

  // ---- 2. aliases -----------------------------------------------------------------
  /// If e is ±var, the var id and sign.
  static bool as_signed_var(const Expr& e, int* id, int* sign) {
    if (e->op == Op::Var) { *id = e->id; *sign = 1; return true; }
    if (e->op == Op::Neg && e->args[0]->op == Op::Var) { *id = e->args[0]->id; *sign = -1; return true; }
    return false;
  }

  /// Constants, propagated: an equation whose solution folds to a constant
  /// (a zero force component, a velocity no joint can produce) makes its
  /// unknown a constant, and each equation that reads it is folded again
  /// (a zero coefficient may now cancel a variable). Every equation is tried
  /// once, then once per variable of it that turns constant.
  void propagate_constants(std::unordered_map<int, Expr>& constant_of) {
    const std::size_t n = eqs_.size();
    std::unordered_map<int, std::vector<int>> readers;
    std::vector<int> ready;
    for (std::size_t i = n; i-- > 0;) {
      std::unordered_set<int> vars;
      collect_vars(eqs_[i].lhs, vars);
      collect_vars(eqs_[i].rhs, vars);
      for (int id : vars)
        if (id != eqs_[i].unknown && !known_.count(id)) readers[id].push_back(static_cast<int>(i));
      if (!eqs_[i].constraint || eqs_[i].in_loop) ready.push_back(static_cast<int>(i));
    }
    const auto fold = [&](const Expr& e) {
      return rewrite(e, [&](const Expr& x) -> Expr {
        if (x->op != Op::Var) return nullptr;
        auto it = constant_of.find(x->id);
        return it == constant_of.end() ? nullptr : it->second;
      });
    };
    while (!ready.empty()) {
      const Equation& eq = eqs_[static_cast<std::size_t>(ready.back())];
      ready.pop_back();
      if (constant_of.count(eq.unknown)) continue;
      Equation folded = eq;
      folded.lhs = fold(eq.lhs);
      folded.rhs = fold(eq.rhs);
      if (eq.constraint) {  // a cut joint's row (in_loop)
        // A row that holds identically (a planar loop's out-of-plane rows,
        // once the geometry is folded) is redundant: its multiplier is 0.
        if (!is_zero(sub(folded.lhs, folded.rhs))) continue;
        constant_of[eq.unknown] = constant(0);
        out_.log.push_back(fmt::format("redundant constraint row: the row of multiplier `{}` ({}) holds identically "
                                       "(its rate is 0 in every configuration): the multiplier is 0",
                                       v(eq.unknown).name, eq.origin));
      } else {
        auto sol = solve_single(folded);
        if (!sol || !is_const(*sol)) continue;
        constant_of[eq.unknown] = *sol;
      }
      ++constants_;
      for (int r : readers[eq.unknown]) ready.push_back(r);
    }
  }

  void eliminate_aliases() {
    std::unordered_map<int, Expr> alias;
    propagate_constants(alias);
    std::vector<Equation> kept;
    std::function<Expr(const Expr&)> resolve = [&](const Expr& e) {
      return rewrite(e, [&](const Expr& n) -> Expr {
        if (n->op != Op::Var) return nullptr;
        auto it = alias.find(n->id);
        return it == alias.end() ? nullptr : resolve(it->second);
      });
    };
    for (Equation& eq : eqs_) {
      if (alias.count(eq.unknown)) continue;  // a constant
      int a = -1, sa = 0, b = -1, sb = 0;
      if (as_signed_var(eq.lhs, &a, &sa) && as_signed_var(eq.rhs, &b, &sb) && a != b &&
          (eq.unknown == a || eq.unknown == b)) {
        int unknown = eq.unknown, other = eq.unknown == a ? b : a;
        // unknown = (sa*sb) * other
        Expr target = resolve(sa * sb > 0 ? var(other) : neg(var(other)));
        if (!mentions_var(target, unknown)) {
          alias[unknown] = target;
          ++aliases_;
          continue;
        }
      }
      kept.push_back(std::move(eq));
    }
    // The aliases are complete: resolve is now a function of the node alone,
    // remembered across all equations (they share a body's sub-expressions).
    // The memo keeps its keys alive, so that no new node can reuse an address.
    std::unordered_map<const Node*, std::pair<Expr, Expr>> resolved;
    std::function<Expr(const Expr&)> resolve_all = [&](const Expr& e) -> Expr {
      if (auto it = resolved.find(e.get()); it != resolved.end()) return it->second.second;
      Expr r;
      if (e->op == Op::Var) {
        auto it = alias.find(e->id);
        r = it == alias.end() ? e : resolve(it->second);
      } else {
        std::vector<Expr> args;
        args.reserve(e->args.size());
        for (const Expr& a : e->args) args.push_back(resolve_all(a));
        r = with_operands(e, std::move(args));
      }
      resolved.emplace(e.get(), std::make_pair(e, r));
      return r;
    };
    for (Equation& eq : kept) {
      eq.lhs = resolve_all(eq.lhs);
      eq.rhs = resolve_all(eq.rhs);
    }
    eqs_ = std::move(kept);
    for (const StateVar& s : out_.states) out_.state_derivative.push_back(resolve_all(var(s.der)));
    for (Output& o : out_.graph.outputs) o.value = resolve_all(o.value);
    for (std::vector<EnergyTerm>* list : {&out_.energy.stored, &out_.energy.supplied, &out_.energy.absorbed})
      for (EnergyTerm& t : *list) t.value = resolve_all(t.value);
    for (DrawnBody& d : out_.graph.drawings) d.for_each_expr([&](Expr& e) { e = resolve_all(e); });
    for (auto& [id, rate] : rate_of_) rate = resolve_all(rate);
    for (ConstraintRow& row : out_.constraints) {
      row.gdot = resolve_all(var(row.flow));
      row.g = resolve_all(row.g);  // (a cut joint's g reads signals, some now constants)
    }
    for (ContactRow& c : out_.contacts) {
      c.gap = resolve_all(c.gap);
      c.rate = resolve_all(c.rate);
      c.normal_force = resolve_all(c.normal_force);
      for (Expr& x : c.tangent_rate)
        if (x) x = resolve_all(x);
      for (Expr& x : c.tangent_force)
        if (x) x = resolve_all(x);
    }
    alias_ = std::move(alias);
    out_.log.push_back(fmt::format("alias elimination: {} equation{} of the form a = ±b removed", aliases_, aliases_ == 1 ? "" : "s"));
    out_.log.push_back(fmt::format("constant propagation: {} variable{} with a constant value folded into their uses", constants_, constants_ == 1 ? "" : "s"));
  }

  // ---- 1. derivative causality ------------------------------------------------------
  /// Explicit solution of `unknown` from its equation, if it is affine in it.
  static std::optional<Expr> solve_single(const Equation& eq) {
    Expr r = sub(eq.lhs, eq.rhs);
    std::vector<Expr> coeff;
    Expr rest;
    if (!affine_in(r, {eq.unknown}, coeff, rest) || is_zero(coeff[0])) return std::nullopt;
    return div(neg(rest), coeff[0]);
  }

  /// d/dt of variable `id`, as an expression: a state's derivative is what the
  /// integrator gets; any other variable gets a derivative variable of its own,
  /// defined by differentiating its (explicit) equation by the chain rule. Each
  /// new equation is local, so the work and the code grow with the graph, not
  /// with the depth of the kinematic chain. nullopt: the variable's equation
  /// is not explicit or sits in an algebraic loop.
  std::optional<Expr> derivative_of_var(int id, std::vector<int>& path, std::vector<Equation>& added) {
    if (auto s = state_index_.find(id); s != state_index_.end()) return out_.state_derivative[s->second];
    if (auto it = der_var_.find(id); it != der_var_.end()) return var(it->second);
    if (auto r = rate_of_.find(id); r != rate_of_.end()) {  // known in closed form (a body's rotation)
      int dx = out_.graph.add_var("der(" + v(id).name + ")", VarKind::Auxiliary, v(id).loc);
      der_var_[id] = dx;
      added.push_back({var(dx), r->second, dx, v(id).loc, "d/dt of [signal " + v(id).name + "] in closed form"});
      return var(dx);
    }
    auto eq = eq_of_.find(id);
    if (eq == eq_of_.end() || std::count(path.begin(), path.end(), id)) return std::nullopt;
    const Equation& def = eqs_[static_cast<std::size_t>(eq->second)];
    auto sol = solve_single(def);
    if (!sol || contains_der(*sol)) return std::nullopt;
    path.push_back(id);
    auto d = derivative_of_expr(*sol, path, added);
    path.pop_back();
    if (!d) return std::nullopt;
    int dx = out_.graph.add_var("der(" + v(id).name + ")", VarKind::Auxiliary, v(id).loc);
    der_var_[id] = dx;
    added.push_back({var(dx), *d, dx, def.loc, "d/dt of [" + def.origin + "]"});
    return var(dx);
  }

  /// d/dt of an expression: its explicit time dependence plus, per variable,
  /// the partial derivative times that variable's rate.
  std::optional<Expr> derivative_of_expr(const Expr& x, std::vector<int>& path, std::vector<Equation>& added) {
    Expr d = diff_time(x);
    std::unordered_set<int> vars;
    collect_vars(x, vars);
    std::vector<int> sorted(vars.begin(), vars.end());
    std::sort(sorted.begin(), sorted.end());  // deterministic output
    for (int id : sorted) {
      Expr partial = diff_var(x, id);
      if (is_zero(partial)) continue;
      auto rate = derivative_of_var(id, path, added);
      if (!rate) return std::nullopt;
      d = add(d, mul(partial, *rate));
    }
    return d;
  }

  /// Derivative causality (§8.4): a storage element whose input is imposed
  /// reads `e = der(p)`; the derivative is taken symbolically through the
  /// equations that compute p from the states, leaving the state derivatives
  /// (accelerations) to the algebraic loop they form with the junction balances.
  bool expand_derivatives() {
    for (std::size_t i = 0; i < eqs_.size(); ++i) eq_of_[eqs_[i].unknown] = static_cast<int>(i);
    for (std::size_t i = 0; i < out_.states.size(); ++i) state_index_[out_.states[i].var] = i;
    int expanded = 0;
    std::vector<Equation> added;
    for (std::size_t i = 0; i < eqs_.size(); ++i) {
      if (!contains_der(eqs_[i].lhs) && !contains_der(eqs_[i].rhs)) continue;
      bool ok = true;
      auto expand = [&](const Expr& side) {
        return rewrite(side, [&](const Expr& n) -> Expr {
          if (n->op != Op::Der || !ok) return nullptr;
          std::vector<int> path;
          auto d = derivative_of_expr(n->args[0], path, added);
          if (!d) {
            ok = false;
            return nullptr;
          }
          return *d;
        });
      };
      Expr lhs = expand(eqs_[i].lhs);
      Expr rhs = expand(eqs_[i].rhs);
      Equation& eq = eqs_[i];
      if (!ok) {
        diags_.error(eq.loc, fmt::format("cannot eliminate the derivative causality in `{}`", eq.origin),
                     "the dependent storage's input comes through an algebraic loop or a nonlinear relation; "
                     "break the rigid coupling with a stiff C or a small R");
        return false;
      }
      eq.lhs = lhs;
      eq.rhs = rhs;
      ++expanded;
      out_.derivative_causality.push_back(eq.in_loop ? fmt::format("{}: g'' taken symbolically through the tree's rates", eq.origin)
                                                     : fmt::format("{}: state eliminated, derivative taken symbolically", eq.origin));
    }
    for (Equation& e : added) eqs_.push_back(std::move(e));
    if (expanded)
      out_.log.push_back(fmt::format("derivative causality: {} equation{} differentiated symbolically ({} derivative variable{})",
                                     expanded, expanded == 1 ? "" : "s", der_var_.size(), der_var_.size() == 1 ? "" : "s"));
    return true;
  }

  // ---- 3. sorting and algebraic loops -------------------------------------------------
  void sort_and_solve() {
    std::size_t n = eqs_.size();
    eq_of_.clear();
    for (std::size_t i = 0; i < n; ++i) eq_of_[eqs_[i].unknown] = static_cast<int>(i);
    std::vector<std::vector<int>> deps(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::unordered_set<int> vars;
      collect_vars(eqs_[i].lhs, vars);
      collect_vars(eqs_[i].rhs, vars);
      for (int id : vars) {
        if (known_.count(id)) continue;
        auto it = eq_of_.find(id);
        if (it == eq_of_.end()) {
          diags_.error(v(id).loc, fmt::format("internal error: nothing computes `{}`", v(id).name),
                       "please report this model to the mbgc developers");
          return;
        }
        deps[i].push_back(it->second);
      }
      std::sort(deps[i].begin(), deps[i].end());
    }
    // Tarjan's SCC, iterative; SCCs come out dependencies-first.
    std::vector<int> index(n, -1), low(n, 0), stack;
    std::vector<bool> on_stack(n, false);
    int counter = 0;
    std::vector<std::vector<int>> blocks;
    for (std::size_t root = 0; root < n; ++root) {
      if (index[root] >= 0) continue;
      std::vector<std::pair<int, std::size_t>> call{{static_cast<int>(root), 0}};
      index[root] = low[root] = counter++;
      stack.push_back(static_cast<int>(root));
      on_stack[root] = true;
      while (!call.empty()) {
        auto& [u, k] = call.back();
        std::size_t uu = static_cast<std::size_t>(u);
        if (k < deps[uu].size()) {
          int w = deps[uu][k++];
          std::size_t ww = static_cast<std::size_t>(w);
          if (index[ww] < 0) {
            index[ww] = low[ww] = counter++;
            stack.push_back(w);
            on_stack[ww] = true;
            call.push_back({w, 0});
          } else if (on_stack[ww]) {
            low[uu] = std::min(low[uu], index[ww]);
          }
          continue;
        }
        if (low[uu] == index[uu]) {
          std::vector<int> block;
          int w;
          do {
            w = stack.back();
            stack.pop_back();
            on_stack[static_cast<std::size_t>(w)] = false;
            block.push_back(w);
          } while (w != u);
          std::sort(block.begin(), block.end());
          blocks.push_back(std::move(block));
        }
        int done = u;
        call.pop_back();
        if (!call.empty()) {
          std::size_t parent = static_cast<std::size_t>(call.back().first);
          low[parent] = std::min(low[parent], low[static_cast<std::size_t>(done)]);
        }
      }
    }
    for (const auto& block : blocks) solve_block(block);
    if (out_.dae) finish_dae();
    if (out_.dae) check_solver_for_dae();
    if (out_.dae) check_contacts_for_dae();
    int linear = 0, nonlinear = 0;
    for (const AlgebraicLoop& l : out_.loops) (l.linear ? linear : nonlinear)++;
    out_.log.push_back(fmt::format("sorting: {} equations in {} blocks; {} linear algebraic loop{} solved symbolically, {} nonlinear left to IDA",
                                   n, blocks.size(), linear, linear == 1 ? "" : "s", nonlinear));
  }

  /// A unilateral contact's impacts are impulses the runtime finds from the
  /// state derivative, which a DAE does not have.
  void check_contacts_for_dae() {
    for (const ContactRow& c : out_.contacts) {
      if (c.compliant) continue;
      diags_.error(c.loc, fmt::format("unilateral contact `{}` in a model solved as a DAE", c.name.substr(0, c.name.rfind('.'))),
                   "its impacts are impulses through the ODE's mass matrix, which a DAE (joints held by lagrange rows) "
                   "does not have: use constraints = coordinates (or penalty) for the joints, or strategy = compliant "
                   "for the contact");
    }
  }

  void solve_block(const std::vector<int>& block) {
    bool has_constraint = false;
    for (int i : block) has_constraint |= eqs_[static_cast<std::size_t>(i)].constraint && !eqs_[static_cast<std::size_t>(i)].in_loop;
    if (has_constraint) {
      // A CN row gdot = 0 determines its multiplier only through the
      // dynamics: it stays a residual of the (index-2) DAE.
      out_.dae = true;
      for (int i : block) {
        dae_block_eqs_.push_back(i);
        dae_unknowns_.insert(eqs_[static_cast<std::size_t>(i)].unknown);
      }
      return;
    }
    // (a contact's row alone: its coefficient vanishes in some modes (a
    // tangential row no body can move along, while stuck): solved rank-revealing)
    if (block.size() == 1 && !contact_multipliers_.count(eqs_[static_cast<std::size_t>(block[0])].unknown)) {
      const Equation& eq = eqs_[static_cast<std::size_t>(block[0])];
      if (auto sol = solve_single(eq)) {
        if (!mentions_var(*sol, eq.unknown)) {
          out_.assignments.push_back({eq.unknown, *sol, eq.loc, eq.origin});
          return;
        }
      }
    }
    if (block.size() > kTearAbove && tear_block(block)) return;
    std::vector<int> unknowns;
    for (int i : block) unknowns.push_back(eqs_[static_cast<std::size_t>(i)].unknown);
    AlgebraicLoop loop;
    loop.vars = unknowns;
    loop.bonds = loop_bonds(block);
    std::size_t n = block.size();
    std::vector<std::vector<Expr>> a(n);
    std::vector<Expr> b(n);
    bool linear = true;
    for (std::size_t i = 0; i < n && linear; ++i) {
      const Equation& eq = eqs_[static_cast<std::size_t>(block[i])];
      Expr rest;
      linear = affine_in(sub(eq.lhs, eq.rhs), unknowns, a[i], rest);
      if (linear) b[i] = neg(rest);
    }
    std::size_t blocks_before = out_.linear_blocks.size();
    if (linear && gauss(block, unknowns, a, b)) {
      loop.linear = true;
      loop.resolution = out_.linear_blocks.size() > blocks_before
                            ? "linear: coefficients derived symbolically, solved at run time with partial pivoting"
                            : "linear: solved symbolically (Gaussian elimination)";
      out_.loops.push_back(loop);
      return;
    }
    // Nonlinear (or singular) loop: hand it to IDA.
    loop.linear = false;
    loop.resolution = "nonlinear: left to IDA as a DAE (residuals)";
    out_.loops.push_back(loop);
    out_.dae = true;
    for (int i : block) {
      const Equation& eq = eqs_[static_cast<std::size_t>(i)];
      dae_block_eqs_.push_back(i);
      dae_unknowns_.insert(eq.unknown);
    }
  }

  /// The bonds whose efforts or flows are unknowns of a loop, sorted, each once (for its report).
  std::vector<int> loop_bonds(const std::vector<int>& block) const {
    std::vector<int> bonds;
    for (int i : block) {
      const Variable& var_info = v(eqs_[static_cast<std::size_t>(i)].unknown);
      if (var_info.kind == VarKind::Effort || var_info.kind == VarKind::Flow) bonds.push_back(var_info.of);
    }
    std::sort(bonds.begin(), bonds.end());
    bonds.erase(std::unique(bonds.begin(), bonds.end()), bonds.end());
    return bonds;
  }

  /// Loops larger than this are torn before Gaussian elimination is tried.
  static constexpr std::size_t kTearAbove = 12;

  /// Tearing: the state derivatives in a loop (the accelerations of a chain in
  /// joint coordinates) are chosen as tear variables. If the rest of the loop
  /// then follows equation by equation, every other unknown is affine in them,
  /// and the tear variables' own equations become a small dense system
  /// M a = b (the mass matrix, when the loop comes from derivative causality)
  /// solved at run time; the other unknowns are plain assignments after it.
  bool tear_block(const std::vector<int>& block) {
    std::vector<int> tears, tear_eqs, rest_eqs;
    for (int i : block) {
      int u = eqs_[static_cast<std::size_t>(i)].unknown;
      // (a cut joint's multiplier is torn too: its equation, g'' = ..., does not contain it)
      if (v(u).kind == VarKind::Derivative || eqs_[static_cast<std::size_t>(i)].in_loop) {
        tears.push_back(u);
        tear_eqs.push_back(i);
      } else {
        rest_eqs.push_back(i);
      }
    }
    if (tears.empty() || tears.size() * 2 > block.size()) return false;
    std::unordered_set<int> tear_set(tears.begin(), tears.end());
    // Order the rest so each equation only reads tears and earlier unknowns.
    std::unordered_map<int, int> eq_of_unknown;
    for (int i : rest_eqs) eq_of_unknown[eqs_[static_cast<std::size_t>(i)].unknown] = i;
    std::unordered_map<int, Expr> solution;
    std::vector<int> order;
    std::unordered_map<int, int> state;  // 0 new, 1 visiting, 2 done
    bool acyclic = true;
    std::function<void(int)> visit = [&](int u) {
      int& st = state[u];
      if (st == 2 || !acyclic) return;
      if (st == 1) { acyclic = false; return; }
      st = 1;
      const Equation& eq = eqs_[static_cast<std::size_t>(eq_of_unknown.at(u))];
      auto sol = solve_single(eq);
      std::unordered_set<int> vars;
      if (sol) collect_vars(*sol, vars);
      if (!sol || vars.count(u)) { acyclic = false; return; }
      solution[u] = *sol;
      std::vector<int> inputs(vars.begin(), vars.end());
      std::sort(inputs.begin(), inputs.end());
      for (int w : inputs)
        if (eq_of_unknown.count(w)) visit(w);
      state[u] = 2;
      order.push_back(u);
    };
    for (int i : rest_eqs) visit(eqs_[static_cast<std::size_t>(i)].unknown);
    if (!acyclic) return false;
    if (eliminate_tree(block, tears, tear_eqs, order, solution, eq_of_unknown)) return true;
    // Each torn unknown as rest + sum_k coeff[k] * tear_k.
    struct Affine { Expr rest; std::vector<Expr> coeff; };
    std::unordered_map<int, Affine> affine;
    auto to_affine = [&](const Expr& e, Affine& out) {
      std::unordered_set<int> vars;
      collect_vars(e, vars);
      std::vector<int> in_loop(tears);
      for (int w : vars)
        if (affine.count(w)) in_loop.push_back(w);
      std::vector<Expr> c;
      Expr rest;
      if (!affine_in(e, in_loop, c, rest)) return false;
      out.rest = rest;
      out.coeff.assign(tears.size(), constant(0));
      for (std::size_t k = 0; k < tears.size(); ++k) out.coeff[k] = c[k];
      for (std::size_t j = tears.size(); j < in_loop.size(); ++j) {
        if (is_zero(c[j])) continue;
        const Affine& w = affine.at(in_loop[j]);
        out.rest = add(out.rest, mul(c[j], w.rest));
        for (std::size_t k = 0; k < tears.size(); ++k)
          if (!is_zero(w.coeff[k])) out.coeff[k] = add(out.coeff[k], mul(c[j], w.coeff[k]));
      }
      return true;
    };
    for (int u : order) {
      Affine a;
      if (!to_affine(solution.at(u), a)) return false;
      affine[u] = std::move(a);
    }
    LinearBlock lb;
    lb.unknowns = tears;
    lb.rank_revealing = any_contact_multiplier(tears);
    for (int i : tear_eqs) {
      const Equation& eq = eqs_[static_cast<std::size_t>(i)];
      Affine r;
      if (!to_affine(sub(eq.lhs, eq.rhs), r)) return false;
      for (const Expr& c : r.coeff) lb.a.push_back(c);
      lb.b.push_back(neg(r.rest));
    }
    const Equation& first = eqs_[static_cast<std::size_t>(tear_eqs[0])];
    int index = static_cast<int>(out_.linear_blocks.size());
    out_.linear_blocks.push_back(std::move(lb));
    for (int u : tears)
      out_.assignments.push_back({u, nullptr, first.loc,
                                  fmt::format("algebraic loop ({} unknowns) torn at {} state derivative{}: dense {}x{} system solved at run time",
                                              block.size(), tears.size(), tears.size() == 1 ? "" : "s", tears.size(), tears.size()),
                                  index});
    for (int u : order) {
      const Equation& eq = eqs_[static_cast<std::size_t>(eq_of_unknown.at(u))];
      out_.assignments.push_back({u, solution.at(u), eq.loc, eq.origin});
    }
    AlgebraicLoop loop;
    loop.vars = tears;
    loop.bonds = loop_bonds(block);
    loop.linear = true;
    loop.resolution = fmt::format("linear: torn at the {} state derivative{}, the other {} unknowns follow in order; "
                                  "the {}x{} system is solved at run time with partial pivoting",
                                  tears.size(), tears.size() == 1 ? "" : "s", order.size(), tears.size(), tears.size());
    out_.loops.push_back(loop);
    return true;
  }

  /// The bodies of a kinematic tree in joint coordinates, from the graph's
  /// tags (GraphNode::tree_node), and the body of each variable: a bond's
  /// efforts and flows belong to the deeper of its two ends' bodies (a bond
  /// from a parent's junction into a child's joint carries the child's
  /// reaction), a state derivative to its storage element's, a derivative
  /// variable der(x) to x's.
  TreeLayout tree_layout() {
    TreeLayout tree;
    std::map<std::string, int> index;
    auto body = [&](const std::string& name) {
      auto [it, fresh] = index.emplace(name, static_cast<int>(tree.names.size()));
      if (fresh) tree.names.push_back(name), tree.parent.push_back(-1);
      return it->second;
    };
    std::vector<int> node_body(out_.graph.nodes.size(), -1);
    for (std::size_t i = 0; i < out_.graph.nodes.size(); ++i) {
      const GraphNode& n = out_.graph.nodes[i];
      if (n.tree_node.empty()) continue;
      const int b = body(n.tree_node);
      node_body[i] = b;
      if (!n.tree_parent.empty()) tree.parent[static_cast<std::size_t>(b)] = body(n.tree_parent);
    }
    if (tree.names.empty()) return tree;
    std::vector<int> depth(tree.names.size(), 0);
    for (std::size_t b = 0; b < depth.size(); ++b)
      for (int p = tree.parent[b]; p >= 0 && depth[b] <= static_cast<int>(depth.size()); p = tree.parent[static_cast<std::size_t>(p)]) ++depth[b];
    std::unordered_map<int, int> derivative_of;  // der(x) -> x
    for (const auto& [x, dx] : der_var_) derivative_of[dx] = x;
    std::unordered_map<int, int> storage_of;     // state -> its storage node
    for (const StateVar& st : out_.states) storage_of[st.var] = st.node;
    // (indices checked: a scene's pruning leaves variables whose bond or node is gone)
    auto body_of_node = [&](int node) {
      return node >= 0 && static_cast<std::size_t>(node) < node_body.size() ? node_body[static_cast<std::size_t>(node)] : -1;
    };
    std::function<int(int, int)> of_var = [&](int id, int hops) -> int {
      if (hops > 8) return -1;
      const Variable& x = v(id);
      if ((x.kind == VarKind::Effort || x.kind == VarKind::Flow) && x.of >= 0 &&
          static_cast<std::size_t>(x.of) < out_.graph.bonds.size()) {
        const Bond& bd = out_.graph.bonds[static_cast<std::size_t>(x.of)];
        const int a = body_of_node(bd.from), b = body_of_node(bd.to);
        if (a < 0 || b < 0) return a < 0 ? b : a;
        return depth[static_cast<std::size_t>(b)] > depth[static_cast<std::size_t>(a)] ? b : a;
      }
      if (x.kind == VarKind::Derivative && storage_of.count(x.of)) return body_of_node(storage_of.at(x.of));
      if (auto d = derivative_of.find(id); d != derivative_of.end()) return of_var(d->second, hops + 1);
      if (auto st = storage_of.find(id); st != storage_of.end()) return body_of_node(st->second);
      return -1;
    };
    for (std::size_t id = 0; id < out_.graph.vars.size(); ++id)
      if (int b = of_var(static_cast<int>(id), 0); b >= 0) tree.body_of[static_cast<int>(id)] = b;
    return tree;
  }

  /// A loop torn at its state derivatives, eliminated along the kinematic
  /// tree its unknowns belong to (tree_elimination.hpp), if they do.
  bool eliminate_tree(const std::vector<int>& block, const std::vector<int>& tears, const std::vector<int>& tear_eqs,
                      const std::vector<int>& order, const std::unordered_map<int, Expr>& solution,
                      const std::unordered_map<int, int>& eq_of_unknown) {
    if (!tree_) tree_ = tree_layout();
    if (tree_->names.empty()) return false;
    TornLoop torn;
    torn.tears = tears;
    torn.order = order;
    torn.solution = solution;
    for (std::size_t k = 0; k < tears.size(); ++k) {
      const Equation& eq = eqs_[static_cast<std::size_t>(tear_eqs[k])];
      torn.tear_residuals.push_back(sub(eq.lhs, eq.rhs));
      torn.source[tears[k]] = {eq.loc, eq.origin};
      if (eq.in_loop) torn.multipliers.push_back(tears[k]);
    }
    for (int u : order) {
      const Equation& eq = eqs_[static_cast<std::size_t>(eq_of_unknown.at(u))];
      torn.source[u] = {eq.loc, eq.origin};
    }
    std::string why;
    auto done = eliminate_along_tree(torn, *tree_, out_.graph, &why);
    if (!done) {
      out_.log.push_back(fmt::format("algebraic loop of {} unknowns not eliminated along the tree: {}", block.size(), why));
      return false;
    }
    const int block_index = static_cast<int>(out_.linear_blocks.size());
    if (done->multipliers) out_.linear_blocks.push_back(std::move(*done->multipliers));
    if (!out_.tree) out_.tree = *tree_;
    for (const auto& [u, b] : done->body_of) out_.tree->body_of[u] = b;
    for (Assignment& a : done->assignments) {
      if (a.block >= 0) a.block = block_index;  // the cut joints' multipliers
      out_.assignments.push_back(std::move(a));
    }
    const std::size_t m = torn.multipliers.size();
    AlgebraicLoop loop;
    loop.vars = tears;
    loop.bonds = loop_bonds(block);
    loop.linear = true;
    loop.resolution = fmt::format(
        "linear: eliminated along the kinematic tree, leaves first ({} bodies, {} joint accelerations; articulated-body "
        "form, {} temporaries): work linear in the bodies, no mass matrix{}",
        done->bodies, tears.size() - m, done->temporaries,
        m ? fmt::format("; {} cut-joint multiplier{} from a {}x{} system", m, m == 1 ? "" : "s", m, m) : std::string());
    out_.loops.push_back(loop);
    tree_eliminated_ = true;
    return true;
  }

  /// Symbolic Gaussian elimination, preferring constant pivots. If every pivot
  /// is free of variables and time it cannot vanish during a run, and the
  /// solution is emitted as plain assignments; otherwise the block is solved
  /// numerically with partial pivoting at run time.
  bool gauss(const std::vector<int>& block, const std::vector<int>& unknowns, std::vector<std::vector<Expr>> a,
             std::vector<Expr> b) {
    const std::vector<std::vector<Expr>> a0 = a;
    const std::vector<Expr> b0 = b;
    std::size_t n = unknowns.size();
    const Equation& first = eqs_[static_cast<std::size_t>(block[0])];
    bool constant_pivots = true;
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t pivot = n;
      for (std::size_t r = k; r < n; ++r) {
        double c = 0;
        if (is_const(a[r][k], &c) && c != 0) { pivot = r; break; }
      }
      if (pivot == n)
        for (std::size_t r = k; r < n; ++r)
          if (!is_zero(a[r][k])) { pivot = r; break; }
      if (pivot == n) {
        diags_.error(first.loc, fmt::format("singular algebraic loop: `{}` cannot be solved from the loop's equations", v(unknowns[k]).name),
                     "the junction structure leaves this variable undetermined; check for a loop of junctions without an element");
        return true;  // reported; do not fall back to a DAE
      }
      std::unordered_set<int> pivot_vars;
      collect_vars(a[pivot][k], pivot_vars);
      if (!pivot_vars.empty() || depends_on_time(a[pivot][k])) constant_pivots = false;
      std::swap(a[k], a[pivot]);
      std::swap(b[k], b[pivot]);
      for (std::size_t r = k + 1; r < n; ++r) {
        if (is_zero(a[r][k])) continue;
        Expr factor = div(a[r][k], a[k][k]);
        for (std::size_t c = k + 1; c < n; ++c) a[r][c] = sub(a[r][c], mul(factor, a[k][c]));
        b[r] = sub(b[r], mul(factor, b[k]));
        a[r][k] = constant(0);
      }
    }
    if (!constant_pivots) {
      LinearBlock lb;
      lb.unknowns = unknowns;
      lb.rank_revealing = any_contact_multiplier(unknowns);
      for (std::size_t r = 0; r < n; ++r)
        for (std::size_t c = 0; c < n; ++c) lb.a.push_back(a0[r][c]);
      lb.b = b0;
      int index = static_cast<int>(out_.linear_blocks.size());
      out_.linear_blocks.push_back(std::move(lb));
      for (int u : unknowns)
        out_.assignments.push_back({u, nullptr, first.loc,
                                    fmt::format("algebraic loop ({} unknowns), solved numerically (pivots depend on the state)", n), index});
      return true;
    }
    for (std::size_t k = n; k-- > 0;) {
      Expr s = b[k];
      for (std::size_t c = k + 1; c < n; ++c) s = sub(s, mul(a[k][c], var(unknowns[c])));
      out_.assignments.push_back({unknowns[k], div(s, a[k][k]), first.loc,
                                  fmt::format("algebraic loop ({} unknowns), solved for {}", n, v(unknowns[k]).name)});
    }
    return true;
  }

  void finish_dae() {
    // y = [states, algebraic]; a state's derivative inside a nonlinear loop is read from yp.
    out_.derivative_unknowns.assign(out_.states.size(), -1);
    std::map<int, std::size_t> state_of_der;
    for (std::size_t i = 0; i < out_.states.size(); ++i) state_of_der[out_.states[i].der] = i;
    std::vector<Residual> state_residuals(out_.states.size());
    std::vector<bool> have(out_.states.size(), false);
    std::vector<Residual> algebraic_residuals;
    for (int i : dae_block_eqs_) {
      const Equation& eq = eqs_[static_cast<std::size_t>(i)];
      Residual r{sub(eq.lhs, eq.rhs), eq.loc, eq.origin};
      if (auto it = state_of_der.find(eq.unknown); it != state_of_der.end()) {
        out_.derivative_unknowns[it->second] = eq.unknown;
        state_residuals[it->second] = r;
        have[it->second] = true;
      } else {
        out_.algebraic.push_back(eq.unknown);
        algebraic_residuals.push_back(r);
      }
    }
    for (std::size_t i = 0; i < out_.states.size(); ++i) {
      if (have[i]) continue;
      // yp_i - f_i(t, y), with yp_i a variable of its own (the der variable is computed).
      const StateVar& s = out_.states[i];
      int yp = out_.graph.add_var("yp(" + v(s.var).name + ")", VarKind::Derivative, v(s.var).loc, s.var);
      out_.derivative_unknowns[i] = yp;
      state_residuals[i] = Residual{sub(var(yp), out_.state_derivative[i]), v(s.var).loc,
                                    fmt::format("der({}) from the integrator", v(s.var).name)};
    }
    stabilise(state_residuals, have, algebraic_residuals);
    out_.residuals = std::move(state_residuals);
    for (Residual& r : algebraic_residuals) out_.residuals.push_back(std::move(r));
  }

  /// A DAE only IDA integrates: a `simulate { solver = ... }` that names
  /// another solver is an error here, with the reason in bond-graph terms,
  /// rather than a simulator that refuses to run.
  void check_solver_for_dae() {
    SimSettings& ss = out_.graph.settings;
    if (!ss.solver) return;
    if (const mbgrt::IntegratorInfo* info = mbgrt::find_integrator(*ss.solver); !info || info->takes(mbgrt::ModelForm::dae))
      return;
    const char* dae_solver = mbgrt::integrator_info(mbgrt::kDefaultDaeSolver).name;
    if (ss.form_option) {  // the command line chose the form: the block's solver was a default
      diags_.warning(ss.solver_loc,
                     fmt::format("solver `{}` cannot integrate the DAE that {} makes of this model: it is integrated by {}",
                                 *ss.solver, *ss.form_option, dae_solver),
                     "the simulate block's solver is a default; the simulator's --solver chooses another at run time");
      ss.solver = dae_solver;
      return;
    }
    std::vector<std::string> rows;
    for (const ConstraintRow& row : out_.constraints)
      if (row.multiplier >= 0) rows.push_back(row.name.substr(0, row.name.find('[')));
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    if (!rows.empty()) {
      const bool one = rows.size() == 1;
      std::string list = fmt::format("{}", fmt::join(rows.begin(), rows.begin() + std::min<std::ptrdiff_t>(4, std::ssize(rows)), ", "));
      if (rows.size() > 4) list += fmt::format(" and {} more", rows.size() - 4);
      diags_.error(ss.solver_loc, fmt::format("solver `{}` cannot integrate this model: it is a DAE", *ss.solver),
                   fmt::format("the constraintor{} {} impose{} {} rows through multipliers, efforts that no storage "
                               "element determines; write solver = {}, or constraints = penalty for an ODE",
                               one ? "" : "s", list, one ? "s" : "", one ? "its" : "their", dae_solver));
      return;
    }
    diags_.error(ss.solver_loc, fmt::format("solver `{}` cannot integrate this model: it is a DAE", *ss.solver),
                 fmt::format("a nonlinear algebraic loop is left to IDA as residual equations (see --dump=causality); "
                             "write solver = {}",
                             dae_solver));
  }

  /// Gear-Gupta-Leimkuhler stabilisation of the lagrange rows: besides
  /// gdot = 0 (multiplier lambda), the position-level g = 0 is a residual too,
  /// with a multiplier mu that corrects the rates of the states g depends on:
  /// x' = f(x) + (dg/dx)^T mu. At the exact solution mu = 0; numerically it keeps
  /// g from drifting, so neither positions nor velocities leave the constraints.
  void stabilise(std::vector<Residual>& state_residuals, const std::vector<bool>& have,
                 std::vector<Residual>& algebraic_residuals) {
    int rows = 0;
    for (ConstraintRow& row : out_.constraints) {
      if (row.multiplier < 0) continue;
      row.stabiliser = out_.graph.add_var("mu(" + row.name + ")", VarKind::Auxiliary, row.loc);
      out_.algebraic.push_back(row.stabiliser);
      algebraic_residuals.push_back({row.g, row.loc, "CN " + row.name + ": g = 0 (position level, GGL)"});
      // Only the states g reads have a nonzero partial: a row of a chain's
      // joint reads two bodies, so this stays linear in the number of bodies.
      std::unordered_set<int> read;
      collect_vars(row.g, read);
      for (std::size_t i = 0; i < out_.states.size(); ++i) {
        if (!read.count(out_.states[i].var)) continue;
        Expr dg = diff_var(row.g, out_.states[i].var);
        if (is_zero(dg)) continue;
        if (have[i]) {
          diags_.error(row.loc, fmt::format("internal error: constraint `{}` depends on `{}`, whose derivative is implicit", row.name, v(out_.states[i].var).name),
                       "please report this model to the mbgc developers");
          continue;
        }
        state_residuals[i].value = sub(state_residuals[i].value, mul(dg, var(row.stabiliser)));
      }
      ++rows;
    }
    if (rows)
      out_.log.push_back(fmt::format("constraints: {} lagrange row{} in stabilised index-2 form (GGL: gdot = 0 with lambda, g = 0 with mu)",
                                     rows, rows == 1 ? "" : "s"));
  }

  // ---- 5. Jacobian for the implicit solvers ------------------------------------------------
  /// d(xdot_i)/d(x_j) by forward-mode symbolic differentiation through the
  /// sorted assignments (reduce/forward_diff.hpp), for ODEs whose assignments
  /// are all explicit.
  void differentiate_for_jacobian() {
    // (after a tree elimination a symbolic Jacobian would be dense in the
    // bodies: the implicit solvers difference the derivative instead)
    if (out_.dae || !out_.linear_blocks.empty() || tree_eliminated_) return;
    std::size_t n = out_.states.size();
    if (n == 0) return;
    ForwardDiff d(out_);
    out_.jacobian.assign(n * n, constant(0));
    std::size_t nonzero = 0;
    for (std::size_t i = 0; i < n; ++i) {
      std::optional<ForwardDiff::Derivatives> row = d.of(out_.state_derivative[i]);  // (no linear block: always)
      for (auto& [j, value] : *row) {
        out_.jacobian[i * n + static_cast<std::size_t>(j)] = std::move(value);
        ++nonzero;
      }
    }
    out_.log.push_back(fmt::format("jacobian: {} of {} entries nonzero, by symbolic differentiation", nonzero, n * n));
  }

  /// G = dg/dx for the runtime (reduce/constraint_jacobian.hpp).
  void differentiate_constraints() {
    if (const std::optional<std::size_t> row = constraint_jacobian(out_)) {
      const ConstraintRow& r = out_.constraints[*row];
      diags_.error(r.loc, fmt::format("internal error: constraint `{}` depends on a variable solved numerically, so it cannot be differentiated", r.name),
                   "please report this model to the mbgc developers");
    }
  }

  EquationSystem& sys_;
  ReducedSystem& out_;
  Diagnostics& diags_;
  bool energy_witness_;
  std::vector<Equation> eqs_;
  std::unordered_set<int> known_;  // what no equation computes: the states and the discrete variables
  // Unilateral contacts' multipliers: a loop with them is solved rank-revealing,
  // since contacts are often redundant (a block's four corners on the floor).
  std::unordered_set<int> contact_multipliers_;
  bool any_contact_multiplier(const std::vector<int>& unknowns) const {
    return std::any_of(unknowns.begin(), unknowns.end(), [&](int u) { return contact_multipliers_.count(u) > 0; });
  }
  std::unordered_map<int, Expr> alias_;
  std::unordered_map<int, int> eq_of_;
  std::unordered_map<int, std::size_t> state_index_;  // state variable -> index in out_.states
  std::unordered_map<int, int> der_var_;               // variable -> its derivative variable
  std::unordered_map<int, Expr> rate_of_;              // signal -> its time derivative in closed form (Signal::rate)
  std::vector<int> dae_block_eqs_;
  std::unordered_set<int> dae_unknowns_;
  std::optional<TreeLayout> tree_;   // the kinematic tree's bodies (built when a loop is torn)
  bool tree_eliminated_ = false;
  int aliases_ = 0;
  int constants_ = 0;
};

}  // namespace
}  // namespace mbgc::reduce

namespace mbgc::reduce {

ReducedSystem reduce(EquationSystem system, Diagnostics& diags, bool energy_witness) {
  ReducedSystem out;
  Reducer r(system, out, diags, energy_witness);
  r.run();
  if (!diags.has_errors()) {
    residual_sparsity(out);
    nominal_values(out);
  }
  return out;
}

}  // namespace mbgc::reduce
