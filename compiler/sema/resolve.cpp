#include "sema/resolve.hpp"

#include "ir/element_settings.hpp"
#include "sema/bind.hpp"

#include "mbgrt/integrators.hpp"
#include "units/literals.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <functional>
#include <set>
#include <unordered_map>

namespace mbgc::sema {
namespace {

using namespace mbgc::ir;

NodeKind kind_of(const std::string& k) {
  if (k == "Se") return NodeKind::Se;
  if (k == "Sf") return NodeKind::Sf;
  if (k == "I") return NodeKind::I;
  if (k == "C") return NodeKind::C;
  if (k == "R") return NodeKind::R;
  if (k == "TF") return NodeKind::TF;
  if (k == "GY") return NodeKind::GY;
  if (k == "MTF") return NodeKind::MTF;
  if (k == "CN") return NodeKind::CN;
  return NodeKind::MGY;
}

/// A parameter declared somewhere, not yet evaluated.
struct PendingParam {
  std::string full;
  SourceLoc loc;
  TermPtr expr;
  int scope;  // scope its expression is evaluated in
  bool fold = false;  // ExpandedParam::fold: a constant where its value is one
  std::optional<DeclaredUnit> unit;
  bool generated = false;  // ExpandedParam::generated
  std::optional<units::Dimension> stated;  // ExpandedParam::dimension
};

/// A bond end as written, with the scope and port bindings it is read in;
/// or a junction's own end, its node known.
struct PendingEnd {
  ExpandedEnd ep;
  int scope = 0;
  int node = -1;
};

/// An expression as written and the scope its names are read in.
struct PendingExpr {
  TermPtr expr;
  int scope = 0;
};

/// An element's declaration as written, the node it became and its scope.
struct PendingElement {
  std::size_t node;
  ExpandedElement element;
  int scope;
};

struct PendingBond {
  std::string name;
  SourceLoc loc;
  PendingEnd from, to;
  std::optional<int> dim;
  SourceLoc dim_loc;
};

class Resolver {
 public:
  Resolver(Diagnostics& diags, ResolvedModel& out, const Limits& limits) : diags_(diags), m_(out), limits_(limits) {}

  void run(const ExpandedProgram& prog) {
    m_.scopes.push_back({"", ""});
    port_bindings_.emplace_back();
    symbols_.names = prog.symbols;
    symbols_.targets.assign(prog.symbols.size(), {});
    for (const ExpandedStmt& s : prog.stmts) {
      if (auto* c = std::get_if<std::shared_ptr<AstComponent>>(&s)) {
        const AstComponent& comp = **c;
        if (components_.count(comp.name)) {
          diags_.error(comp.loc, fmt::format("component `{}` is declared twice", comp.name),
                       "rename one of them");
          continue;
        }
        components_[comp.name] = *c;
        m_.components.push_back(*c);
      }
    }
    flatten(prog.stmts, 0, 0);
    if (too_big_) return;  // the model is not whole: nothing more to say about it
    evaluate_params();
    bind_bonds();
    label_bonds();
    bind_names(prog.unit_checks);
  }

 private:
  // ---- flattening ----------------------------------------------------------------
  bool claim_name(const std::string& full, const SourceLoc& loc, const char* what) {
    auto it = declared_.find(full);
    if (it != declared_.end()) {
      auto& d = diags_.error(loc, fmt::format("`{}` is already declared", full),
                             fmt::format("give this {} another name", what));
      d.notes.push_back({it->second, "first declared here"});
      return false;
    }
    declared_[full] = loc;
    return true;
  }

  /// The statements of the top level or of a component's body (as
  /// written: none of the expansion's extensions).
  void flatten(const std::vector<ExpandedStmt>& stmts, int scope, int depth) {
    const std::string prefix = m_.scopes[static_cast<std::size_t>(scope)].prefix;
    for (const ExpandedStmt& s : stmts) {
      if (too_big_) return;
      std::visit(
          [&](const auto& st) {
            using T = std::decay_t<decltype(st)>;
            if constexpr (requires { st.loc; })
              if (depth == 0) top_loc_ = st.loc;
            if constexpr (std::is_same_v<T, AstModel>) {
              if (m_.model_name.empty()) m_.model_name = st.name;
            } else if constexpr (std::is_same_v<T, ExpandedParam>) {
              if (!claim_name(prefix + st.name, st.loc, "parameter")) return;
              declares(st.symbol, SymbolTarget::Kind::Param, pending_params_.size());
              pending_params_.push_back({prefix + st.name, st.loc, st.value, scope, st.fold,
                                         declared_unit(st.unit, st.value), st.generated, st.dimension});
            } else if constexpr (std::is_same_v<T, ExpandedSignal>) {
              if (claim_name(prefix + st.name, st.loc, "signal")) {
                declares(st.symbol, SymbolTarget::Kind::Signal, m_.signals.size());
                m_.signals.push_back({prefix + st.name, st.loc, nullptr, nullptr, st.unit, st.generated});
                signal_exprs_.push_back({{st.value, scope}, {st.rate, scope}});
              }
            } else if constexpr (std::is_same_v<T, ExpandedOutput>) {
              if (st.drawing) {
                m_.drawings.push_back({st.drawing, st.loc, nullptr, nullptr});
                drawing_exprs_.push_back({{st.value, scope}, {st.modes, scope}});
                return;
              }
              if (claim_name("output " + prefix + st.name, st.loc, "output")) {
                m_.outputs.push_back({prefix + st.name, st.loc, nullptr, nullptr, st.unit, false});
                output_exprs_.push_back({st.value, scope});
              }
            } else if constexpr (std::is_same_v<T, ExpandedElement>) {
              if (!claim_name(prefix + st.name, st.loc, "element")) return;
              ResolvedNode n;
              n.kind = kind_of(st.kind);
              n.name = prefix + st.name;
              n.loc = st.loc;
              n.kind_loc = st.kind_loc;
              const ExpandedElement& el = st;
              n.tree = el.tree;
              n.generated = el.generated;
              n.element = BoundElement{el.kind, nullptr, {}, std::nullopt, el.configuration_dependent, el.state_limits};
              elements_.push_back({m_.nodes.size(), el, scope});
              declares(st.symbol, SymbolTarget::Kind::Node, m_.nodes.size());
              add_node(std::move(n));
            } else if constexpr (std::is_same_v<T, ExpandedJunction>) {
              if (!claim_name(prefix + st.name, st.loc, "junction")) return;
              ResolvedNode n;
              n.kind = st.type == '0' ? NodeKind::Zero : NodeKind::One;
              n.name = prefix + st.name;
              n.loc = st.loc;
              n.kind_loc = st.kind_loc;
              n.dim = st.dim;
              n.dim_loc = st.dim_loc;
              n.tree = st.tree, n.generated = st.generated;
              PendingEnd self;  // (its node known)
              self.ep.path = st.name;
              self.ep.loc = st.loc;
              self.scope = scope;
              self.node = static_cast<int>(m_.nodes.size());
              declares(st.symbol, SymbolTarget::Kind::Node, m_.nodes.size());
              add_node(std::move(n));
              for (const ExpandedEnd& in : st.inputs) add_bond("", in.loc, written(in, scope), self, std::nullopt, {});
              for (const ExpandedEnd& out : st.outputs) add_bond("", out.loc, self, written(out, scope), std::nullopt, {});
            } else if constexpr (std::is_same_v<T, ExpandedBond>) {
              std::string name = st.name.empty() ? "" : prefix + st.name;
              if (!name.empty() && !claim_name(name, st.loc, "bond")) return;
              declares(st.symbol, SymbolTarget::Kind::Bond, bonds_.size());  // (pending: its index in m_.bonds once bound)
              add_bond(name, st.loc, written(st.from, scope), written(st.to, scope), st.dim, st.dim_loc);
            } else if constexpr (std::is_same_v<T, AstSimulate>) {
              if (scope != 0) {
                diags_.error(st.loc, "`simulate` belongs at the top level, not inside a component",
                             "move the simulate { } block to the model file's top level");
                return;
              }
              if (simulate_seen_) {
                diags_.error(st.loc, "a second `simulate` block",
                             fmt::format("the model already has one at line {}; merge their settings into one block", simulate_line_));
                return;
              }
              simulate_seen_ = true;
              simulate_line_ = st.loc.line;
              read_settings(st);
            } else if constexpr (std::is_same_v<T, AstInstance>) {
              instantiate(st, scope, depth);
            } else {
              // components were collected up front; nested ones are rejected by the parser
            }
          },
          s);
      check_size();
    }
  }

  /// Past limits_.model_size elements, junctions and bonds the model stops
  /// here, at the top-level statement that grew it (a loop's statement, a body,
  /// an instance of components within components).
  void check_size() {
    const std::size_t size = m_.nodes.size() + bonds_.size();
    if (too_big_ || size <= static_cast<std::size_t>(limits_.model_size)) return;
    too_big_ = true;
    diags_.error(top_loc_,
                 fmt::format("the model grows past {} elements, junctions and bonds here", limits_.model_size),
                 "mbgc writes each of them into the generated C++ (the 2000-rod chain has 80000 and makes 115 MB "
                 "of it): make the loops shorter or the components' instances fewer");
  }

  /// A bond end as written in `scope`.
  static PendingEnd written(const ExpandedEnd& ep, int scope) {
    PendingEnd end;
    end.ep = ep;
    end.scope = scope;
    return end;
  }

  /// (Built member by member: GCC 12 at -O3 takes a braced PendingBond's strings for uninitialised.)
  void add_bond(const std::string& name, const SourceLoc& loc, const PendingEnd& from, const PendingEnd& to,
                std::optional<int> dim, const SourceLoc& dim_loc) {
    PendingBond b;
    b.name = name;
    b.loc = loc;
    b.from = from;
    b.to = to;
    b.dim = dim;
    b.dim_loc = dim_loc;
    bonds_.push_back(std::move(b));
  }

  void add_node(ResolvedNode n) {
    m_.node_index[n.name] = static_cast<int>(m_.nodes.size());
    m_.nodes.push_back(std::move(n));
  }

  void instantiate(const AstInstance& in, int scope, int depth) {
    const std::string prefix = m_.scopes[static_cast<std::size_t>(scope)].prefix;
    auto it = components_.find(in.component);
    if (it == components_.end()) {
      std::vector<std::string> names;
      for (const auto& [n, c] : components_) names.push_back(n);
      std::string near = closest_name(in.component, names);
      diags_.error(in.component_loc, fmt::format("unknown component `{}`", in.component),
                   near.empty() ? "declare it with component name(port a, ...) { ... } or import its file"
                                : fmt::format("did you mean `{}`?", near));
      return;
    }
    const AstComponent& comp = *it->second;
    if (depth > 32 || std::count(stack_.begin(), stack_.end(), comp.name)) {
      diags_.error(in.component_loc, fmt::format("component `{}` instantiates itself", comp.name),
                   "a component cannot contain an instance of itself, directly or through others");
      return;
    }
    if (!claim_name(prefix + in.name, in.loc, "instance")) return;
    int child = static_cast<int>(m_.scopes.size());
    m_.scopes.push_back({prefix + in.name + ".", comp.name});
    port_bindings_.emplace_back();
    std::set<std::string> given;
    std::map<std::string, SourceLoc> given_at;
    for (const AstAttr& a : in.args) {
      if (auto dup = given_at.find(a.key); dup != given_at.end()) {
        auto& d = diags_.error(a.loc, fmt::format("`{}` is given twice for instance `{}`", a.key, in.name),
                               "give each port and parameter once");
        d.notes.push_back({dup->second, "first given here"});
        continue;
      }
      given_at[a.key] = a.loc;
      given.insert(a.key);
      bool is_port = std::any_of(comp.ports.begin(), comp.ports.end(),
                                 [&](const AstEndpoint& p) { return p.path == a.key; });
      bool is_param = std::any_of(comp.params.begin(), comp.params.end(),
                                  [&](const AstParam& p) { return p.name == a.key; });
      if (is_port) {
        if (a.value->kind != AstExpr::Kind::Name) {
          diags_.error(a.value->loc, fmt::format("port `{}` must be connected to a junction or element", a.key),
                       fmt::format("write {} = node_name", a.key));
          continue;
        }
        PendingEnd bound;
        bound.ep.path = a.value->name;
        bound.ep.loc = a.value->loc;
        bound.scope = scope;
        port_bindings_[static_cast<std::size_t>(child)][a.key] = bound;
      } else if (is_param) {
        // the value's own unit, else the interface's: `param V = 12 {V}`
        std::optional<DeclaredUnit> unit = declared_unit(std::nullopt, a.value);
        for (const AstParam& p : comp.params)
          if (p.name == a.key && !unit) unit = declared_unit(p.unit, p.value);
        pending_params_.push_back({m_.scopes.back().prefix + a.key, a.loc, to_term(a.value), scope, false, unit, false, std::nullopt});
        declared_[m_.scopes.back().prefix + a.key] = a.loc;
      } else {
        std::vector<std::string> names;
        for (const auto& p : comp.ports) names.push_back(p.path);
        for (const auto& p : comp.params) names.push_back(p.name);
        std::string near = closest_name(a.key, names);
        diags_.error(a.loc, fmt::format("component `{}` has no port or parameter `{}`", comp.name, a.key),
                     near.empty() ? fmt::format("its interface is ({})", fmt::join(names, ", "))
                                  : fmt::format("did you mean `{}`?", near));
      }
    }
    for (const AstEndpoint& p : comp.ports) {
      if (!given.count(p.path)) unconnected_ports_.insert(m_.scopes.back().prefix + p.path);
      if (!given.count(p.path))
        diags_.error(in.loc, fmt::format("port `{}` of component `{}` is not connected", p.path, comp.name),
                     fmt::format("connect it: instance {} = {}(..., {} = some_junction)", in.name, comp.name, p.path));
    }
    for (const AstParam& p : comp.params) {
      if (given.count(p.name)) continue;
      if (!p.value) {
        diags_.error(in.loc, fmt::format("parameter `{}` of component `{}` has no default and is not given", p.name, comp.name),
                     fmt::format("write instance {} = {}(..., {} = value)", in.name, comp.name, p.name));
        continue;
      }
      pending_params_.push_back(
          {m_.scopes.back().prefix + p.name, p.loc, to_term(p.value), child, false, declared_unit(p.unit, p.value), false, std::nullopt});
      declared_[m_.scopes.back().prefix + p.name] = p.loc;
    }
    stack_.push_back(comp.name);
    std::vector<ExpandedStmt> body;  // as written: none of the expansion's extensions
    for (const AstStmt& st : comp.body)
      if (ExpandedStmt e; as_expanded(st, e)) body.push_back(std::move(e));
    flatten(body, child, depth + 1);
    stack_.pop_back();
  }

  bool simulate_seen_ = false;
  int simulate_line_ = 0;

  void read_settings(const AstSimulate& sim) {
    for (const AstAttr& a : sim.settings) {
      const SimSetting* setting = nullptr;
      for (const SimSetting& s : sim_settings())
        if (a.key == s.name) setting = &s;
      if (!setting) {
        std::vector<std::string> names;
        for (const SimSetting& s : sim_settings()) names.emplace_back(s.name);
        std::string near = closest_name(a.key, names);
        diags_.error(a.loc, fmt::format("unknown simulation setting `{}`", a.key),
                     near.empty() ? fmt::format("settings are {}", fmt::join(names, ", "))
                                  : fmt::format("did you mean `{}`?", near));
        continue;
      }
      if (!setting->slot) {  // the solver
        if (a.value->kind != AstExpr::Kind::Name || !mbgrt::find_integrator(a.value->name)) {
          diags_.error(a.value->loc, "unknown solver", "choose one of " + mbgrt::integrator_names());
          continue;
        }
        m_.settings.solver = a.value->name;
        m_.settings.solver_loc = a.value->loc;
        continue;
      }
      if (setting->dimension) {  // a literal's unit here; a parameter's, with the model's (units/check)
        const std::string what = fmt::format("{} of the simulate block", a.key);
        if (!units::check_literal_units(*a.value, *setting->dimension, what, diags_)) continue;
        if (units::reads_a_name(*a.value)) setting_checks_.push_back({to_term(a.value), *setting->dimension, a.loc, what});
      }
      settings_.push_back({&(m_.settings.*(setting->slot)), a, setting});
    }
  }

  // ---- parameters --------------------------------------------------------------------
  void evaluate_params() {
    for (std::size_t i = 0; i < pending_params_.size(); ++i) param_by_name_[pending_params_[i].full] = i;
    state_.assign(pending_params_.size(), 0);
    m_.param_values.assign(pending_params_.size(), Value{});
    has_value_.assign(pending_params_.size(), 0);
    for (std::size_t i = 0; i < pending_params_.size(); ++i) evaluate(i);
    for (auto& [slot, attr, setting] : settings_) {
      auto v = lower(*attr.value, param_lookup(0), diags_);
      if (!v) continue;
      double c = 0;
      if (!v->is_scalar() || !is_const(substitute_params(v->items[0]), &c)) {
        diags_.error(attr.value->loc, fmt::format("`{}` must be a constant number", attr.key),
                     "simulation settings may use numbers and parameters, not time or states");
        continue;
      }
      if (setting->fraction && !(c >= 0 && c <= 1)) {
        diags_.error(attr.value->loc, fmt::format("`{}` must be from 0 to 1", attr.key),
                     setting->meaning ? setting->meaning : "");
        continue;
      }
      if (!setting->fraction && !(c > 0)) {
        diags_.error(attr.value->loc, fmt::format("`{}` must be positive", attr.key), "");
        continue;
      }
      *slot = c;
    }
  }

  /// Fold parameters to their current values (for settings, which are fixed at compile time).
  Expr substitute_params(const Expr& e) {
    return rewrite(e, [&](const Expr& n) -> Expr {
      if (n->op != Op::Param) return nullptr;
      return substitute_params(m_.params[static_cast<std::size_t>(n->id)].value);
    });
  }

  NameLookup param_lookup(int scope) {
    return [this, scope](const std::string& name, const SourceLoc& loc) -> std::optional<Value> {
      return lookup_param(name, scope, loc);
    };
  }
  /// As param_lookup, for a parameter's value (a term whose refs are names,
  /// or the multibody layer's symbols).
  RefLookup param_ref_lookup(int scope) {
    return [this, scope](const Term& leaf) -> std::optional<Value> {
      if (leaf.ref.kind != Ref::Kind::Symbol) return lookup_param(leaf.name, scope, leaf.loc);
      const std::size_t i = symbols_.param(leaf.ref);
      if (!evaluate(i, &leaf.loc)) return std::nullopt;
      return m_.param_values[i];
    };
  }

  std::optional<Value> lookup_param(const std::string& name, int scope, const SourceLoc& loc) {
    std::vector<std::string> tries;
    if (scope != 0) tries.push_back(m_.scopes[static_cast<std::size_t>(scope)].prefix + name);
    tries.push_back(name);
    for (const std::string& full : tries) {
      auto it = param_by_name_.find(full);
      if (it == param_by_name_.end()) continue;
      if (!evaluate(it->second, &loc)) return std::nullopt;
      return m_.param_values[it->second];
    }
    std::vector<std::string> names;
    for (const auto& [n, i] : param_by_name_) names.push_back(n);
    std::sort(names.begin(), names.end());  // (from a hash map: the suggestion must not depend on its order)
    std::string near = closest_name(name, names);
    if (m_.node_index.count(tries.front()) || m_.node_index.count(name) || name.find('.') != std::string::npos) {
      diags_.error(loc, fmt::format("`{}` is not a parameter", name),
                   "parameters and simulation settings may only use numbers and other parameters");
    } else {
      diags_.error(loc, fmt::format("unknown parameter `{}`", name),
                   near.empty() ? "declare it with param name = value" : fmt::format("did you mean `{}`?", near));
    }
    return std::nullopt;
  }

  /// Evaluate pending parameter i (depth-first; a cycle is reported once).
  bool evaluate(std::size_t i, const SourceLoc* used_at = nullptr) {
    if (state_[i] == 2) return has_value_[i] != 0;
    if (state_[i] == 1) {
      if (!cycle_reported_) {
        cycle_reported_ = true;
        std::vector<std::string> chain;
        for (std::size_t k : eval_stack_) chain.push_back(pending_params_[k].full);
        auto pos = std::find(eval_stack_.begin(), eval_stack_.end(), i);
        std::vector<std::string> cycle;
        for (auto p = pos; p != eval_stack_.end(); ++p) cycle.push_back(pending_params_[*p].full);
        cycle.push_back(pending_params_[i].full);
        auto& d = diags_.error(pending_params_[i].loc,
                               fmt::format("parameter cycle: {}", fmt::join(cycle, " -> ")),
                               "a parameter cannot depend on itself; give one of them a value");
        if (used_at) d.notes.push_back({*used_at, "the cycle closes here"});
      }
      return false;
    }
    state_[i] = 1;
    eval_stack_.push_back(i);
    const PendingParam& p = pending_params_[i];
    auto v = lower(*p.expr, param_ref_lookup(p.scope), diags_);
    eval_stack_.pop_back();
    state_[i] = 2;
    if (!v) return false;
    for (const Expr& item : v->items) {
      if (depends_on_time(item)) {
        diags_.error(p.expr->loc, fmt::format("parameter `{}` depends on time", p.full),
                     "parameters are constant; use a signal for a time-varying quantity");
        return false;
      }
    }
    Value as_params = *v;
    for (int k = 0; k < v->length(); ++k) {
      if (p.fold && is_const(v->items[static_cast<std::size_t>(k)])) continue;  // stays the number it is
      std::string name = v->is_scalar() ? p.full
                         : v->cols == 1 ? fmt::format("{}[{}]", p.full, k + 1)
                                        : fmt::format("{}[{},{}]", p.full, k / v->cols + 1, k % v->cols + 1);
      Parameter par;
      par.name = name;
      par.loc = p.loc;
      par.value = v->items[static_cast<std::size_t>(k)];
      par.literal = is_const(par.value, &par.literal_value);
      par.unit = p.unit;
      par.generated = p.generated;
      par.stated = p.stated;
      m_.params.push_back(par);
      as_params.items[static_cast<std::size_t>(k)] = param(static_cast<int>(m_.params.size()) - 1);
    }
    m_.param_values[i] = as_params;
    has_value_[i] = 1;
    return true;
  }

  // ---- bonds --------------------------------------------------------------------------
  std::optional<ResolvedEnd> bind_end(const PendingEnd& end, int depth = 0) {
    if (end.node >= 0) return ResolvedEnd{end.node, 0, end.ep.loc};
    if (end.ep.symbol >= 0) return layer_end(end.ep);
    const Scope& sc = m_.scopes[static_cast<std::size_t>(end.scope)];
    const std::string& path = end.ep.path;
    std::string head = path.substr(0, path.find('.'));
    auto& ports = port_bindings_[static_cast<std::size_t>(end.scope)];
    if (auto p = ports.find(head); p != ports.end() && depth < 64) {
      if (head != path) {
        diags_.error(end.ep.loc, fmt::format("`{}` is a port; it has no parts", head), "connect to the port itself");
        return std::nullopt;
      }
      auto bound = bind_end(p->second, depth + 1);
      if (bound) bound->loc = end.ep.loc;
      return bound;
    }
    if (unconnected_ports_.count(sc.prefix + head)) return std::nullopt;  // reported at the instance
    std::string full = sc.prefix + path;
    if (auto it = m_.node_index.find(full); it != m_.node_index.end()) return ResolvedEnd{it->second, 0, end.ep.loc};
    auto dot = full.rfind('.');
    if (dot != std::string::npos) {
      std::string stem = full.substr(0, dot), port = full.substr(dot + 1);
      if (auto it = m_.node_index.find(stem); it != m_.node_index.end()) {
        if (!is_two_port(m_.nodes[static_cast<std::size_t>(it->second)].kind)) {
          diags_.error(end.ep.loc, fmt::format("`{}` has no port `{}`", stem, port),
                       "only two-ports (TF, GY, MTF, MGY) have ports p1 and p2; connect the element itself");
          return std::nullopt;
        }
        if (port != "p1" && port != "p2") {
          diags_.error(end.ep.loc, fmt::format("two-port `{}` has no port `{}`", stem, port),
                       "two-ports have ports p1 (power in) and p2 (power out)");
          return std::nullopt;
        }
        return ResolvedEnd{it->second, port == "p1" ? 1 : 2, end.ep.loc};
      }
    }
    std::vector<std::string> names;
    for (const auto& [n, i] : m_.node_index)
      if (n.rfind(sc.prefix, 0) == 0) names.push_back(n.substr(sc.prefix.size()));
    for (const auto& [n, b] : ports) names.push_back(n);
    std::sort(names.begin(), names.end());  // (node_index is a hash map: the suggestion must not depend on its order)
    std::string near = closest_name(path, names);
    diags_.error(end.ep.loc, fmt::format("bond to nowhere: no element or junction named `{}`", path),
                 near.empty() ? "declare it, or fix the name" : fmt::format("did you mean `{}`?", near));
    return std::nullopt;
  }

  void bind_bonds() {
    std::vector<int> bound(bonds_.size(), -1);  // pending bond -> its index in m_.bonds
    for (std::size_t i = 0; i < bonds_.size(); ++i) {
      const PendingBond& pb = bonds_[i];
      auto from = bind_end(pb.from);
      auto to = bind_end(pb.to);
      if (!from || !to) continue;
      if (from->node == to->node) {
        diags_.error(pb.loc, fmt::format("bond from `{}` to itself", m_.nodes[static_cast<std::size_t>(from->node)].name),
                     "a bond connects two different nodes");
        continue;
      }
      bound[i] = static_cast<int>(m_.bonds.size());
      m_.bonds.push_back({pb.name, "", pb.loc, *from, *to, pb.dim, pb.dim_loc});
    }
    for (SymbolTarget& t : symbols_.targets)
      if (t.kind == SymbolTarget::Kind::Bond) t.index = static_cast<std::size_t>(bound[t.index]);
  }

  /// An end the multibody layer wrote: its symbol's node (at a two-port, the port it names).
  ResolvedEnd layer_end(const ExpandedEnd& ep) const {
    const SymbolTarget& t = symbols_.targets.at(static_cast<std::size_t>(ep.symbol));
    const std::string& name = symbols_.names.at(static_cast<std::size_t>(ep.symbol));
    if (t.kind != SymbolTarget::Kind::Node)
      throw InternalError(fmt::format("the multibody layer bonds `{}`, which it did not declare as an element or a junction", name));
    if (ep.port != 0 && !is_two_port(m_.nodes[t.index].kind))
      throw InternalError(fmt::format("the multibody layer bonds `{}` at a port it has not", name));
    return ResolvedEnd{static_cast<int>(t.index), ep.port, ep.loc};
  }

  /// Statement `symbol` of the multibody layer's (none: -1) is `index` of `kind`.
  void declares(int symbol, SymbolTarget::Kind kind, std::size_t index) {
    if (symbol >= 0) symbols_.targets[static_cast<std::size_t>(symbol)] = {kind, index};
  }

  // ---- names in expressions -------------------------------------------------------
  /// Unnamed bonds are called b<number>, unless a node or a bond took that name.
  void label_bonds() {
    std::set<std::string> taken;
    for (const ResolvedBond& rb : m_.bonds) taken.insert(rb.name);
    for (const auto& [name, index] : m_.node_index) taken.insert(name);
    for (std::size_t b = 0; b < m_.bonds.size(); ++b) {
      ResolvedBond& rb = m_.bonds[b];
      rb.label = rb.name;
      if (!rb.label.empty()) continue;
      const int number = static_cast<int>(b) + 1;
      rb.label = fmt::format("b{}", number);
      for (int k = 2; taken.count(rb.label); ++k) rb.label = fmt::format("b{}_{}", number, k);
      taken.insert(rb.label);
    }
  }

  /// Every element law, signal, output and drawing, and what the multibody
  /// layer and the simulate block state of a value's unit, with their names
  /// bound (sema/bind.hpp), in the order the graph pass lowers them.
  void bind_names(const std::vector<ExpandedUnitCheck>& layer_checks) {
    for (std::size_t i = 0; i < pending_params_.size(); ++i)
      if (has_value_[i]) m_.param_index.emplace(pending_params_[i].full, static_cast<int>(i));
    if (diags_.has_errors()) return;  // a name may be unknown only because its declaration was in error
    const Binder binder(m_, symbols_);
    auto bind = [&](const TermPtr& e, int scope, OwnQuantities own = {}) -> TermPtr {
      return e ? binder.bind(*e, scope, diags_, own) : nullptr;
    };
    for (const PendingElement& pe : elements_) {
      const ExpandedElement& el = pe.element;
      BoundElement& out = *m_.nodes[pe.node].element;
      const NodeKind kind = m_.nodes[pe.node].kind;
      OwnQuantities own;  // inside a law: the element's own e, f and state
      if (!is_two_port(kind)) {
        own.any = true;
        const bool free_rate = kind == NodeKind::Sf && !el.value &&
                               std::any_of(el.attrs.begin(), el.attrs.end(),
                                           [](const TermAttr& a) { return a.key == element_setting::rate0.key; });
        own.state = kind == NodeKind::I ? 'p' : (kind == NodeKind::C || free_rate) ? 'q' : 0;
      }
      out.value = bind(el.value, pe.scope);
      for (const TermAttr& a : el.attrs) {
        const ElementSetting* setting = find_element_setting(kind, a.key);
        const bool law = setting && setting->role == ElementSetting::Role::Law;
        out.attrs.push_back({a.key, a.loc, setting ? bind(a.value, pe.scope, law ? own : OwnQuantities{}) : nullptr});
      }
      if (el.constraint) {
        BoundConstraintLaw law;
        for (std::size_t f = 0; f < ConstraintLaw::fields().size(); ++f) {
          const TermPtr& value = (*el.constraint).*ConstraintLaw::fields()[f].member;
          law.*BoundConstraintLaw::fields()[f].member = bind(value, pe.scope, f == 0 ? own : OwnQuantities{});
        }
        out.constraint = law;
      }
    }
    for (std::size_t i = 0; i < m_.signals.size(); ++i) {
      m_.signals[i].expr = bind(signal_exprs_[i].first.expr, signal_exprs_[i].first.scope);
      m_.signals[i].rate = bind(signal_exprs_[i].second.expr, signal_exprs_[i].second.scope);
    }
    for (std::size_t i = 0; i < m_.outputs.size(); ++i) m_.outputs[i].expr = bind(output_exprs_[i].expr, output_exprs_[i].scope);
    for (std::size_t i = 0; i < m_.drawings.size(); ++i) {
      m_.drawings[i].pose = bind(drawing_exprs_[i].first.expr, drawing_exprs_[i].first.scope);
      m_.drawings[i].modes = bind(drawing_exprs_[i].second.expr, drawing_exprs_[i].second.scope);
    }
    // a value that does not bind here was reported where the multibody layer read it
    Diagnostics scratch(diags_.sources());
    for (const std::vector<ExpandedUnitCheck>* checks : {&layer_checks, static_cast<const std::vector<ExpandedUnitCheck>*>(&setting_checks_)})
      for (const ExpandedUnitCheck& c : *checks)
        m_.unit_checks.push_back({binder.bind(*c.value, 0, scratch), c.dimension, c.loc, c.what, c.quantity});
  }

  Diagnostics& diags_;
  ResolvedModel& m_;
  SymbolTable symbols_;                                                 // what the layer's symbols declare
  std::vector<PendingElement> elements_;                                // per element node, in order
  std::vector<std::pair<PendingExpr, PendingExpr>> signal_exprs_;       // per signal: its value and rate
  std::vector<PendingExpr> output_exprs_;                               // per output
  std::vector<std::pair<PendingExpr, PendingExpr>> drawing_exprs_;      // per drawing: its pose and modes
  std::vector<ExpandedUnitCheck> setting_checks_;                       // the simulate block's, with a name
  std::vector<char> has_value_;                                         // per pending parameter
  std::map<std::string, std::shared_ptr<const AstComponent>> components_;
  std::unordered_map<std::string, SourceLoc> declared_;  // looked up only
  std::vector<std::map<std::string, PendingEnd>> port_bindings_;  // per scope
  std::set<std::string> unconnected_ports_;                      // "u1.b": reported once
  std::vector<PendingParam> pending_params_;
  std::unordered_map<std::string, std::size_t> param_by_name_;
  std::vector<int> state_;
  std::vector<std::size_t> eval_stack_;
  bool cycle_reported_ = false;
  std::vector<PendingBond> bonds_;
  std::vector<std::string> stack_;
  const Limits& limits_;
  SourceLoc top_loc_;     ///< the top-level statement being flattened
  bool too_big_ = false;  ///< past limits_.model_size: reported, flattening stopped
  struct PendingSetting {
    std::optional<double>* slot;
    AstAttr attr;
    const SimSetting* setting;
  };
  std::vector<PendingSetting> settings_;
};

}  // namespace

ResolvedModel resolve(const ExpandedProgram& program, const std::string& source_file, Diagnostics& diags,
                      const Limits& limits) {
  ResolvedModel m;
  m.source_file = source_file;
  Resolver r(diags, m, limits);
  r.run(program);
  if (m.model_name.empty()) m.model_name = "model";
  return m;
}

}  // namespace mbgc::sema
