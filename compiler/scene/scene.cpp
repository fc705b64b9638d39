#include "scene/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <unordered_set>

namespace mbgc::scene {

using namespace mbgc::ir;

namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// A number as written in a scene: `2`, `-0.5`.
std::optional<double> literal(const AstExpr& e) {
  if (e.kind == AstExpr::Kind::Number) return e.number;
  if (e.kind == AstExpr::Kind::Unary && e.args.size() == 1 && e.args[0]->kind == AstExpr::Kind::Number)
    return e.op == '-' ? -e.args[0]->number : e.args[0]->number;
  return std::nullopt;
}

/// An output's name without its component index: "v[2]" -> "v".
std::string base_name(const std::string& column) { return column.substr(0, column.find('[')); }

/// Every expression a node's law reads (its parameters and variables).
std::vector<Expr> node_exprs(const GraphNode& n) {
  std::vector<Expr> out;
  for (const Value* v : {&n.value, &n.constraint_g, &n.initial})
    for (const Expr& e : v->items)
      if (e) out.push_back(e);
  for (const Expr& e : n.law_rhs)
    if (e) out.push_back(e);
  return out;
}

/// The top-level name a graph node belongs to: "rod3" for "rod3.v.J".
std::string owner_of(const std::string& path) { return path.substr(0, path.find('.')); }

}  // namespace

std::vector<AstScene> take_scenes(AstProgram& program, Diagnostics& diags) {
  std::vector<AstScene> scenes;
  std::vector<AstStmt> rest;
  for (AstStmt& st : program.stmts) {
    if (auto* s = std::get_if<AstScene>(&st)) {
      for (const AstScene& earlier : scenes)
        if (earlier.name == s->name)
          diags.error(s->loc, fmt::format("scene `{}` is declared twice", s->name), "give each scene its own name")
              .notes.push_back({earlier.loc, "first declared here"});
      scenes.push_back(std::move(*s));
    } else {
      rest.push_back(std::move(st));
    }
  }
  program.stmts = std::move(rest);
  return scenes;
}

std::optional<SelectedScene> select_scene(const std::vector<AstScene>& scenes, const std::string& name,
                                          const AstProgram& program, Diagnostics& diags) {
  auto it = std::find_if(scenes.begin(), scenes.end(), [&](const AstScene& s) { return s.name == name; });
  if (it == scenes.end()) return std::nullopt;
  std::vector<std::string> params;
  for (const AstStmt& st : program.stmts)
    if (const auto* p = std::get_if<AstParam>(&st)) params.push_back(p->name);

  SelectedScene sel{it->name, it->loc, {}, {}};
  bool has_outputs = false, ok = true;
  for (const AstAttr& a : it->attrs) {
    if (a.key == "outputs") {
      if (has_outputs) {
        diags.error(a.loc, fmt::format("scene `{}` gives `outputs` twice", sel.name), "list every output in one `outputs = [...]`");
        ok = false;
        continue;
      }
      has_outputs = true;
      if (a.value->kind != AstExpr::Kind::List || a.value->args.empty()) {
        diags.error(a.value->loc, "a scene's `outputs` is a list of the model's output names",
                    "write outputs = [name1, name2]");
        ok = false;
        continue;
      }
      for (const AstExprPtr& e : a.value->args) {
        if (e->kind != AstExpr::Kind::Name) {
          diags.error(e->loc, "expected an output's name", "write outputs = [name1, name2] with names of `output` statements");
          ok = false;
          continue;
        }
        sel.outputs.emplace_back(e->name, e->loc);
      }
      continue;
    }
    if (std::find(params.begin(), params.end(), a.key) == params.end()) {
      const std::string near = closest_name(a.key, params);
      diags.error(a.loc, fmt::format("scene `{}` sets `{}`, which is not a top-level parameter of the model", sel.name, a.key),
                  near.empty() ? "a scene may set `outputs` and the model's top-level parameters (param NAME = ...)"
                               : fmt::format("did you mean `{}`?", near));
      ok = false;
      continue;
    }
    const std::optional<double> v = literal(*a.value);
    if (!v) {
      diags.error(a.value->loc, fmt::format("a scene fixes `{}` to a number", a.key),
                  fmt::format("write {} = 2 (the scene acts as mbgc --set {}=2)", a.key, a.key));
      ok = false;
      continue;
    }
    sel.overrides[a.key] = *v;
  }
  if (!has_outputs) {
    diags.error(sel.loc, fmt::format("scene `{}` does not say which outputs it needs", sel.name),
                "write outputs = [name1, name2] in the scene's block");
    ok = false;
  }
  if (!ok) return std::nullopt;
  return sel;
}

std::string no_such_scene(const std::vector<AstScene>& scenes, const std::string& name) {
  std::vector<std::string> names;
  for (const AstScene& s : scenes) names.push_back("`" + s.name + "`");
  return fmt::format("the model declares no scene `{}` ({})", name,
                     names.empty() ? std::string("it declares none: write scene NAME { outputs = [a, b] }")
                                   : fmt::format("its scenes: {}", fmt::join(names, ", ")));
}

SceneReport prune_graph(BondGraph& g, const SelectedScene& scene, Diagnostics& diags) {
  SceneReport rep;
  rep.scene = scene.name;
  rep.nodes_before = static_cast<int>(g.nodes.size());
  rep.bonds_before = static_cast<int>(g.bonds.size());
  for (const GraphNode& n : g.nodes) rep.states_before += static_cast<int>(n.state_vars.size());

  // The requested outputs (a vector output `v` is its columns v[1], v[2], ...).
  std::vector<char> keep_output(g.outputs.size(), 0);
  std::vector<std::string> declared;
  for (const Output& o : g.outputs)
    if (declared.empty() || declared.back() != base_name(o.name)) declared.push_back(base_name(o.name));
  for (const auto& [name, loc] : scene.outputs) {
    bool found = false;
    for (std::size_t i = 0; i < g.outputs.size(); ++i)
      if (base_name(g.outputs[i].name) == name) keep_output[i] = 1, found = true;
    if (!found) {
      const std::string near = closest_name(name, declared);
      diags.error(loc, fmt::format("scene `{}` asks for output `{}`, which the model does not declare", scene.name, name),
                  near.empty() ? "list names of the model's `output` statements" : fmt::format("did you mean `{}`?", near));
    }
  }
  if (diags.has_errors()) return rep;

  // Who owns each variable: a state's storage, both ends of a bond, a signal.
  std::vector<std::vector<int>> owners(g.vars.size());
  std::vector<int> signal_of(g.vars.size(), -1);
  for (std::size_t n = 0; n < g.nodes.size(); ++n)
    for (int v : g.nodes[n].state_vars) owners[at(v)].push_back(static_cast<int>(n));
  for (const Bond& b : g.bonds)
    for (const std::vector<int>* vs : {&b.effort_vars, &b.flow_vars})
      for (int v : *vs) owners[at(v)] = {b.from, b.to};
  for (std::size_t s = 0; s < g.signals.size(); ++s)
    if (g.signals[s].var >= 0) signal_of[at(g.signals[s].var)] = static_cast<int>(s);
  for (std::size_t v = 0; v < g.vars.size(); ++v)  // der(x) belongs where x does
    if (g.vars[v].kind == VarKind::Derivative && g.vars[v].of >= 0) owners[v] = owners[at(g.vars[v].of)];

  std::vector<char> need_var(g.vars.size(), 0), need_node(g.nodes.size(), 0), need_signal(g.signals.size(), 0);
  std::deque<int> vars, nodes;
  auto want_vars_of = [&](const Expr& e) {
    std::unordered_set<int> read;
    collect_vars(e, read);
    for (int v : read)
      if (!need_var[at(v)]) need_var[at(v)] = 1, vars.push_back(v);
  };
  auto want_node = [&](int n) {
    if (n >= 0 && !need_node[at(n)]) need_node[at(n)] = 1, nodes.push_back(n);
  };
  for (std::size_t i = 0; i < g.outputs.size(); ++i)
    if (keep_output[i]) want_vars_of(g.outputs[i].value);
  while (!vars.empty() || !nodes.empty()) {
    if (!vars.empty()) {
      const int v = vars.front();
      vars.pop_front();
      for (int n : owners[at(v)]) want_node(n);
      if (const int s = signal_of[at(v)]; s >= 0 && !need_signal[at(s)]) {
        need_signal[at(s)] = 1;
        want_vars_of(g.signals[at(s)].value);
        if (g.signals[at(s)].rate) want_vars_of(g.signals[at(s)].rate);
      }
      continue;
    }
    const int n = nodes.front();
    nodes.pop_front();
    for (int b : g.nodes[at(n)].bonds) want_node(g.bonds[at(b)].from), want_node(g.bonds[at(b)].to);
    for (const Expr& e : node_exprs(g.nodes[at(n)])) want_vars_of(e);
  }

  // Rebuild the graph from what is needed (variable ids stay as they are).
  std::vector<int> node_index(g.nodes.size(), -1), bond_index(g.bonds.size(), -1);
  std::vector<GraphNode> kept_nodes;
  for (std::size_t n = 0; n < g.nodes.size(); ++n) {
    if (need_node[n]) {
      node_index[n] = static_cast<int>(kept_nodes.size());
      kept_nodes.push_back(std::move(g.nodes[n]));
    } else {
      rep.removed_nodes.push_back(fmt::format("{} ({})", g.nodes[n].name, node_kind_name(g.nodes[n].kind)));
    }
  }
  std::vector<Bond> kept_bonds;
  for (std::size_t b = 0; b < g.bonds.size(); ++b) {
    if (node_index[at(g.bonds[b].from)] < 0) continue;  // a kept node's bonds join only kept nodes
    bond_index[b] = static_cast<int>(kept_bonds.size());
    Bond bond = std::move(g.bonds[b]);
    bond.from = node_index[at(bond.from)];
    bond.to = node_index[at(bond.to)];
    kept_bonds.push_back(std::move(bond));
  }
  for (GraphNode& n : kept_nodes)
    for (int& b : n.bonds) b = bond_index[at(b)];
  for (Variable& v : g.vars)  // an effort or flow names its bond: renumbered too (-1: removed)
    if ((v.kind == VarKind::Effort || v.kind == VarKind::Flow) && v.of >= 0) v.of = bond_index[at(v.of)];
  g.nodes = std::move(kept_nodes);
  g.bonds = std::move(kept_bonds);

  std::vector<Signal> kept_signals;
  for (std::size_t s = 0; s < g.signals.size(); ++s) {
    if (need_signal[s]) kept_signals.push_back(std::move(g.signals[s]));
    else rep.removed_signals.push_back(g.signals[s].name);
  }
  g.signals = std::move(kept_signals);
  std::vector<Output> kept_outputs;
  for (std::size_t i = 0; i < g.outputs.size(); ++i) {
    const std::string name = base_name(g.outputs[i].name);
    std::vector<std::string>& list = keep_output[i] ? rep.kept_outputs : rep.removed_outputs;
    if (list.empty() || list.back() != name) list.push_back(name);
    if (keep_output[i]) kept_outputs.push_back(std::move(g.outputs[i]));
  }
  g.outputs = std::move(kept_outputs);
  // A drawn body stays if everything its pose reads is kept.
  std::vector<DrawnBody> kept_drawings;
  for (DrawnBody& d : g.drawings) {
    std::unordered_set<int> reads;
    d.for_each_expr([&](const Expr& e) { collect_vars(e, reads); });
    if (std::all_of(reads.begin(), reads.end(), [&](int v) { return need_var[at(v)] != 0; }))
      kept_drawings.push_back(std::move(d));
  }
  g.drawings = std::move(kept_drawings);

  // Parameters nothing kept reads any more (directly or through other parameters).
  std::unordered_set<int> read;
  for (const GraphNode& n : g.nodes)
    for (const Expr& e : node_exprs(n)) collect_params(e, read);
  for (const Signal& s : g.signals)
    for (const Expr& e : {s.value, s.rate})
      if (e) collect_params(e, read);
  for (const Output& o : g.outputs) collect_params(o.value, read);
  for (const DrawnBody& d : g.drawings) d.for_each_expr([&](const Expr& e) { collect_params(e, read); });
  for (std::size_t p = g.params.size(); p-- > 0;)  // dependencies come first: walk back
    if (read.count(static_cast<int>(p)) && g.params[p].value) collect_params(g.params[p].value, read);
  // ... are removed too (a scene's simulator refuses --set for them), and
  // the others renumbered in every expression that reads one.
  std::vector<int> param_index(g.params.size(), -1);
  std::vector<Parameter> kept_params;
  for (std::size_t p = 0; p < g.params.size(); ++p) {
    if (!read.count(static_cast<int>(p))) {
      rep.idle_parameters.push_back(g.params[p].name);
      continue;
    }
    param_index[p] = static_cast<int>(kept_params.size());
    kept_params.push_back(std::move(g.params[p]));
  }
  g.params = std::move(kept_params);
  const auto renumber = [&](Expr& e) {
    if (!e) return;
    e = rewrite(e, [&](const Expr& x) -> Expr { return x->op == Op::Param ? param(param_index[at(x->id)]) : nullptr; });
  };
  for (Parameter& p : g.params) renumber(p.value);
  for (GraphNode& n : g.nodes) {
    for (Value* v : {&n.value, &n.constraint_g, &n.initial})
      for (Expr& e : v->items) renumber(e);
    for (Expr& e : n.law_rhs) renumber(e);
  }
  for (Signal& s : g.signals) renumber(s.value), renumber(s.rate);
  for (Output& o : g.outputs) renumber(o.value);
  for (DrawnBody& d : g.drawings) d.for_each_expr(renumber);
  // A unit check on a removed parameter goes with it.
  std::vector<UnitCheck> kept_checks;
  for (UnitCheck& c : g.unit_checks) {
    std::unordered_set<int> ps;
    for (const Expr& e : c.items) collect_params(e, ps);
    if (std::any_of(ps.begin(), ps.end(), [&](int p) { return param_index[at(p)] < 0; })) continue;
    for (Expr& e : c.items) renumber(e);
    kept_checks.push_back(std::move(c));
  }
  g.unit_checks = std::move(kept_checks);

  rep.nodes_after = static_cast<int>(g.nodes.size());
  rep.bonds_after = static_cast<int>(g.bonds.size());
  for (const GraphNode& n : g.nodes) rep.states_after += static_cast<int>(n.state_vars.size());
  return rep;
}

std::string explain(const SceneReport& r) {
  std::string out = fmt::format("scene `{}`\n", r.scene);
  out += fmt::format("  outputs kept: {}\n", fmt::join(r.kept_outputs, ", "));
  if (!r.removed_outputs.empty()) out += fmt::format("  outputs dropped: {}\n", fmt::join(r.removed_outputs, ", "));
  out += fmt::format("  graph: {} of {} nodes, {} of {} bonds, {} of {} states kept\n", r.nodes_after, r.nodes_before,
                     r.bonds_after, r.bonds_before, r.states_after, r.states_before);
  if (r.removed_nodes.empty()) {
    out += "  removed: nothing (every part can act on the outputs)\n";
  } else {
    out += "  removed (cannot act on the outputs):\n";
    std::vector<std::pair<std::string, std::vector<std::string>>> groups;
    for (const std::string& n : r.removed_nodes) {
      const std::string owner = owner_of(n.substr(0, n.find(" (")));
      if (groups.empty() || groups.back().first != owner) groups.push_back({owner, {}});
      groups.back().second.push_back(n);
    }
    for (auto& [owner, members] : groups) {
      if (members.size() == 1 && members[0].rfind(owner + " (", 0) == 0) {  // a top-level element
        out += fmt::format("    {}\n", members[0]);
        continue;
      }
      for (std::string& m : members)
        if (m.rfind(owner + ".", 0) == 0) m = m.substr(owner.size() + 1);
      out += fmt::format("    {}: {}\n", owner, fmt::join(members, ", "));
    }
  }
  if (!r.removed_signals.empty()) out += fmt::format("  signals removed: {}\n", fmt::join(r.removed_signals, ", "));
  // The model's own parameters by name; those the expansion made (hinge.Fa[1,2]) only counted.
  std::vector<std::string> declared;
  for (const std::string& p : r.idle_parameters)
    if (p.find_first_of(".[") == std::string::npos) declared.push_back(p);
  const std::size_t internal = r.idle_parameters.size() - declared.size();
  if (!r.idle_parameters.empty())
    out += fmt::format("  parameters removed (they act on no output): {}{}\n",
                       declared.empty() ? "none of the model's own" : fmt::format("{}", fmt::join(declared, ", ")),
                       internal ? fmt::format(" (and {} of bodies, joints or elements)", internal) : "");
  return out;
}

}  // namespace mbgc::scene
