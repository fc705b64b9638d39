#include "ir/print.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace mbgc::ir {

Namer model_namer(const BondGraph& g) {
  Namer n;
  n.var = [&g](int id) { return g.vars[static_cast<std::size_t>(id)].name; };
  n.param = [&g](int id) { return g.params[static_cast<std::size_t>(id)].name; };
  return n;
}

// ---- AST ---------------------------------------------------------------------------
/// ` {N/m}` after a declaration that has one.
static std::string declared(const std::optional<AstUnit>& unit) {
  return unit ? fmt::format(" {{{}}}", unit->unit.text) : std::string();
}

/// An AST expression or a term, as the user would write it (a ref as its name).
template <class X>
static std::string ast_expr(const X& e) {
  using K = typename X::Kind;
  switch (e.kind) {
    case K::Number:
      if (e.unit) return fmt::format("{} {{{}}}", e.written, e.unit->unit.text);
      return fmt::format("{}", e.number);
    case K::String: return fmt::format("\"{}\"", e.name);
    case K::Unary: return fmt::format("({}{})", e.op, ast_expr(*e.args[0]));
    case K::Binary: return fmt::format("({} {} {})", ast_expr(*e.args[0]), e.op, ast_expr(*e.args[1]));
    case K::Call:
    case K::List:
    case K::Index: {
      std::vector<std::string> parts;
      std::size_t first = e.kind == K::Index ? 1 : 0;
      for (std::size_t i = first; i < e.args.size(); ++i) parts.push_back(ast_expr(*e.args[i]));
      if (e.kind == K::Call) return fmt::format("{}({})", e.name, fmt::join(parts, ", "));
      if (e.kind == K::List) return fmt::format("[{}]", fmt::join(parts, ", "));
      return fmt::format("{}[{}]", ast_expr(*e.args[0]), fmt::join(parts, ", "));
    }
    default: return e.name;  // a name (AST) or a ref (a term)
  }
  return "?";
}

template <class Attr>
static std::string attrs(const std::vector<Attr>& a) {
  std::vector<std::string> parts;
  for (const Attr& x : a) parts.push_back(fmt::format("{} = {}", x.key, ast_expr(*x.value)));
  return fmt::format("{{ {} }}", fmt::join(parts, "; "));
}

/// The points of a body or ground block, its `for` loops where they stand.
static std::vector<std::string> ast_points(const std::vector<AstPoint>& points,
                                           const std::vector<std::shared_ptr<AstPointFor>>& loops) {
  std::vector<std::string> parts;
  std::size_t next_loop = 0;
  for (std::size_t k = 0; k <= points.size(); ++k) {
    for (; next_loop < loops.size() && loops[next_loop]->position == k; ++next_loop) {
      const AstPointFor& f = *loops[next_loop];
      parts.push_back(fmt::format("for {} in {}..{} {{ {} }}", f.var, ast_expr(*f.from), ast_expr(*f.to),
                                  fmt::join(ast_points(f.points, f.loops), "; ")));
    }
    if (k < points.size()) parts.push_back(fmt::format("point {} = {}", points[k].name, ast_expr(*points[k].value)));
  }
  return parts;
}

/// The statements as written (AstStmt) or after the expansion
/// (ExpandedStmt: a derived parameter prints as `const`, a signal its rate).
template <class Stmt>
static void ast_stmts(std::string& out, const std::vector<Stmt>& stmts, int indent) {
  std::string pad(static_cast<std::size_t>(indent), ' ');
  for (const Stmt& s : stmts) {
    std::visit(
        [&](const auto& st) {
          using T = std::decay_t<decltype(st)>;
          if constexpr (std::is_same_v<T, AstModel>) out += fmt::format("{}model {}\n", pad, st.name);
          else if constexpr (std::is_same_v<T, AstImport>) out += fmt::format("{}import \"{}\"\n", pad, st.path);
          else if constexpr (std::is_same_v<T, AstParam> || std::is_same_v<T, ExpandedParam>) {
            bool fold = false;
            if constexpr (std::is_same_v<T, ExpandedParam>) fold = st.fold;
            out += fmt::format("{}{} {} = {}{}\n", pad, fold ? "const" : "param", st.name, ast_expr(*st.value),
                               declared(st.unit));
          } else if constexpr (std::is_same_v<T, AstSignal> || std::is_same_v<T, ExpandedSignal>) {
            out += fmt::format("{}signal {} = {}{}", pad, st.name, ast_expr(*st.value), declared(st.unit));
            std::string rate;
            if constexpr (std::is_same_v<T, ExpandedSignal>)
              if (st.rate) rate = ast_expr(*st.rate);
            out += rate.empty() ? "\n" : fmt::format("  // d/dt = {}\n", rate);
          }
          else if constexpr (std::is_same_v<T, AstOutput> || std::is_same_v<T, ExpandedOutput>)
            out += fmt::format("{}output {} = {}{}\n", pad, st.name, ast_expr(*st.value), declared(st.unit));
          else if constexpr (std::is_same_v<T, AstElement> || std::is_same_v<T, ExpandedElement>) {
            out += fmt::format("{}{} {}", pad, st.kind, st.name);
            if (st.value) out += " = " + ast_expr(*st.value);
            auto settings = st.attrs;
            if constexpr (std::is_same_v<T, ExpandedElement>)
              if (st.constraint)  // printed as a user would write it
                for (const ConstraintLaw::Field& f : ConstraintLaw::fields())
                  if (const TermPtr& v = (*st.constraint).*f.member) settings.push_back({f.key, v->loc, v});
            if (!settings.empty()) out += " " + attrs(settings);
            out += "\n";
          } else if constexpr (std::is_same_v<T, AstJunction> || std::is_same_v<T, ExpandedJunction>) {
            std::vector<std::string> in, o;
            for (const auto& e : st.inputs) in.push_back(e.path);
            for (const auto& e : st.outputs) o.push_back(e.path);
            out += fmt::format("{}{} {}{} : {} -> {}\n", pad, st.type, st.name, st.dim ? fmt::format(" [{}]", *st.dim) : "",
                               fmt::join(in, ", "), fmt::join(o, ", "));
          } else if constexpr (std::is_same_v<T, AstBond> || std::is_same_v<T, ExpandedBond>) {
            out += fmt::format("{}bond {}{} -> {}{}\n", pad, st.name.empty() ? "" : st.name + ": ", st.from.path, st.to.path,
                               st.dim ? fmt::format(" [{}]", *st.dim) : "");
          } else if constexpr (std::is_same_v<T, AstSimulate>) {
            out += fmt::format("{}simulate {}\n", pad, attrs(st.settings));
          } else if constexpr (std::is_same_v<T, AstScene>) {
            out += fmt::format("{}scene {} {}\n", pad, st.name, attrs(st.attrs));
          } else if constexpr (std::is_same_v<T, AstInstance>) {
            std::vector<std::string> a;
            for (const AstAttr& x : st.args) a.push_back(fmt::format("{} = {}", x.key, ast_expr(*x.value)));
            out += fmt::format("{}instance {} = {}({})\n", pad, st.name, st.component, fmt::join(a, ", "));
          } else if constexpr (std::is_same_v<T, AstBody>) {
            std::vector<std::string> parts;
            for (const AstAttr& x : st.attrs) parts.push_back(fmt::format("{} = {}", x.key, ast_expr(*x.value)));
            for (std::string& p : ast_points(st.points, st.loops)) parts.push_back(std::move(p));
            if (st.name == "ground") out += fmt::format("{}ground {{ {} }}\n", pad, fmt::join(parts, "; "));
            else out += fmt::format("{}body {} {{ {} }}\n", pad, st.name, fmt::join(parts, "; "));
          } else if constexpr (std::is_same_v<T, AstJoint>) {
            if (st.connector == Connector::Joint)
              out += fmt::format("{}joint {} {}({}, {})", pad, st.name, st.type, st.a.path, st.b.path);
            else
              out += fmt::format("{}{} {}({}, {})", pad, connector_keyword(st.connector), st.name,
                                 st.a.path, st.b.path);
            if (!st.attrs.empty()) out += " " + attrs(st.attrs);
            out += "\n";
          } else if constexpr (std::is_same_v<T, AstSetting>) {
            out += fmt::format("{}{} = {}\n", pad, st.key, ast_expr(*st.value));
          } else if constexpr (std::is_same_v<T, std::shared_ptr<AstFor>>) {
            out += fmt::format("{}for {} in {}..{} {{\n", pad, st->var, ast_expr(*st->from), ast_expr(*st->to));
            ast_stmts(out, st->body, indent + 2);
            out += pad + "}\n";
          } else {
            std::vector<std::string> iface;
            for (const auto& p : st->ports) iface.push_back("port " + p.path);
            for (const auto& p : st->params)
              iface.push_back(p.value ? fmt::format("param {} = {}", p.name, ast_expr(*p.value)) : "param " + p.name);
            out += fmt::format("{}component {}({}) {{\n", pad, st->name, fmt::join(iface, ", "));
            ast_stmts(out, st->body, indent + 2);
            out += pad + "}\n";
          }
        },
        s);
  }
}

std::string print_ast(const AstProgram& program) {
  std::string out;
  ast_stmts(out, program.stmts, 0);
  return out;
}

std::string print_expanded(const ExpandedProgram& program) {
  std::string out;
  ast_stmts(out, program.stmts, 0);
  return out;
}

// ---- graph ----------------------------------------------------------------------------
static std::string value_text(const Value& v, const Namer& n) {
  if (v.items.empty()) return "";
  if (v.is_scalar()) return to_string(v.items[0], n);
  std::vector<std::string> rows;
  for (int r = 0; r < v.rows; ++r) {
    std::vector<std::string> cols;
    for (int c = 0; c < v.cols; ++c) cols.push_back(to_string(v.at(r, c), n));
    rows.push_back(v.cols == 1 ? cols[0] : fmt::format("[{}]", fmt::join(cols, ", ")));
  }
  return fmt::format("[{}]", fmt::join(rows, ", "));
}

static std::string law_text(const GraphNode& nd, const Namer& n) {
  auto rhs = [&] { return value_text(Value{static_cast<int>(nd.law_rhs.size()), 1, nd.law_rhs}, n); };
  switch (nd.law) {
    case LawForm::EffortOfFlow: return "e = " + rhs();
    case LawForm::FlowOfEffort: return "f = " + rhs();
    case LawForm::EffortOfState: return "e = " + rhs();
    case LawForm::FlowOfState: return "f = " + rhs();
    case LawForm::Constraint: return "f = d/dt g = 0 (lagrange), g = " + value_text(nd.constraint_g, n);
    case LawForm::Penalty: return "e = " + rhs() + " (penalty), g = " + value_text(nd.constraint_g, n);
    case LawForm::Unilateral:
      return fmt::format("contact g >= 0 (unilateral: a row while it pushes, impacts with restitution {}), g = {}",
                         to_string(nd.law_rhs[1], n), value_text(nd.constraint_g, n));
    case LawForm::Compliant:
      return fmt::format("contact g >= 0 (compliant: Hunt-Crossley, stiffness {}, exponent {}, restitution {}), g = {}",
                         to_string(nd.law_rhs[0], n), to_string(nd.law_rhs[1], n), to_string(nd.law_rhs[2], n),
                         value_text(nd.constraint_g, n));
    default: return value_text(nd.value, n);
  }
}

std::string print_graph(const BondGraph& g) {
  Namer n = model_namer(g);
  std::string out = fmt::format("model {}: {} nodes, {} bonds\n", g.model_name, g.nodes.size(), g.bonds.size());
  out += "nodes:\n";
  for (const GraphNode& nd : g.nodes) {
    std::string dim = is_two_port(nd.kind) ? fmt::format("[{}->{}]", nd.dim, nd.dim2) : fmt::format("[{}]", nd.dim);
    out += fmt::format("  {:<3} {} {}", node_kind_name(nd.kind), nd.name, dim);
    if (!is_junction(nd.kind)) out += "  " + law_text(nd, n);
    out += "\n";
  }
  out += "bonds:\n";
  for (const Bond& b : g.bonds)
    out += fmt::format("  {:>3}  {} -> {}  [{}]  e: {}  f: {}\n", b.number, g.nodes[static_cast<std::size_t>(b.from)].name,
                       g.nodes[static_cast<std::size_t>(b.to)].name, b.dim,
                       g.vars[static_cast<std::size_t>(b.effort_vars[0])].name, g.vars[static_cast<std::size_t>(b.flow_vars[0])].name);
  if (!g.signals.empty()) out += "signals:\n";
  for (const Signal& s : g.signals) {
    out += fmt::format("  {} = {}\n", s.name, to_string(s.value, n));
    if (s.rate) out += fmt::format("    d/dt = {}\n", to_string(s.rate, n));
  }
  if (!g.outputs.empty()) out += "outputs:\n";
  for (const Output& o : g.outputs) out += fmt::format("  {} = {}\n", o.name, to_string(o.value, n));
  return out;
}

std::string print_graph_dot(const BondGraph& g, bool with_causality) {
  std::string out = fmt::format("// {} graph of model {} (mbgc --dump=graph --format=dot | dot -Tsvg)\n",
                                with_causality ? "causal multibond" : "multibond", g.model_name);
  out += "digraph bondgraph {\n  rankdir=LR;\n  node [shape=plaintext, fontname=\"Helvetica\"];\n"
         "  edge [fontname=\"Helvetica\", fontsize=10];\n";
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    const GraphNode& nd = g.nodes[i];
    std::string label = is_junction(nd.kind) ? fmt::format("{}\\n{}", node_kind_name(nd.kind), nd.name)
                                             : fmt::format("{}: {}", node_kind_name(nd.kind), nd.name);
    out += fmt::format("  n{} [label=\"{}\"];\n", i, label);
  }
  for (const Bond& b : g.bonds) {
    // Half-arrow head at `to` (power direction); the causal stroke (a bar,
    // "tee") at the end that receives the effort, i.e. not the effort setter.
    std::string label = b.dim > 1 ? fmt::format("{} [{}]", b.number, b.dim) : std::to_string(b.number);
    std::string head = "lvee", tail;
    if (with_causality && b.effort_setter >= 0) {
      if (b.effort_setter == b.from) head = "teelvee";  // the `to` end receives the effort
      else tail = ", dir=both, arrowtail=tee";
    }
    // A multibond is drawn heavier and labelled with its dimension.
    std::string attrs = fmt::format("label=\"{}\", arrowhead={}{}{}", label, head, tail, b.dim > 1 ? ", penwidth=3" : "");
    out += fmt::format("  n{} -> n{} [{}];\n", b.from, b.to, attrs);
  }
  out += "}\n";
  return out;
}

// ---- causality ---------------------------------------------------------------------------
std::string print_causality(const CausalGraph& c) {
  const BondGraph& g = c.graph;
  std::string out = fmt::format("causality of model {} (SCAP)\n", g.model_name);
  out += "bonds (stroke at the end that receives the effort):\n";
  for (const Bond& b : g.bonds) {
    std::string setter = b.effort_setter >= 0 ? g.nodes[static_cast<std::size_t>(b.effort_setter)].name : "?";
    int receiver = b.effort_setter == b.from ? b.to : b.from;
    out += fmt::format("  {:>3}  {} -> {}  effort from {}, stroke at {}\n", b.number, g.nodes[static_cast<std::size_t>(b.from)].name,
                       g.nodes[static_cast<std::size_t>(b.to)].name, setter,
                       b.effort_setter >= 0 ? g.nodes[static_cast<std::size_t>(receiver)].name : "?");
  }
  out += "procedure:\n";
  for (const std::string& s : c.report.steps) out += "  " + s + "\n";
  out += fmt::format("report:\n  states ({}):", c.report.integral.size());
  for (int n : c.report.integral) {
    const GraphNode& nd = g.nodes[static_cast<std::size_t>(n)];
    out += fmt::format(" {}.{}", nd.name, nd.kind == NodeKind::I ? "p" : "q");
  }
  out += fmt::format("\n  derivative causality ({}):", c.report.derivative.size());
  for (int n : c.report.derivative) out += " " + g.nodes[static_cast<std::size_t>(n)].name;
  out += fmt::format("\n  arbitrary choices ({}): ", c.report.chosen.size());
  std::vector<std::string> chosen;
  for (int b : c.report.chosen) chosen.push_back(fmt::format("bond {}", g.bonds[static_cast<std::size_t>(b)].number));
  out += fmt::format("{}\n", fmt::join(chosen, ", "));
  return out;
}

// ---- equations -----------------------------------------------------------------------------
std::string print_equations(const EquationSystem& s) {
  Namer n = model_namer(s.graph);
  std::string out = fmt::format("equations of model {}: {} equations, {} states\n", s.graph.model_name, s.equations.size(), s.states.size());
  for (const Equation& eq : s.equations)
    out += fmt::format("  [{}]  {} = {}    ; {} (line {})\n", s.graph.vars[static_cast<std::size_t>(eq.unknown)].name,
                       to_string(eq.lhs, n), to_string(eq.rhs, n), eq.origin, eq.loc.line);
  return out;
}

// ---- reduced ---------------------------------------------------------------------------------
std::string print_reduced(const ReducedSystem& s) {
  const BondGraph& g = s.graph;
  Namer n = model_namer(g);
  std::string out = fmt::format("reduced model {}: {} states, {} assignments{}\n", g.model_name, s.states.size(),
                                s.assignments.size(), s.dae ? fmt::format(", DAE with {} algebraic unknowns", s.algebraic.size()) : ", ODE");
  out += "reduction:\n";
  for (const std::string& l : s.log) out += "  " + l + "\n";
  if (!s.derivative_causality.empty()) out += "derivative causality:\n";
  for (const std::string& l : s.derivative_causality) out += "  " + l + "\n";
  out += fmt::format("algebraic loops ({}):\n", s.loops.size());
  for (const AlgebraicLoop& l : s.loops) {
    std::vector<std::string> vars, bonds;
    for (int v : l.vars) vars.push_back(g.vars[static_cast<std::size_t>(v)].name);
    for (int b : l.bonds) bonds.push_back(std::to_string(g.bonds[static_cast<std::size_t>(b)].number));
    out += fmt::format("  bonds {}: unknowns {} — {}\n", fmt::join(bonds, ", "), fmt::join(vars, ", "), l.resolution);
  }
  out += "assignments (in order):\n";
  for (std::size_t i = 0; i < s.assignments.size(); ++i) {
    const Assignment& a = s.assignments[i];
    auto in = [&](const std::vector<int>& slice) { return std::find(slice.begin(), slice.end(), static_cast<int>(i)) != slice.end(); };
    std::string value = a.block >= 0 ? fmt::format("solve(block {})", a.block + 1) : to_string(a.value, n);
    out += fmt::format("  {} := {}    ; {}{}{}{}{}\n", g.vars[static_cast<std::size_t>(a.var)].name, value, a.origin,
                       in(s.for_derivative) ? " [derivative]" : "", in(s.for_outputs) ? " [outputs]" : "",
                       in(s.for_drawings) ? " [poses]" : "",
                       in(s.for_energy) || in(s.for_power) ? " [energy]" : "");
  }
  // A torn loop's entries are DAGs whose printed trees can be huge (a long
  // chain's mass matrix): past this size an entry prints as its node count.
  auto entry = [&](const Expr& e) {
    std::size_t nodes = size(e);
    return nodes > 4000 ? fmt::format("<expression of {} nodes as a tree>", nodes) : to_string(e, n);
  };
  for (std::size_t k = 0; k < s.linear_blocks.size(); ++k) {
    const LinearBlock& lb = s.linear_blocks[k];
    std::size_t m = lb.unknowns.size();
    out += fmt::format("linear block {} (A x = b, solved at run time with partial pivoting):\n", k + 1);
    for (std::size_t r = 0; r < m; ++r) {
      std::vector<std::string> row;
      for (std::size_t c = 0; c < m; ++c) row.push_back(entry(lb.a[r * m + c]));
      out += fmt::format("  [{}] * x = {}\n", fmt::join(row, ", "), entry(lb.b[r]));
    }
    std::vector<std::string> xs;
    for (int u : lb.unknowns) xs.push_back(g.vars[static_cast<std::size_t>(u)].name);
    out += fmt::format("  x = ({})\n", fmt::join(xs, ", "));
  }
  out += "states:\n";
  for (std::size_t i = 0; i < s.states.size(); ++i) {
    const StateVar& st = s.states[i];
    out += fmt::format("  {}' = {}    (initial {})\n", g.vars[static_cast<std::size_t>(st.var)].name,
                       to_string(s.state_derivative[i], n), to_string(st.initial, n));
  }
  if (!s.jacobian.empty()) {
    out += "jacobian (nonzero entries d x_i' / d x_j):\n";
    std::size_t m = s.states.size();
    for (std::size_t k = 0; k < s.jacobian.size(); ++k)
      if (!is_zero(s.jacobian[k]))
        out += fmt::format("  [{}, {}] = {}\n", g.vars[static_cast<std::size_t>(s.states[k / m].var)].name,
                           g.vars[static_cast<std::size_t>(s.states[k % m].var)].name, to_string(s.jacobian[k], n));
  }
  if (s.dae) {
    out += "residuals:\n";
    for (const Residual& r : s.residuals) out += fmt::format("  0 = {}    ; {}\n", to_string(r.value, n), r.origin);
  }
  out += "outputs:\n";
  for (const Output& o : g.outputs) out += fmt::format("  {} = {}\n", o.name, to_string(o.value, n));
  if (!g.drawings.empty()) out += "poses of the drawn bodies (origin, rotation row-major; modal coordinates):\n";
  for (const DrawnBody& d : g.drawings) {
    std::vector<std::string> pose, modes;
    for (const Expr& e : d.pose) pose.push_back(to_string(e, n));
    for (const Expr& e : d.modes) modes.push_back(to_string(e, n));
    out += fmt::format("  {}: [{}]{}\n", d.drawing->body, fmt::join(pose, ", "),
                       modes.empty() ? "" : fmt::format("; [{}]", fmt::join(modes, ", ")));
  }
  if (!s.events.empty()) out += "events (each step a mode, switched where its argument crosses 0):\n";
  for (std::size_t k = 0; k < s.events.size(); ++k)
    out += fmt::format("  mode {}: {}, argument {}{}\n", k, to_string(s.events[k].step, n), to_string(s.events[k].arg, n),
                       s.events[k].time_event ? " (time event)" : "");
  return out;
}

}  // namespace mbgc::ir
