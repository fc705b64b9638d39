#include "equations/generate.hpp"

#include <fmt/format.h>

namespace mbgc::equations {
namespace {

using namespace mbgc::ir;

class Generator {
 public:
  Generator(EquationSystem& sys, Diagnostics& diags) : s_(sys), g_(sys.graph), diags_(diags) {}

  void run() {
    for (std::size_t n = 0; n < g_.nodes.size(); ++n) node(static_cast<int>(n));
    for (const Signal& sig : g_.signals) emit(var(sig.var), sig.value, sig.var, sig.loc, "signal " + sig.name);
  }

 private:
  // ---- helpers ----------------------------------------------------------------
  const Bond& bond(int b) const { return g_.bonds[static_cast<std::size_t>(b)]; }
  Expr e(int b, int k) const { return var(bond(b).effort_vars[static_cast<std::size_t>(k)]); }
  Expr f(int b, int k) const { return var(bond(b).flow_vars[static_cast<std::size_t>(k)]); }
  int e_id(int b, int k) const { return bond(b).effort_vars[static_cast<std::size_t>(k)]; }
  int f_id(int b, int k) const { return bond(b).flow_vars[static_cast<std::size_t>(k)]; }

  /// Entry (r, c) of a node's modulus; a scalar stands for scalar * identity.
  static Expr entry(const Value& v, int r, int c) {
    if (v.is_scalar()) return r == c ? v.items[0] : constant(0);
    return v.at(r, c);
  }
  /// sum_c M(r, c) * x(c)
  template <class X>
  static Expr row_times(const Value& m, int r, int n, X x, bool transpose = false) {
    Expr s = constant(0);
    for (int c = 0; c < n; ++c) s = add(s, mul(transpose ? entry(m, c, r) : entry(m, r, c), x(c)));
    return s;
  }

  void emit(Expr lhs, Expr rhs, int unknown, SourceLoc loc, std::string origin) {
    s_.equations.push_back({std::move(lhs), std::move(rhs), unknown, loc, std::move(origin)});
  }

  int sign(int n, int b) const { return flow_sign(g_, n, b); }
  static Expr signed_(int s, Expr x) { return s < 0 ? neg(x) : x; }

  std::string label(const GraphNode& n, const std::string& what) const {
    return fmt::format("{} {}: {}", node_kind_name(n.kind), n.name, what);
  }

  // ---- per node kind ------------------------------------------------------------
  void node(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    if (nd.bonds.empty()) return;
    switch (nd.kind) {
      case NodeKind::Se: case NodeKind::Sf: source(n); break;
      case NodeKind::I: case NodeKind::C: storage(n); break;
      case NodeKind::R: resistor(n); break;
      case NodeKind::TF: case NodeKind::MTF: transformer(n); break;
      case NodeKind::GY: case NodeKind::MGY: gyrator(n); break;
      case NodeKind::Zero: case NodeKind::One: junction(n); break;
      case NodeKind::CN: constraintor(n); break;
    }
  }

  void constraintor(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    int b = nd.bonds[0];
    int s = sign(n, b);
    bool lagrange = nd.law == LawForm::Constraint;
    if (nd.law == LawForm::Unilateral || nd.law == LawForm::Compliant) {
      contact(n);
      return;
    }
    for (int k = 0; k < nd.dim; ++k) {
      std::string row = nd.dim == 1 ? nd.name : fmt::format("{}[{}]", nd.name, k + 1);
      s_.constraints.push_back({row, nd.loc, nd.constraint_g.items[static_cast<std::size_t>(k)], f_id(b, k), lagrange ? e_id(b, k) : -1, nullptr, -1,
                                nd.law == LawForm::Stabilised});
      if (nd.law == LawForm::Stabilised) {
        // A cut joint on a tree in joint coordinates: the flow (g') follows
        // from the tree's rates; the multiplier keeps g'' + 2 w g' + w^2 g = 0,
        // an equation of the accelerations, solved with them (reduce).
        const Expr& w = nd.law_rhs[0];
        const Expr rate = signed_(s, f(b, k));
        Expr lhs = add(add(der(rate), mul(mul(constant(2), w), rate)), mul(mul(w, w), nd.constraint_g.items[static_cast<std::size_t>(k)]));
        Equation eq{lhs, constant(0), e_id(b, k), nd.loc, label(nd, "g'' + 2 w g' + w^2 g = 0, e is the multiplier"), /*constraint=*/true};
        eq.in_loop = true;
        s_.equations.push_back(std::move(eq));
        continue;
      }
      if (lagrange) {
        // The flow is computed by the rest of the graph; this equation pins it
        // to zero and thereby determines the multiplier e (an index-2 DAE row).
        s_.equations.push_back({signed_(s, f(b, k)), constant(0), e_id(b, k), nd.loc,
                                label(nd, "f = dg/dt = 0, e is the multiplier"), /*constraint=*/true});
      } else {
        emit(e(b, k), nd.law_rhs[static_cast<std::size_t>(k)], e_id(b, k), nd.loc, label(nd, "e = stiffness g + damping f (penalty)"));
      }
    }
  }

  /// A contact (a CN with a restitution, one row g >= 0). Its normal force
  /// F = -s e pushes the sides apart (s: the sign that makes the flow dg/dt).
  /// Unilateral: while closed e keeps g'' + 2 w g' + w^2 g = bias (solved with
  /// the accelerations, as a cut joint's row), while open e = 0:
  ///   closed (g'' + 2 w g' + w^2 g - bias) + (1 - closed) e = 0.
  /// Compliant: F = closed max(0, k max(0, -g)^n (1 - damping g')), Hunt-Crossley.
  void contact(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    const int b = nd.bonds[0];
    const int s = sign(n, b);
    ContactRow c;
    c.name = nd.name;
    c.loc = nd.loc;
    c.compliant = nd.law == LawForm::Compliant;
    c.gap = nd.constraint_g.items[0];
    c.rate = signed_(s, f(b, 0));
    c.normal_force = signed_(-s, e(b, 0));
    c.restitution = nd.law_rhs[c.compliant ? 2 : 1];
    c.closed = nd.discrete[0];
    const Expr closed = var(c.closed);
    if (c.compliant) {
      c.damping = nd.discrete[1];
      const Expr& k = nd.law_rhs[0];
      const Expr& exponent = nd.law_rhs[1];
      const Expr depth = call(Fn::Max, {constant(0), neg(c.gap)});
      const Expr push = mul(mul(k, pow(depth, exponent)), sub(constant(1), mul(var(c.damping), c.rate)));
      const Expr force = mul(closed, call(Fn::Max, {constant(0), push}));
      emit(e(b, 0), signed_(-s, force), e_id(b, 0), nd.loc,
           label(nd, "e = -F, F = closed max(0, k max(0, -g)^n (1 - damping g')) (Hunt-Crossley contact)"));
    } else {
      c.bias = nd.discrete[1];
      const Expr& w = nd.law_rhs[0];
      const Expr row = sub(add(add(der(c.rate), mul(mul(constant(2), w), c.rate)), mul(mul(w, w), c.gap)), var(c.bias));
      Equation eq{add(mul(closed, row), mul(sub(constant(1), closed), e(b, 0))), constant(0), e_id(b, 0), nd.loc,
                  label(nd, "closed: g'' + 2 w g' + w^2 g = bias, open: e = 0 (unilateral contact)"), /*constraint=*/true};
      eq.in_loop = true;
      s_.equations.push_back(std::move(eq));
      if (nd.law_rhs.size() > 2) friction_rows(n, c);
    }
    s_.contacts.push_back(std::move(c));
  }

  /// A unilateral contact's tangential rows 2 and 3 (e: the friction, -s e on
  /// the first side): while closed and stuck their rate keeps der(f) + 2 w f = 0,
  /// while closed and sliding e = mu push slip (Coulomb, against the slip
  /// direction), while open e = 0:
  ///   closed (stick (f' + 2 w f) + (1 - stick) (e - s mu push slip)) + (1 - closed) e = 0.
  void friction_rows(int n, ContactRow& c) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    const int b = nd.bonds[0];
    const int s = sign(n, b);
    const Expr& w = nd.law_rhs[0];
    c.friction = nd.law_rhs[2];
    c.stick = nd.discrete[2];
    c.slip1 = nd.discrete[3];
    c.slip2 = nd.discrete[4];
    const Expr closed = var(c.closed), stick = var(c.stick);
    for (int k = 1; k <= 2; ++k) {
      const Expr rate = signed_(s, f(b, k));
      c.tangent_rate[k - 1] = rate;
      c.tangent_force[k - 1] = signed_(-s, e(b, k));
      const Expr held = add(der(rate), mul(mul(constant(2), w), rate));
      // (the friction on the first side, -s e, is -mu push slip)
      const Expr sliding = sub(e(b, k), signed_(s, mul(mul(c.friction, c.normal_force), var(k == 1 ? c.slip1 : c.slip2))));
      const Expr closed_row = add(mul(stick, held), mul(sub(constant(1), stick), sliding));
      Equation eq{add(mul(closed, closed_row), mul(sub(constant(1), closed), e(b, k))), constant(0), e_id(b, k), nd.loc,
                  label(nd, "stuck: f' + 2 w f = 0, sliding: e = mu push slip, open: e = 0 (friction)"), /*constraint=*/true};
      eq.in_loop = true;
      s_.equations.push_back(std::move(eq));
    }
  }

  void source(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    int b = nd.bonds[0];
    int s = sign(n, b);
    if (nd.law == LawForm::FreeRate) {
      // An independent rate (Bos' independent-coordinate junction, thesis §8.4):
      // the flow is a state; the source must deliver no effort, and that
      // equation determines the state's derivative (an acceleration).
      for (int k = 0; k < nd.dim; ++k) {
        int x = nd.state_vars[static_cast<std::size_t>(k)];
        int dx = g_.add_var("der(" + g_.vars[static_cast<std::size_t>(x)].name + ")", VarKind::Derivative, nd.loc, x);
        s_.states.push_back({x, dx, n, nd.initial.items[static_cast<std::size_t>(k)]});
        emit(signed_(s, f(b, k)), var(x), f_id(b, k), nd.loc, label(nd, "f = rate (a state)"));
        emit(e(b, k), constant(0), dx, nd.loc, label(nd, "e = 0, solved for der(rate)"));
      }
      return;
    }
    for (int k = 0; k < nd.dim; ++k) {
      Expr v = nd.value.is_scalar() ? nd.value.items[0] : nd.value.items[static_cast<std::size_t>(k)];
      if (nd.kind == NodeKind::Se) emit(e(b, k), v, e_id(b, k), nd.loc, label(nd, "e = value"));
      else emit(signed_(s, f(b, k)), v, f_id(b, k), nd.loc, label(nd, "f = value"));
    }
  }

  void storage(int n) {
    GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    int b = nd.bonds[0];
    int s = sign(n, b);
    bool inertia = nd.kind == NodeKind::I;
    // The state's input: effort for I (dp/dt = e), flow for C (dq/dt = f).
    auto input = [&](int k) { return inertia ? e(b, k) : signed_(s, f(b, k)); };
    auto output = [&](int k) { return inertia ? signed_(s, f(b, k)) : e(b, k); };
    auto output_id = [&](int k) { return inertia ? f_id(b, k) : e_id(b, k); };
    auto input_id = [&](int k) { return inertia ? e_id(b, k) : f_id(b, k); };
    const char* st = inertia ? "p" : "q";
    const char* out = inertia ? "f" : "e";
    bool integral = sets_effort(g_, n, b) == !inertia;
    if (integral) {
      for (int k = 0; k < nd.dim; ++k) {
        int x = nd.state_vars[static_cast<std::size_t>(k)];
        int dx = g_.add_var("der(" + g_.vars[static_cast<std::size_t>(x)].name + ")", VarKind::Derivative, nd.loc, x);
        s_.states.push_back({x, dx, n, nd.initial.items[static_cast<std::size_t>(k)]});
        emit(var(dx), input(k), dx, nd.loc, label(nd, fmt::format("der({}) = {}", st, inertia ? "e" : "f")));
      }
      for (int k = 0; k < nd.dim; ++k) {
        int x = nd.state_vars[static_cast<std::size_t>(k)];
        if (nd.law != LawForm::Linear) {
          emit(output(k), nd.law_rhs[static_cast<std::size_t>(k)], output_id(k), nd.loc, label(nd, fmt::format("{} = law({})", out, st)));
        } else {
          // p = I f  (q = C e): one row per component; reduce solves the block.
          emit(var(x), row_times(nd.value, k, nd.dim, output), output_id(k), nd.loc,
               label(nd, fmt::format("{} = {} {}", st, inertia ? "I" : "C", out)));
        }
      }
      return;
    }
    // Derivative causality: the state is a function of the imposed input.
    if (nd.law != LawForm::Linear) {
      diags_.error(nd.loc,
                   fmt::format("{} `{}` is in derivative causality, but its nonlinear law cannot be inverted", node_kind_name(nd.kind), nd.name),
                   "give it a linear law, or change the graph so that it gets integral causality (e.g. a stiff C or small R in between)");
      return;
    }
    for (int k = 0; k < nd.dim; ++k) {
      int x = nd.state_vars[static_cast<std::size_t>(k)];
      g_.vars[static_cast<std::size_t>(x)].kind = VarKind::Auxiliary;  // no longer a state
      emit(var(x), row_times(nd.value, k, nd.dim, output), x, nd.loc,
           label(nd, fmt::format("{} = {} {} (derivative causality)", st, inertia ? "I" : "C", out)));
      emit(input(k), der(var(x)), input_id(k), nd.loc,
           label(nd, fmt::format("{} = der({}) (derivative causality)", inertia ? "e" : "f", st)));
    }
  }

  void resistor(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    int b = nd.bonds[0];
    int s = sign(n, b);
    bool sets_e = sets_effort(g_, n, b);
    auto flow = [&](int k) { return signed_(s, f(b, k)); };
    // A nonlinear law solved for the other variable is implicit; reduce hands it to IDA.
    if (nd.law == LawForm::EffortOfFlow || nd.law == LawForm::FlowOfEffort) {
      bool effort_law = nd.law == LawForm::EffortOfFlow;
      for (int k = 0; k < nd.dim; ++k) {
        int unknown = sets_e ? e_id(b, k) : f_id(b, k);
        Expr rhs = nd.law_rhs[static_cast<std::size_t>(k)];
        if (effort_law) emit(e(b, k), rhs, unknown, nd.loc, label(nd, sets_e ? "e = law(f)" : "e = law(f), solved for f"));
        else emit(flow(k), rhs, unknown, nd.loc, label(nd, sets_e ? "f = law(e), solved for e" : "f = law(e)"));
      }
      return;
    }
    for (int k = 0; k < nd.dim; ++k)
      emit(e(b, k), row_times(nd.value, k, nd.dim, flow), sets_e ? e_id(b, k) : f_id(b, k), nd.loc,
           label(nd, sets_e ? "e = R f" : "f = e / R"));
  }

  void transformer(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    int b1 = nd.bonds[0], b2 = nd.bonds[1];
    int s1 = sign(n, b1), s2 = sign(n, b2);  // flow into port 1, out of port 2
    bool forward = sets_effort(g_, n, b1);  // computes e1 and f2
    // f2 = T f1  (rows: dim2)   and   e1 = T^T e2  (rows: dim1)
    for (int r = 0; r < nd.dim2; ++r)
      emit(signed_(s2, f(b2, r)), row_times(nd.value, r, nd.dim, [&](int c) { return signed_(s1, f(b1, c)); }),
           forward ? f_id(b2, r) : f_id(b1, r), nd.loc, label(nd, "f2 = T f1"));
    for (int r = 0; r < nd.dim; ++r)
      emit(e(b1, r), row_times(nd.value, r, nd.dim2, [&](int c) { return e(b2, c); }, /*transpose=*/true),
           forward ? e_id(b1, r) : e_id(b2, r), nd.loc, label(nd, "e1 = T' e2"));
  }

  void gyrator(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    int b1 = nd.bonds[0], b2 = nd.bonds[1];
    int s1 = sign(n, b1), s2 = sign(n, b2);
    bool efforts = sets_effort(g_, n, b1);  // computes e1 and e2 (from the flows)
    // e2 = G f1 (rows: dim2)   and   e1 = G^T f2 (rows: dim1)
    for (int r = 0; r < nd.dim2; ++r)
      emit(e(b2, r), row_times(nd.value, r, nd.dim, [&](int c) { return signed_(s1, f(b1, c)); }),
           efforts ? e_id(b2, r) : f_id(b1, r), nd.loc, label(nd, "e2 = G f1"));
    for (int r = 0; r < nd.dim; ++r)
      emit(e(b1, r), row_times(nd.value, r, nd.dim2, [&](int c) { return signed_(s2, f(b2, c)); }, true),
           efforts ? e_id(b1, r) : f_id(b2, r), nd.loc, label(nd, "e1 = G' f2"));
  }

  void junction(int n) {
    const GraphNode& nd = g_.nodes[static_cast<std::size_t>(n)];
    bool zero = nd.kind == NodeKind::Zero;
    int strong = -1;
    for (int b : nd.bonds) {
      bool junction_sets = sets_effort(g_, n, b);
      if (zero ? !junction_sets : junction_sets) strong = b;
    }
    if (strong < 0) return;  // causality reported the conflict
    for (int k = 0; k < nd.dim; ++k) {
      // Common variable: every other bond copies the strong bond's.
      for (int b : nd.bonds) {
        if (b == strong) continue;
        if (zero) emit(e(b, k), e(strong, k), e_id(b, k), nd.loc, label(nd, "equal efforts"));
        else emit(f(b, k), f(strong, k), f_id(b, k), nd.loc, label(nd, "equal flows"));
      }
      // Balance: sum in = sum out, solved for the strong bond's other variable.
      Expr in = constant(0), out = constant(0);
      for (int b : nd.bonds) {
        Expr x = zero ? f(b, k) : e(b, k);
        if (bond(b).to == n) in = add(in, x);
        else out = add(out, x);
      }
      emit(in, out, zero ? f_id(strong, k) : e_id(strong, k), nd.loc,
           label(nd, zero ? "flows in = flows out" : "efforts in = efforts out"));
    }
  }

  EquationSystem& s_;
  BondGraph& g_;
  Diagnostics& diags_;
};

}  // namespace

EquationSystem generate(CausalGraph causal, Diagnostics& diags) {
  EquationSystem sys;
  sys.graph = std::move(causal.graph);
  sys.causality = std::move(causal.report);
  Generator gen(sys, diags);
  gen.run();
  return sys;
}

}  // namespace mbgc::equations
