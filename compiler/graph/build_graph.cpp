#include "graph/build_graph.hpp"
#include "ir/element_settings.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <functional>
#include <map>
#include <numeric>
#include <set>

namespace mbgc::graph {
namespace {

using namespace mbgc::ir;

/// Dimension slots: one per bond, merged by junctions and scalar two-ports.
class DimSlots {
 public:
  explicit DimSlots(std::size_t n) : parent_(n), fixed_(n, 0), why_(n) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int a) {
    while (parent_[static_cast<std::size_t>(a)] != a) a = parent_[static_cast<std::size_t>(a)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(a)])];
    return a;
  }
  /// Returns false (and the conflicting reason) if both are fixed differently.
  bool unite(int a, int b, std::pair<SourceLoc, std::string>* conflict) {
    a = find(a);
    b = find(b);
    if (a == b) return true;
    int fa = fixed_[static_cast<std::size_t>(a)], fb = fixed_[static_cast<std::size_t>(b)];
    if (fa && fb && fa != fb) {
      *conflict = why_[static_cast<std::size_t>(a)];
      return false;
    }
    parent_[static_cast<std::size_t>(b)] = a;
    if (!fa && fb) {
      fixed_[static_cast<std::size_t>(a)] = fb;
      why_[static_cast<std::size_t>(a)] = why_[static_cast<std::size_t>(b)];
    }
    return true;
  }
  bool fix(int a, int dim, SourceLoc loc, std::string why, std::pair<SourceLoc, std::string>* conflict) {
    a = find(a);
    int& f = fixed_[static_cast<std::size_t>(a)];
    if (f && f != dim) {
      *conflict = why_[static_cast<std::size_t>(a)];
      return false;
    }
    if (!f) {
      f = dim;
      why_[static_cast<std::size_t>(a)] = {loc, std::move(why)};
    }
    return true;
  }
  int dim(int a) {
    int f = fixed_[static_cast<std::size_t>(find(a))];
    return f ? f : 1;
  }
  int fixed(int a) { return fixed_[static_cast<std::size_t>(find(a))]; }

 private:
  std::vector<int> parent_;
  std::vector<int> fixed_;
  std::vector<std::pair<SourceLoc, std::string>> why_;
};

class Builder {
 public:
  Builder(const ResolvedModel& m, const SourceManager& sources, Diagnostics& diags)
      : m_(m), sources_(sources), diags_(diags) {}

  BondGraph run() {
    g_.model_name = m_.model_name;
    g_.source_file = m_.source_file;
    g_.params = m_.params;
    g_.settings = m_.settings;
    make_nodes_and_bonds();
    if (diags_.has_errors()) return std::move(g_);
    infer_dimensions();
    if (diags_.has_errors()) return std::move(g_);
    make_variables();
    lower_laws();
    lower_signals_and_outputs();
    return std::move(g_);
  }

 private:
  // ---- structure -----------------------------------------------------------------
  void make_nodes_and_bonds() {
    for (const ResolvedNode& rn : m_.nodes) {
      GraphNode n;
      n.kind = rn.kind;
      n.name = rn.name;
      n.loc = rn.loc;
      n.tree_node = rn.tree.node, n.tree_parent = rn.tree.parent;
      n.generated = rn.generated;
      if (is_two_port(rn.kind)) n.bonds = {-1, -1};
      g_.nodes.push_back(std::move(n));
    }
    for (const ResolvedBond& rb : m_.bonds) {
      Bond b;
      b.number = static_cast<int>(g_.bonds.size()) + 1;
      b.name = rb.label;
      b.loc = rb.loc;
      b.from = rb.from.node;
      b.to = rb.to.node;
      int index = static_cast<int>(g_.bonds.size());
      g_.bonds.push_back(b);
      attach(index, rb.from, /*outgoing=*/true);
      attach(index, rb.to, /*outgoing=*/false);
    }
    report_bonds_written_twice();
    for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
      const GraphNode& n = g_.nodes[i];
      if (is_junction(n.kind)) {
        if (n.bonds.empty())
          diags_.error(n.loc, fmt::format("{}-junction `{}` has no bonds", node_kind_name(n.kind), n.name),
                       "connect it, or remove it");
      } else if (is_two_port(n.kind)) {
        for (int p = 0; p < 2; ++p)
          if (n.bonds[static_cast<std::size_t>(p)] < 0)
            diags_.error(n.loc, fmt::format("port p{} of {} `{}` is not connected", p + 1, node_kind_name(n.kind), n.name),
                         p == 0 ? fmt::format("add a bond into it: bond some_node -> {}", n.name)
                                : fmt::format("add a bond out of it: bond {} -> some_node", n.name));
      } else if (n.bonds.empty()) {
        diags_.error(n.loc, fmt::format("{} `{}` is not connected to anything", node_kind_name(n.kind), n.name),
                     "bond it to a junction, e.g. in `1 j : ... -> " + n.name + "`");
      }
    }
  }

  // Two bonds between the same two junctions carry the same effort and flow:
  // the power between them counts twice. A junction-to-junction bond written
  // in both junctions' lists gives that, so it is an error naming both places.
  // (An element's port takes one bond; attach() reports a second one.)
  void report_bonds_written_twice() {
    std::map<std::pair<int, int>, std::size_t> first;  // {junction, junction} -> bond index
    for (std::size_t i = 0; i < m_.bonds.size(); ++i) {
      const ResolvedBond& rb = m_.bonds[i];
      const GraphNode& from = g_.nodes[static_cast<std::size_t>(rb.from.node)];
      const GraphNode& to = g_.nodes[static_cast<std::size_t>(rb.to.node)];
      if (!is_junction(from.kind) || !is_junction(to.kind)) continue;
      auto [it, fresh] = first.emplace(std::minmax(rb.from.node, rb.to.node), i);
      if (fresh) continue;
      const ResolvedBond& earlier = m_.bonds[it->second];
      bool one_list = earlier.loc.file == rb.loc.file && earlier.loc.line == rb.loc.line;
      Diagnostic& d =
          one_list ? diags_.error(rb.loc, fmt::format("a second bond between `{}` and `{}`", from.name, to.name),
                                  "two bonds between the same junctions carry the same effort and flow, so their power "
                                  "counts twice; list the bond once")
                   : diags_.error(rb.loc,
                                  fmt::format("the bond between `{}` and `{}` is listed at both of its junctions", from.name, to.name),
                                  fmt::format("a bond between two junctions is written once, in either junction's list: remove "
                                              "`{}` from the list of `{}`, or `{}` from the list of `{}`",
                                              to.name, from.name, from.name, to.name));
      d.notes.push_back({earlier.loc, one_list ? "the first bond is here" : "it is listed here too"});
    }
  }

  void attach(int bond, const ResolvedEnd& end, bool outgoing) {
    GraphNode& n = g_.nodes[static_cast<std::size_t>(end.node)];
    if (is_two_port(n.kind)) {
      int port = end.port ? end.port : (outgoing ? 2 : 1);
      int& slot = n.bonds[static_cast<std::size_t>(port - 1)];
      if (slot >= 0) {
        auto& d = diags_.error(end.loc, fmt::format("port p{} of `{}` already has a bond", port, n.name),
                               "each port of a two-port takes exactly one bond; join several through a junction");
        d.notes.push_back({g_.bonds[static_cast<std::size_t>(slot)].loc, "the first bond is here"});
        return;
      }
      slot = bond;
      return;
    }
    if (end.port) {
      diags_.error(end.loc, fmt::format("`{}` has no ports", n.name), "connect the element itself");
      return;
    }
    if (!is_junction(n.kind) && !n.bonds.empty()) {
      auto& d = diags_.error(end.loc, fmt::format("{} `{}` already has a bond", node_kind_name(n.kind), n.name),
                             "a one-port element takes exactly one bond; put a junction in between");
      d.notes.push_back({g_.bonds[static_cast<std::size_t>(n.bonds[0])].loc, "the first bond is here"});
      return;
    }
    n.bonds.push_back(bond);
  }

  // ---- dimensions -------------------------------------------------------------------
  /// Lower an element's value only to learn its shape (variables read as scalars).
  std::optional<Value> probe_shape(const ResolvedNode& rn) {
    if (!rn.element || !rn.element->value) return std::nullopt;
    Diagnostics scratch(sources_);
    RefLookup lookup = [&](const Term& leaf) -> std::optional<Value> {
      if (leaf.ref.kind == Ref::Kind::Param) return param_value(leaf.ref);
      return Value::scalar(constant(0));
    };
    return lower(*rn.element->value, lookup, scratch);
  }

  void infer_dimensions() {
    DimSlots slots(g_.bonds.size());
    std::pair<SourceLoc, std::string> conflict;
    auto mismatch = [&](SourceLoc at, int dim, const std::string& what) {
      auto& d = diags_.error(at, fmt::format("multibond dimension mismatch: {} needs dimension {}", what, dim),
                             "every bond at a junction has the same dimension; check the shapes of the elements");
      d.notes.push_back({conflict.first, conflict.second});
    };
    for (std::size_t b = 0; b < g_.bonds.size(); ++b) {
      const ResolvedBond& rb = m_.bonds[b];
      if (rb.dim && !slots.fix(static_cast<int>(b), *rb.dim, rb.dim_loc, fmt::format("bond declared [{}] here", *rb.dim), &conflict))
        mismatch(rb.dim_loc, *rb.dim, fmt::format("bond {}", g_.bonds[b].number));
    }
    for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
      GraphNode& n = g_.nodes[i];
      const ResolvedNode& rn = m_.nodes[i];
      if (is_junction(n.kind)) {
        if (rn.dim && !n.bonds.empty() &&
            !slots.fix(n.bonds[0], *rn.dim, rn.dim_loc, fmt::format("junction `{}` declared [{}] here", n.name, *rn.dim), &conflict))
          mismatch(rn.dim_loc, *rn.dim, fmt::format("junction `{}`", n.name));
        for (std::size_t k = 1; k < n.bonds.size(); ++k)
          if (!slots.unite(n.bonds[0], n.bonds[k], &conflict))
            mismatch(g_.bonds[static_cast<std::size_t>(n.bonds[k])].loc, slots.fixed(n.bonds[k]),
                     fmt::format("bond {} at junction `{}`", g_.bonds[static_cast<std::size_t>(n.bonds[k])].number, n.name));
        continue;
      }
      auto shape = probe_shape(rn);
      if (is_two_port(n.kind)) {
        if (n.bonds[0] < 0 || n.bonds[1] < 0) continue;
        // The probe reads states as scalars; a modulus that needs their real shapes
        // (jacobian(g, body.r.q)) cannot be probed: its ports take their dimensions
        // from the junctions, and lower_laws checks the real shape against them.
        if (!shape) continue;
        if (shape->is_scalar()) {
          if (!slots.unite(n.bonds[0], n.bonds[1], &conflict))
            mismatch(n.loc, slots.fixed(n.bonds[0]), fmt::format("scalar {} `{}` (same dimension on both ports)", node_kind_name(n.kind), n.name));
          continue;
        }
        // TF: f2 = T f1 (T is dim2 x dim1); GY: e2 = G f1 (likewise).
        if (!slots.fix(n.bonds[0], shape->cols, n.loc, fmt::format("`{}` is {} (port p1 has dimension {})", n.name, shape->shape(), shape->cols), &conflict))
          mismatch(n.loc, shape->cols, fmt::format("port p1 of `{}`", n.name));
        if (!slots.fix(n.bonds[1], shape->rows, n.loc, fmt::format("`{}` is {} (port p2 has dimension {})", n.name, shape->shape(), shape->rows), &conflict))
          mismatch(n.loc, shape->rows, fmt::format("port p2 of `{}`", n.name));
        continue;
      }
      if (n.bonds.empty() || !shape || shape->is_scalar()) continue;
      int dim = 0;
      bool is_source = n.kind == NodeKind::Se || n.kind == NodeKind::Sf;
      if (is_source) {
        if (!shape->is_vector()) {
          diags_.error(rn.element->value->loc, fmt::format("{} `{}` needs a scalar or a vector, not {}", node_kind_name(n.kind), n.name, shape->shape()),
                       "write a vector as [a, b, c]");
          continue;
        }
        dim = shape->length();
      } else {
        if (shape->rows != shape->cols) {
          diags_.error(rn.element->value->loc, fmt::format("{} `{}` needs a scalar or a square matrix, not {}", node_kind_name(n.kind), n.name, shape->shape()),
                       "an n-dimensional I, C or R takes an n x n matrix, e.g. diag(m, m, J)");
          continue;
        }
        dim = shape->rows;
      }
      if (!slots.fix(n.bonds[0], dim, n.loc, fmt::format("`{}` is {} here", n.name, shape->shape()), &conflict))
        mismatch(n.loc, dim, fmt::format("{} `{}`", node_kind_name(n.kind), n.name));
    }
    for (std::size_t b = 0; b < g_.bonds.size(); ++b) g_.bonds[b].dim = slots.dim(static_cast<int>(b));
    for (GraphNode& n : g_.nodes) {
      if (n.bonds.empty() || n.bonds[0] < 0) continue;
      n.dim = g_.bonds[static_cast<std::size_t>(n.bonds[0])].dim;
      if (is_two_port(n.kind) && n.bonds[1] >= 0) n.dim2 = g_.bonds[static_cast<std::size_t>(n.bonds[1])].dim;
    }
  }

  // ---- variables ----------------------------------------------------------------------
  static std::string component_name(const std::string& base, const char* q, int k, int dim) {
    return dim == 1 ? fmt::format("{}.{}", base, q) : fmt::format("{}.{}[{}]", base, q, k + 1);
  }

  void make_variables() {
    // Name bond variables after the element they feed, so dumps and code read
    // in model terms: "armature_l.f" rather than "b3.f".
    std::vector<std::string> base(g_.bonds.size());
    std::vector<std::string> suffix(g_.bonds.size());
    for (std::size_t b = 0; b < g_.bonds.size(); ++b) base[b] = g_.bonds[b].name;
    for (const GraphNode& n : g_.nodes) {
      if (is_junction(n.kind)) continue;
      for (std::size_t p = 0; p < n.bonds.size(); ++p) {
        int b = n.bonds[p];
        if (b < 0 || m_.bonds[static_cast<std::size_t>(b)].name.size()) continue;
        base[static_cast<std::size_t>(b)] = n.name;
        if (is_two_port(n.kind)) suffix[static_cast<std::size_t>(b)] = std::to_string(p + 1);
      }
    }
    for (std::size_t b = 0; b < g_.bonds.size(); ++b) {
      Bond& bond = g_.bonds[b];
      std::string e = "e" + suffix[b], f = "f" + suffix[b];
      for (int k = 0; k < bond.dim; ++k) {
        bond.effort_vars.push_back(g_.add_var(component_name(base[b], e.c_str(), k, bond.dim), VarKind::Effort, bond.loc, static_cast<int>(b)));
        bond.flow_vars.push_back(g_.add_var(component_name(base[b], f.c_str(), k, bond.dim), VarKind::Flow, bond.loc, static_cast<int>(b)));
      }
    }
    for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
      GraphNode& n = g_.nodes[i];
      if (n.bonds.empty()) continue;
      if (is_free_rate(m_.nodes[i])) {
        for (int k = 0; k < n.dim; ++k) n.state_vars.push_back(g_.add_var(component_name(n.name, "rate", k, n.dim), VarKind::State, n.loc));
        continue;
      }
      if (!is_storage(n.kind)) continue;
      const char* q = n.kind == NodeKind::I ? "p" : "q";
      for (int k = 0; k < n.dim; ++k)
        n.state_vars.push_back(g_.add_var(component_name(n.name, q, k, n.dim), VarKind::State, n.loc));
    }
    for (const ResolvedExpr& s : m_.signals) signal_var_.push_back(g_.add_var(s.name, VarKind::Signal, s.loc));
  }

  Value bond_value(int bond, bool effort, int sign) const {
    const Bond& b = g_.bonds[static_cast<std::size_t>(bond)];
    Value v{b.dim, 1, {}};
    for (int k = 0; k < b.dim; ++k) {
      Expr x = var(effort ? b.effort_vars[static_cast<std::size_t>(k)] : b.flow_vars[static_cast<std::size_t>(k)]);
      v.items.push_back(sign < 0 ? neg(x) : x);
    }
    return v;
  }

  // ---- what a term's refs stand for ----------------------------------------------------
  const Value& param_value(const Ref& ref) const { return m_.param_values[static_cast<std::size_t>(ref.id)]; }

  /// An element's own quantities, as its law reads them (Ref::Own).
  struct Own {
    Value e, f, state;
  };

  /// A node's quantity; a contact's `closed` and `stick` exist once its law made them.
  std::optional<Value> node_quantity(const Ref& ref, const SourceLoc& loc) {
    const GraphNode& n = g_.nodes[static_cast<std::size_t>(ref.id)];
    auto port = [&](int k, bool effort) {
      const int b = n.bonds[static_cast<std::size_t>(k)];
      return bond_value(b, effort, effort ? 1 : flow_sign(g_, ref.id, b));
    };
    switch (ref.quantity) {
      case Quantity::e: return bond_value(n.bonds[0], true, 1);
      case Quantity::f: return bond_value(n.bonds[0], false, is_junction(n.kind) ? 1 : flow_sign(g_, ref.id, n.bonds[0]));
      case Quantity::p:
      case Quantity::q: {
        Value v{n.dim, 1, {}};
        for (int s : n.state_vars) v.items.push_back(var(s));
        return v;
      }
      case Quantity::e1: return port(0, true);
      case Quantity::f1: return port(0, false);
      case Quantity::e2: return port(1, true);
      case Quantity::f2: return port(1, false);
      case Quantity::closed:
        if (!n.discrete.empty()) return Value::scalar(var(n.discrete[0]));
        break;
      case Quantity::stick:
        if (n.discrete.size() > 2) return Value::scalar(var(n.discrete[2]));
        break;
      case Quantity::value: break;  // (a node has none: resolve binds none)
    }
    diags_.error(loc, fmt::format("{} `{}` has no quantity `{}`", node_kind_name(n.kind), n.name,
                                  ref.quantity == Quantity::closed ? "closed" : "stick"),
                 element_quantities(n.kind));
    return std::nullopt;
  }

  /// The values of refs, an element's own quantities among them where `own` is given.
  RefLookup lookup(const Own* own = nullptr) {
    return [this, own](const Term& leaf) -> std::optional<Value> {
      const Ref& ref = leaf.ref;
      switch (ref.kind) {
        case Ref::Kind::Param: return param_value(ref);
        case Ref::Kind::Signal: return Value::scalar(var(signal_var_[static_cast<std::size_t>(ref.id)]));
        case Ref::Kind::Node: return node_quantity(ref, leaf.loc);
        case Ref::Kind::Bond: return bond_value(ref.id, ref.quantity == Quantity::e, 1);
        case Ref::Kind::Own:
          if (!own) throw InternalError(fmt::format("`{}` reads an element's own quantity outside its law", leaf.name));
          return ref.quantity == Quantity::e ? own->e : ref.quantity == Quantity::f ? own->f : own->state;
        case Ref::Kind::Time:
        case Ref::Kind::Pi: break;  // (lowering knows them)
        case Ref::Kind::Name:
        case Ref::Kind::Symbol: break;  // (bound by resolve)
      }
      return std::nullopt;
    };
  }

  /// `Sf name { rate0 = ... }` without a value: a free rate (LawForm::FreeRate).
  static bool is_free_rate(const ResolvedNode& rn) {
    if (!rn.element || rn.element->kind != "Sf" || rn.element->value) return false;
    for (const TermAttr& a : rn.element->attrs)
      if (a.key == element_setting::rate0.key) return true;
    return false;
  }

  // ---- element laws ---------------------------------------------------------------------
  static bool only_params(const Value& v) {
    for (const Expr& e : v.items) {
      std::unordered_set<int> vars;
      collect_vars(e, vars);
      if (!vars.empty() || depends_on_time(e)) return false;
    }
    return true;
  }

  void lower_laws() {
    for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
      GraphNode& n = g_.nodes[i];
      const ResolvedNode& rn = m_.nodes[i];
      if (!rn.element || n.bonds.empty() || (is_two_port(n.kind) && (n.bonds[0] < 0 || n.bonds[1] < 0))) continue;
      const BoundElement& el = *rn.element;
      n.state_limits = el.state_limits;
      Own own;  // the element's own e, f, p/q inside { } laws
      if (!is_two_port(n.kind)) {
        int sign = flow_sign(g_, static_cast<int>(i), n.bonds[0]);
        own.e = bond_value(n.bonds[0], true, 1);
        own.f = bond_value(n.bonds[0], false, sign);
        own.state = Value{n.dim, 1, {}};
        for (int v : n.state_vars) own.state.items.push_back(var(v));
      }
      RefLookup plain = lookup();
      RefLookup with_own = lookup(&own);
      if (el.value && n.kind == NodeKind::CN) {
        diags_.error(el.value->loc, fmt::format("CN `{}` takes no value", n.name),
                     fmt::format("a constraintor is defined by its position constraint, not by a modulus: write CN {} {{ g "
                                 "= ... }} (add stiffness and damping for a penalty)",
                                 n.name));
        continue;
      }
      if (el.value) {
        auto v = lower(*el.value, plain, diags_);
        if (!v) continue;
        n.value = *v;
        if (!check_value_shape(n, el)) continue;
        n.law = (n.kind == NodeKind::Se || n.kind == NodeKind::Sf) ? LawForm::Source : LawForm::Linear;
        bool fixed_modulus = n.kind == NodeKind::C || n.kind == NodeKind::TF || n.kind == NodeKind::GY ||
                             (n.kind == NodeKind::I && !el.configuration_dependent);
        if (fixed_modulus && !only_params(n.value)) {
          diags_.error(el.value->loc,
                       fmt::format("the value of {} `{}` must be constant (parameters only)", el.kind, n.name),
                       n.kind == NodeKind::TF   ? "use MTF for a modulus that depends on states, time or signals"
                       : n.kind == NodeKind::GY ? "use MGY for a modulus that depends on states, time or signals"
                                                : "give a nonlinear law instead, e.g. I m { f = p / mass(p) }");
        }
      }
      // a CN's settings, typed: the multibody layer's as written, a user's read from its braces
      BoundConstraintLaw law = el.constraint.value_or(BoundConstraintLaw{});
      bool has_law = law.g != nullptr;
      bool misspelt = false;  // a setting it has none of: likely the law meant, so not reported missing too
      for (const TermAttr& a : el.attrs) {
        const ElementSetting* setting = find_element_setting(n.kind, a.key);
        if (n.kind == NodeKind::CN && setting) {
          const bool is_g = setting->role == ElementSetting::Role::Law;
          if (is_g && has_law) {
            diags_.error(a.loc, fmt::format("{} `{}` has two constitutive laws", el.kind, n.name),
                         "give either `= value` or one law in { }, not both");
            continue;
          }
          has_law = has_law || is_g;
          for (const BoundConstraintLaw::Field& f : BoundConstraintLaw::fields())
            if (a.key == f.key) law.*f.member = a.value;
          continue;
        }
        if (setting && setting->role == ElementSetting::Role::Law) {
          if (el.value || has_law) {
            diags_.error(a.loc, fmt::format("{} `{}` has two constitutive laws", el.kind, n.name),
                         "give either `= value` or one law in { }, not both");
            continue;
          }
          has_law = true;
          auto v = lower(*a.value, with_own, diags_);
          if (!v) continue;
          if (!(v->is_scalar() || (v->is_vector() && v->length() == n.dim))) {
            diags_.error(a.value->loc, fmt::format("the law of `{}` is {}, but its multibond has dimension {}", n.name, v->shape(), n.dim),
                         n.dim == 1 ? "a scalar element's law is a scalar expression"
                                    : fmt::format("give a vector of {} components (a scalar applies to every component)", n.dim));
            continue;
          }
          n.law_rhs = v->is_scalar() ? std::vector<Expr>(static_cast<std::size_t>(n.dim), v->items[0]) : v->items;
          n.law = setting->law;
          check_law_inputs(n, a);
        } else if (setting) {
          // an initial value or a CN's settings: handled after the law is known
        } else {
          std::vector<std::string> keys = element_setting_keys(n.kind);
          std::string near = closest_name(a.key, keys);
          misspelt = true;
          diags_.error(a.loc, fmt::format("{} `{}` has no setting `{}`", el.kind, n.name, a.key),
                       keys.empty() ? fmt::format("{} takes only a value: {} {} = ...", el.kind, el.kind, n.name)
                       : near.empty() ? fmt::format("{} accepts {}", el.kind, fmt::join(keys, ", "))
                                      : fmt::format("did you mean `{}`?", near));
        }
      }
      if (is_free_rate(rn)) {
        n.law = LawForm::FreeRate;
        lower_initial(n, el, plain);
        continue;
      }
      if (!el.value && !has_law) {
        if (!misspelt)
          diags_.error(n.loc,
                       n.kind == NodeKind::CN ? fmt::format("CN `{}` has no constraint g", n.name)
                                              : fmt::format("{} `{}` has no value or law", el.kind, n.name),
                       law_hint(n.kind, n.name));
        continue;
      }
      if (is_storage(n.kind)) lower_initial(n, el, plain);
      if (n.kind == NodeKind::CN) lower_constraint(n, law, with_own, plain, own);
    }
  }

  /// A CN: its rows g, then what holds them (lower_penalty).
  void lower_constraint(GraphNode& n, const BoundConstraintLaw& law, const RefLookup& with_own, const RefLookup& plain,
                        const Own& own) {
    auto v = lower(*law.g, with_own, diags_);
    if (!v) return;
    if (!(v->is_scalar() || (v->is_vector() && v->length() == n.dim))) {
      diags_.error(law.g->loc, fmt::format("the constraint g of `{}` is {}, but its multibond has dimension {}", n.name, v->shape(), n.dim),
                   fmt::format("a constraintor holds one row of g per dimension of its bond: give g {} row{}, or "
                               "give the CN's junction dimension [{}]",
                               n.dim, n.dim == 1 ? "" : "s", v->is_vector() ? v->length() : v->rows));
      return;
    }
    n.constraint_g = Value{n.dim, 1, v->is_scalar() ? std::vector<Expr>(static_cast<std::size_t>(n.dim), v->items[0]) : v->items};
    n.law = LawForm::Constraint;
    // (a cut joint's or a contact's g may read the pose signals of bodies moved by joint coordinates)
    check_constraint_inputs(n, *law.g, /*signals_too=*/law.stabilisation || law.restitution);
    lower_penalty(n, law, plain, own);
  }

  /// A CN with `stiffness` (and optionally `damping`) is a penalty constraint:
  /// e = stiffness * g + damping * f per component, an ODE instead of a multiplier.
  ///
  /// A CN with a `restitution` is a contact (a unilateral row g >= 0): with a
  /// `stiffness` (and `exponent`) a compliant Hunt-Crossley force, else a
  /// row held while it pushes (LawForm::Unilateral, Compliant).
  void lower_penalty(GraphNode& n, const BoundConstraintLaw& law, const RefLookup& lookup, const Own& own) {
    using L = BoundConstraintLaw;
    std::optional<Value> k, d, w, e, x, mu;
    for (const L::Field& f : L::fields()) {
      const TermPtr& value = law.*f.member;
      if (!value || f.member == &L::g) continue;
      auto v = lower(*value, lookup, diags_);
      if (!v) return;
      const bool constant = v->is_scalar() && only_params(*v);
      if (f.member == &L::restitution || f.member == &L::exponent || f.member == &L::friction) {
        if (!constant) {
          diags_.error(value->loc, fmt::format("the {} of `{}` must be a constant scalar (numbers and parameters)", f.key, n.name),
                       f.member == &L::restitution ? "restitution = 0.8: the normal speed after an impact is -0.8 times the one before"
                       : f.member == &L::exponent  ? "exponent = 1.5 (Hertz: a sphere on a plane)"
                                                   : "friction = 0.3: Coulomb's coefficient");
          return;
        }
        (f.member == &L::restitution ? e : f.member == &L::exponent ? x : mu) = v;
      } else if (f.member == &L::stabilisation) {
        if (!constant) {
          diags_.error(value->loc, fmt::format("the stabilisation of `{}` must be a constant scalar (rad/s)", n.name),
                       "stabilisation = 20 keeps g'' + 2 w g' + w^2 g = 0 with w = 20 rad/s");
          return;
        }
        w = v;
      } else {  // a penalty's stiffness or damping
        if (!constant) {
          diags_.error(value->loc, fmt::format("the {} of `{}` must be a constant scalar (numbers and parameters)", f.key, n.name),
                       fmt::format("the penalty effort is e = stiffness * g + damping * f with constant coefficients, e.g. {} = 1e6",
                                   f.key));
          return;
        }
        (f.member == &L::stiffness ? k : d) = v;
      }
    }
    if (mu && (!e || k)) {
      diags_.error(n.loc, fmt::format("CN `{}` has a friction but is not a unilateral contact", n.name),
                   "friction rows belong to a unilateral contact CN: g = [gap, tangential rows], a restitution, no stiffness");
      return;
    }
    if (e) {
      if (n.dim != (mu ? 3 : 1)) {
        diags_.error(n.loc, fmt::format("contact CN `{}` has {} rows", n.name, n.dim),
                     mu ? "a contact with friction has three rows: its gap g >= 0 and two tangential rows whose rate is the "
                          "sliding velocity"
                        : "a contact is one unilateral row g >= 0: give it a scalar g");
        return;
      }
      if (d) {
        diags_.error(n.loc, fmt::format("contact CN `{}` has a damping", n.name),
                     "a contact's damping follows from its restitution (Hunt-Crossley): remove `damping`");
        return;
      }
      if (k) {
        n.law = LawForm::Compliant;
        n.law_rhs = {k->items[0], x ? x->items[0] : constant(*L::field(&L::exponent).default_value), e->items[0]};
      } else {
        n.law = LawForm::Unilateral;
        n.law_rhs = {w ? w->items[0] : constant(*L::field(&L::stabilisation).default_value), e->items[0]};
        if (mu) n.law_rhs.push_back(mu->items[0]);
      }
      std::vector<std::string> names = {"closed", k ? "damping" : "bias"};
      if (mu) names.insert(names.end(), {"stick", "slip[1]", "slip[2]"});
      for (const std::string& d : names) n.discrete.push_back(g_.add_var(n.name + "." + d, VarKind::Discrete, n.loc));
      return;
    }
    if (x) {
      diags_.error(n.loc, fmt::format("CN `{}` has an exponent but no restitution", n.name),
                   "the exponent belongs to a compliant contact: add restitution = e (and stiffness = k)");
      return;
    }
    if (w) {
      n.law = LawForm::Stabilised;
      n.law_rhs = {w->items[0]};
      return;
    }
    if (!k && !d) return;
    if (!k) {
      diags_.error(n.loc, fmt::format("CN `{}` has a damping but no stiffness", n.name),
                   "a penalty constraint needs `stiffness = ...` (and usually `damping = ...`)");
      return;
    }
    n.law = LawForm::Penalty;
    const Value& f = own.f;
    for (int c = 0; c < n.dim; ++c) {
      Expr e = mul(k->items[0], n.constraint_g.items[static_cast<std::size_t>(c)]);
      if (d) e = add(e, mul(d->items[0], f.items[static_cast<std::size_t>(c)]));
      n.law_rhs.push_back(e);
    }
  }

  /// g must be a function of states (the positions whose rate the CN's flow is), not of efforts or flows.
  void check_constraint_inputs(const GraphNode& n, const Term& g, bool signals_too) {
    for (const Expr& e : n.constraint_g.items) {
      std::unordered_set<int> vars;
      collect_vars(e, vars);
      for (int id : vars) {
        VarKind k = g_.vars[static_cast<std::size_t>(id)].kind;
        if (k != VarKind::State && !(signals_too && k == VarKind::Signal)) {
          diags_.error(g.loc, fmt::format("the constraint g of `{}` depends on `{}`, which is not a state", n.name, g_.vars[static_cast<std::size_t>(id)].name),
                       "g is a position-level constraint: write it in terms of displacements (a C element's q)");
          return;
        }
      }
    }
  }

  bool check_value_shape(const GraphNode& n, const BoundElement& el) {
    const Value& v = n.value;
    if (v.is_scalar()) return true;
    bool ok = true;
    if (is_two_port(n.kind)) ok = v.rows == n.dim2 && v.cols == n.dim;
    else if (n.kind == NodeKind::Se || n.kind == NodeKind::Sf) ok = v.is_vector() && v.length() == n.dim;
    else ok = v.rows == n.dim && v.cols == n.dim;
    if (!ok)
      diags_.error(el.value->loc, fmt::format("{} `{}` is {}, but its multibond has dimension {}", el.kind, n.name, v.shape(), n.dim),
                   "the value's shape must match the multibond");
    return ok;
  }

  /// A law may read its own input (f for e = phi(f), q for e = phi(q), ...) but not its output.
  void check_law_inputs(const GraphNode& n, const TermAttr& a) {
    std::unordered_set<int> vars;
    for (const Expr& e : n.law_rhs) collect_vars(e, vars);
    const Bond& b = g_.bonds[static_cast<std::size_t>(n.bonds[0])];
    bool effort_out = n.law == LawForm::EffortOfFlow || n.law == LawForm::EffortOfState;
    const char* out_name = effort_out ? "e" : "f";
    const std::vector<int>& own_outputs = effort_out ? b.effort_vars : b.flow_vars;
    const std::vector<int>& others = n.law == LawForm::EffortOfState ? b.flow_vars : b.effort_vars;
    bool reads_own_output = false, reads_other = false;
    for (int id : own_outputs) reads_own_output |= vars.count(id) > 0;
    for (int id : others) reads_other |= vars.count(id) > 0;
    if (n.kind != NodeKind::R) {
      if (reads_other)
        diags_.error(a.value->loc, fmt::format("the law of `{}` must be a function of its state", n.name),
                     n.kind == NodeKind::C ? "write C name { e = expression of q }" : "write I name { f = expression of p }");
    }
    if (reads_own_output)
      diags_.error(a.value->loc, fmt::format("the law `{} = ...` of `{}` refers to `{}` itself", out_name, n.name, out_name),
                   "the right-hand side may use the element's input, parameters, time and signals");
  }

  void lower_initial(GraphNode& n, const BoundElement& el, const RefLookup& lookup) {
    n.initial = Value{n.dim, 1, std::vector<Expr>(static_cast<std::size_t>(n.dim), constant(0))};
    for (const TermAttr& a : el.attrs) {
      if (!is_element_setting(n.kind, a.key, ElementSetting::Role::Initial)) continue;
      auto v = lower(*a.value, lookup, diags_);
      if (!v) return;
      if (!only_params(*v)) {
        diags_.error(a.value->loc, "an initial value must be constant (numbers and parameters)", "");
        return;
      }
      if (!(v->is_scalar() && n.dim == 1) && !(v->is_vector() && v->length() == n.dim)) {
        diags_.error(a.value->loc, fmt::format("initial value is {}, but `{}` has dimension {}", v->shape(), n.name, n.dim), "");
        return;
      }
      namespace es = element_setting;
      const bool given_as_state = a.key == es::p0.key || a.key == es::q0.key || a.key == es::rate0.key;
      if (given_as_state) {
        n.initial.items = v->items;
        n.initial_is_state = true;
        continue;
      }
      if (n.law != LawForm::Linear) {
        diags_.error(a.loc, fmt::format("`{}` needs a linear element", a.key),
                     fmt::format("give the initial state instead ({})", n.kind == NodeKind::I ? "p0" : "q0"));
        return;
      }
      // p0 = I f0, q0 = C e0 (the last one given wins: not the state as given)
      n.initial_is_state = false;
      for (int r = 0; r < n.dim; ++r) {
        Expr s = constant(0);
        for (int c = 0; c < n.dim; ++c) {
          Expr m = n.value.is_scalar() ? (r == c ? n.value.items[0] : constant(0)) : n.value.at(r, c);
          s = add(s, mul(m, v->items[static_cast<std::size_t>(c)]));
        }
        n.initial.items[static_cast<std::size_t>(r)] = s;
      }
    }
  }

  void lower_signals_and_outputs() {
    for (std::size_t i = 0; i < m_.signals.size(); ++i) {
      const ResolvedExpr& s = m_.signals[i];
      auto v = lower(*s.expr, lookup(), diags_);
      if (!v) continue;
      if (!v->is_scalar()) {
        diags_.error(s.expr->loc, fmt::format("signal `{}` is {}; signals are scalars", s.name, v->shape()),
                     "index it, e.g. v[1], or declare one signal per component");
        continue;
      }
      Expr rate;
      if (s.rate) {
        auto r = lower(*s.rate, lookup(), diags_);
        if (!r) continue;
        rate = r->items[0];  // (scalar: the multibody layer writes one entry per signal)
      }
      g_.signals.push_back({s.name, s.loc, signal_var_[i], v->items[0], rate, s.unit, s.generated});
    }
    for (const ResolvedExpr& o : m_.outputs) {
      auto v = lower(*o.expr, lookup(), diags_);
      if (!v) continue;
      if (v->is_scalar()) {
        g_.outputs.push_back({o.name, o.loc, v->items[0], o.unit, std::nullopt});
        continue;
      }
      for (int r = 0; r < v->rows; ++r)
        for (int c = 0; c < v->cols; ++c) {
          std::string col = v->cols == 1 ? fmt::format("{}[{}]", o.name, r + 1)
                                         : fmt::format("{}[{},{}]", o.name, r + 1, c + 1);
          g_.outputs.push_back({col, o.loc, v->at(r, c), o.unit, std::nullopt});
        }
    }
    for (const ResolvedDrawing& d : m_.drawings) {
      auto pose = lower(*d.pose, lookup(), diags_);  // hcat(R, p): 3 x 4
      if (!pose) continue;
      DrawnBody body{d.drawing, d.loc, {}, {}};
      for (int r = 0; r < 3; ++r) body.pose.push_back(pose->at(r, 3));
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) body.pose.push_back(pose->at(r, c));
      if (d.modes) {
        auto modes = lower(*d.modes, lookup(), diags_);
        if (!modes) continue;
        body.modes = modes->items;
      }
      g_.drawings.push_back(std::move(body));
    }
    // What the multibody layer states of the user's settings: a value that does
    // not lower was reported where the layer read it.
    for (const BoundUnitCheck& c : m_.unit_checks) {
      Diagnostics scratch(sources_);
      if (!c.value) continue;
      if (auto v = lower(*c.value, lookup(), scratch))
        g_.unit_checks.push_back({v->items, c.dimension, c.loc, c.what, c.quantity});
    }
  }

  const ResolvedModel& m_;
  const SourceManager& sources_;
  Diagnostics& diags_;
  BondGraph g_;
  std::vector<int> signal_var_;  // per resolved signal, its variable
};

}  // namespace

BondGraph build_graph(const ResolvedModel& model, const SourceManager& sources, Diagnostics& diags) {
  Builder b(model, sources, diags);
  return b.run();
}

}  // namespace mbgc::graph

