#include "causality/scap.hpp"

#include <deque>
#include <fmt/format.h>

namespace mbgc::causality {
namespace {

using namespace mbgc::ir;

/// What an element wants on its (one) bond.
enum class Want { Effort, Flow, Either };

/// The causality rules, one entry per node kind.
struct Rule {
  NodeKind kind;
  Want fixed;      // hard constraint (sources)
  Want preferred;  // storage: integral causality
  int step;        // SCAP step at which an open bond of this kind is decided
};

// Integral causality: I receives effort (computes flow); C computes effort.
constexpr Rule kRules[] = {
    {NodeKind::Se, Want::Effort, Want::Effort, 1},
    {NodeKind::Sf, Want::Flow, Want::Flow, 1},
    {NodeKind::I, Want::Either, Want::Flow, 2},
    {NodeKind::C, Want::Either, Want::Effort, 2},
    {NodeKind::R, Want::Either, Want::Effort, 3},
    {NodeKind::CN, Want::Effort, Want::Effort, 1},  // lagrange: unknown effort; penalty: e = law(g, f)
    {NodeKind::TF, Want::Either, Want::Either, 4},
    {NodeKind::MTF, Want::Either, Want::Either, 4},
    {NodeKind::GY, Want::Either, Want::Either, 4},
    {NodeKind::MGY, Want::Either, Want::Either, 4},
    {NodeKind::Zero, Want::Either, Want::Either, 4},
    {NodeKind::One, Want::Either, Want::Either, 4},
};

const Rule& rule(NodeKind k) {
  for (const Rule& r : kRules)
    if (r.kind == k) return r;
  return kRules[0];
}

class Scap {
 public:
  Scap(BondGraph& g, Diagnostics& diags, CausalityReport& report) : g_(g), diags_(diags), report_(report) {}

  void run() {
    // Step 1: sources and laws that fix causality.
    for (int n = 0; n < node_count(); ++n) {
      Want w = fixed_want(n);
      if (w == Want::Either) continue;
      const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
      if (is_two_port(node.kind)) {  // non-square: only f2 = T f1 (T sets e1) is possible
        decide(node.bonds[0], n, "forced: non-square " + std::string(node_kind_name(node.kind)) + " `" + node.name + "` computes e1 = T^T e2");
        continue;
      }
      set_want(n, w, fmt::format("{} `{}` {}", node_kind_name(node.kind), node.name,
                                 w == Want::Effort ? "imposes effort" : "imposes flow"));
    }
    if (!propagate()) return;
    // Step 2: storage, integral causality preferred.
    for (int n = 0; n < node_count(); ++n) {
      const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
      if (!is_storage(node.kind) || node.bonds.empty()) continue;
      int b = node.bonds[0];
      Want preferred = rule(node.kind).preferred;
      if (g_.bonds[static_cast<std::size_t>(b)].effort_setter < 0) {
        set_want(n, preferred, fmt::format("{} `{}`: integral causality", node_kind_name(node.kind), node.name));
        if (!propagate()) return;
      }
      bool integral = (preferred == Want::Effort) == sets_effort(g_, n, b);
      (integral ? report_.integral : report_.derivative).push_back(n);
      if (!integral) report_.steps.push_back(fmt::format("{} `{}`: derivative causality (forced by the graph)", node_kind_name(node.kind), node.name));
    }
    // Step 3: resistors still open.
    for (int n = 0; n < node_count(); ++n) {
      const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
      if (node.kind != NodeKind::R || node.bonds.empty()) continue;
      int b = node.bonds[0];
      if (g_.bonds[static_cast<std::size_t>(b)].effort_setter >= 0) continue;
      report_.chosen.push_back(b);
      // A nonlinear law is used in the form it was written (e = phi(f) or
      // f = phi(e)); if the graph forces the other form, the law becomes an
      // implicit equation (see reduce).
      bool conductance = node.law == LawForm::FlowOfEffort;
      set_want(n, conductance ? Want::Flow : Want::Effort,
               fmt::format("R `{}`: {} causality (a choice)", node.name, conductance ? "conductance" : "resistance"));
      if (!propagate()) return;
    }
    // Step 4: whatever is still open.
    for (std::size_t b = 0; b < g_.bonds.size(); ++b) {
      Bond& bond = g_.bonds[b];
      if (bond.effort_setter >= 0) continue;
      report_.chosen.push_back(static_cast<int>(b));
      decide(static_cast<int>(b), bond.from, fmt::format("bond {}: effort from `{}` (a choice)", bond.number, g_.nodes[static_cast<std::size_t>(bond.from)].name));
      if (!propagate()) return;
    }
  }

 private:
  int node_count() const { return static_cast<int>(g_.nodes.size()); }

  Want fixed_want(int n) const {
    const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
    if (node.bonds.empty()) return Want::Either;
    if (is_two_port(node.kind)) return node.dim != node.dim2 ? Want::Effort : Want::Either;
    return rule(node.kind).fixed;
  }

  void set_want(int n, Want w, const std::string& why) {
    int b = g_.nodes[static_cast<std::size_t>(n)].bonds[0];
    decide(b, w == Want::Effort ? n : other_end(g_, n, b), why);
  }

  /// Set bond b's effort setter to node `setter` (or check it, if already set).
  void decide(int b, int setter, const std::string& why) {
    Bond& bond = g_.bonds[static_cast<std::size_t>(b)];
    if (bond.effort_setter >= 0) {
      if (bond.effort_setter != setter) conflict_at_bond(b, setter, why);
      return;
    }
    bond.effort_setter = setter;
    report_.steps.push_back(fmt::format("bond {} ({} -> {}): effort from `{}` — {}", bond.number,
                                        g_.nodes[static_cast<std::size_t>(bond.from)].name,
                                        g_.nodes[static_cast<std::size_t>(bond.to)].name,
                                        g_.nodes[static_cast<std::size_t>(setter)].name, why));
    queue_.push_back(bond.from);
    queue_.push_back(bond.to);
  }

  void conflict_at_bond(int b, int wanted_setter, const std::string& why) {
    if (failed_) return;
    failed_ = true;
    const Bond& bond = g_.bonds[static_cast<std::size_t>(b)];
    const GraphNode& wanted = g_.nodes[static_cast<std::size_t>(wanted_setter)];
    int n = wanted_setter;
    const GraphNode& elem = g_.nodes[static_cast<std::size_t>(
        is_junction(wanted.kind) ? other_end(g_, n, b) : n)];
    auto& d = diags_.error(elem.loc,
                           fmt::format("causal conflict on bond {} at {} `{}`: {}, but the rest of the graph already fixed "
                                       "the other causality",
                                       bond.number, node_kind_name(elem.kind), elem.name, why),
                           conflict_hint(elem));
    d.notes.push_back({bond.loc, fmt::format("bond {} is declared here", bond.number)});
  }

  static std::string conflict_hint(const GraphNode& n) {
    switch (n.kind) {
      case NodeKind::Se: return "two effort sources on one 0-junction (or an effort source against a flow source) fight; remove one or put an R or C between them";
      case NodeKind::Sf: return "two flow sources on one 1-junction (or a flow source against an effort source) fight; remove one or put an R or I between them";
      case NodeKind::R: return "this nonlinear R is forced into the other causality; write its law in the other form (e = ... instead of f = ..., or the reverse)";
      default: return "check the sources and the junction structure around this element";
    }
  }

  void junction_conflict(int n, const std::vector<int>& bonds, bool zero) {
    if (failed_) return;
    failed_ = true;
    const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
    std::vector<std::string> nums;
    for (int b : bonds) nums.push_back(std::to_string(g_.bonds[static_cast<std::size_t>(b)].number));
    auto& d = diags_.error(
        node.loc,
        fmt::format("causal conflict at {}-junction `{}`: bonds {} {} impose {} on it", zero ? "0" : "1", node.name,
                    fmt::join(nums, " and "), nums.size() == 2 ? "both" : "all", zero ? "effort" : "flow"),
        zero ? "a 0-junction takes its effort from exactly one bond; two effort sources (or an effort source and a C in "
               "parallel) cannot both set it — remove one or put an R between them"
             : "a 1-junction takes its flow from exactly one bond; two flow sources (or a flow source and an I in "
               "series) cannot both set it — remove one or put an R between them");
    for (int b : bonds)
      d.notes.push_back({g_.bonds[static_cast<std::size_t>(b)].loc,
                         fmt::format("bond {} from `{}`", g_.bonds[static_cast<std::size_t>(b)].number,
                                     g_.nodes[static_cast<std::size_t>(other_end(g_, n, b))].name)});
  }

  /// Apply junction/TF/GY constraints until nothing changes. False on conflict.
  bool propagate() {
    while (!queue_.empty() && !failed_) {
      int n = queue_.front();
      queue_.pop_front();
      const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
      if (is_junction(node.kind)) junction(n);
      else if (is_two_port(node.kind)) two_port(n);
    }
    queue_.clear();
    return !failed_;
  }

  void junction(int n) {
    const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
    bool zero = node.kind == NodeKind::Zero;
    // "strong" bonds: at a 0-junction those bringing effort in; at a 1-junction
    // those taking effort from the junction (i.e. bringing flow in).
    std::vector<int> strong, open;
    for (int b : node.bonds) {
      int setter = g_.bonds[static_cast<std::size_t>(b)].effort_setter;
      if (setter < 0) open.push_back(b);
      else if (zero ? setter != n : setter == n) strong.push_back(b);
    }
    if (strong.size() > 1) return junction_conflict(n, strong, zero);
    auto make_weak = [&](int b) { decide(b, zero ? n : other_end(g_, n, b), fmt::format("{}-junction `{}` has its {} from bond {}", zero ? "0" : "1", node.name, zero ? "effort" : "flow", g_.bonds[static_cast<std::size_t>(strong[0])].number)); };
    auto make_strong = [&](int b) { decide(b, zero ? other_end(g_, n, b) : n, fmt::format("{}-junction `{}` needs one bond to set its {}", zero ? "0" : "1", node.name, zero ? "effort" : "flow")); };
    if (strong.size() == 1) {
      for (int b : open) make_weak(b);
    } else if (open.size() == 1) {
      make_strong(open[0]);
    } else if (open.empty()) {
      // every bond is weak: nobody sets the common variable
      std::vector<int> all(node.bonds.begin(), node.bonds.end());
      if (!failed_) {
        failed_ = true;
        diags_.error(node.loc,
                     fmt::format("causal conflict at {}-junction `{}`: no bond sets its {}", zero ? "0" : "1", node.name,
                                 zero ? "effort" : "flow"),
                     zero ? "every element on this 0-junction wants its effort from it; add an effort source or a C"
                          : "every element on this 1-junction wants its flow from it; add a flow source or an I");
      }
    }
  }

  void two_port(int n) {
    const GraphNode& node = g_.nodes[static_cast<std::size_t>(n)];
    int b1 = node.bonds[0], b2 = node.bonds[1];
    if (b1 < 0 || b2 < 0) return;
    int s1 = g_.bonds[static_cast<std::size_t>(b1)].effort_setter;
    int s2 = g_.bonds[static_cast<std::size_t>(b2)].effort_setter;
    bool gyrator = node.kind == NodeKind::GY || node.kind == NodeKind::MGY;
    // TF: sets the effort on exactly one port. GY: on both or on neither.
    auto partner = [&](int setter_known, int other_bond) {
      bool sets = setter_known == n;
      bool other_sets = gyrator ? sets : !sets;
      decide(other_bond, other_sets ? n : other_end(g_, n, other_bond),
             fmt::format("{} `{}` passes causality through", node_kind_name(node.kind), node.name));
    };
    if (s1 >= 0) partner(s1, b2);
    else if (s2 >= 0) partner(s2, b1);
  }

  BondGraph& g_;
  Diagnostics& diags_;
  CausalityReport& report_;
  std::deque<int> queue_;
  bool failed_ = false;
};

}  // namespace

CausalGraph assign_causality(BondGraph graph, Diagnostics& diags) {
  CausalGraph out;
  out.graph = std::move(graph);
  Scap s(out.graph, diags, out.report);
  s.run();
  return out;
}

}  // namespace mbgc::causality
