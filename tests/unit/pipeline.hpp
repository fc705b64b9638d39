// tests/unit/pipeline.hpp — shared helpers for the per-pass unit tests: run the
// passes on a model text exactly as driver.cpp does (stopping after the first
// pass with an error), look things up by their model names, and evaluate
// ir::Expr numerically.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "causality/scap.hpp"
#include "codegen/emit_cpp.hpp"
#include "equations/generate.hpp"
#include "graph/build_graph.hpp"
#include "ir/print.hpp"
#include "parse/parse.hpp"
#include "reduce/reduce.hpp"
#include "sema/resolve.hpp"

namespace mbgc_test {

namespace ir = mbgc::ir;

enum class Stage { Parse, Resolve, Graph, Causality, Equations, Reduce };

/// Every stage's output is kept (later passes get copies). Not movable:
/// Diagnostics points at the SourceManager.
struct Compiled {
  ir::SourceManager sources;
  ir::Diagnostics diags{sources};
  int file = -1;
  ir::AstProgram ast;
  ir::ResolvedModel resolved;
  ir::BondGraph graph;
  ir::CausalGraph causal;
  ir::EquationSystem equations;
  ir::ReducedSystem reduced;

  Compiled() = default;
  Compiled(const Compiled&) = delete;
  Compiled& operator=(const Compiled&) = delete;

  bool ok() const { return !diags.has_errors(); }
  /// All diagnostics, rendered as the driver prints them (for failure messages).
  std::string messages() const {
    std::ostringstream os;
    diags.render(os);
    return os.str();
  }
};

/// Runs the passes from `ast` (already parsed into c) up to `upto`.
inline void continue_pipeline(Compiled& c, Stage upto, const std::string& path) {
  if (upto == Stage::Parse || c.diags.has_errors()) return;
  c.resolved = mbgc::sema::resolve(mbgc::ir::as_expanded(c.ast), path, c.diags);
  if (upto == Stage::Resolve || c.diags.has_errors()) return;
  c.graph = mbgc::graph::build_graph(c.resolved, c.sources, c.diags);
  if (upto == Stage::Graph || c.diags.has_errors()) return;
  c.causal = mbgc::causality::assign_causality(c.graph, c.diags);
  if (upto == Stage::Causality || c.diags.has_errors()) return;
  c.equations = mbgc::equations::generate(c.causal, c.diags);
  if (upto == Stage::Equations || c.diags.has_errors()) return;
  c.reduced = mbgc::reduce::reduce(c.equations, c.diags);
}

/// Registers `text` as `path` and runs the pipeline up to `upto`.
inline std::unique_ptr<Compiled> run(const std::string& text, Stage upto,
                                     const std::string& path = "test.mbg") {
  auto c = std::make_unique<Compiled>();
  c->file = c->sources.add(path, text);
  c->ast = mbgc::parse::parse_source(c->sources, c->file, c->diags);
  continue_pipeline(*c, upto, path);
  return c;
}

/// Like run(), but reads the file and its imports with parse::load_program.
inline std::unique_ptr<Compiled> run_file(const std::string& path, Stage upto) {
  auto c = std::make_unique<Compiled>();
  c->ast = mbgc::parse::load_program(path, c->sources, c->diags);
  continue_pipeline(*c, upto, path);
  return c;
}

// ---- lookups by model name (-1 if absent) ------------------------------------------
inline int var_id(const ir::BondGraph& g, const std::string& name) {
  for (std::size_t i = 0; i < g.vars.size(); ++i)
    if (g.vars[i].name == name) return static_cast<int>(i);
  return -1;
}
inline int node_id(const ir::BondGraph& g, const std::string& name) {
  for (std::size_t i = 0; i < g.nodes.size(); ++i)
    if (g.nodes[i].name == name) return static_cast<int>(i);
  return -1;
}
inline int param_id(const ir::BondGraph& g, const std::string& name) {
  for (std::size_t i = 0; i < g.params.size(); ++i)
    if (g.params[i].name == name) return static_cast<int>(i);
  return -1;
}
/// Index of the bond with 1-based `number`.
inline int bond_index(const ir::BondGraph& g, int number) {
  for (std::size_t i = 0; i < g.bonds.size(); ++i)
    if (g.bonds[i].number == number) return static_cast<int>(i);
  return -1;
}
inline std::string str(const ir::Expr& e, const ir::BondGraph& g) {
  return e ? ir::to_string(e, ir::model_namer(g)) : std::string("<null>");
}
inline std::vector<std::string> names_of_nodes(const ir::BondGraph& g, const std::vector<int>& nodes) {
  std::vector<std::string> out;
  for (int n : nodes) out.push_back(g.nodes[static_cast<std::size_t>(n)].name);
  return out;
}

// ---- numeric evaluation ----------------------------------------------------------------
struct Env {
  std::map<int, double> vars;
  std::map<int, double> params;
  double t = 0.0;
};

inline double eval(const ir::Expr& e, const Env& env) {
  using ir::Fn;
  using ir::Op;
  auto ev = [&](std::size_t i) { return eval(e->args[i], env); };
  switch (e->op) {
    case Op::Const: return e->value;
    case Op::Param: {
      auto it = env.params.find(e->id);
      if (it == env.params.end()) throw std::out_of_range("eval: parameter " + std::to_string(e->id) + " has no value");
      return it->second;
    }
    case Op::Var: {
      auto it = env.vars.find(e->id);
      if (it == env.vars.end()) throw std::out_of_range("eval: variable " + std::to_string(e->id) + " has no value");
      return it->second;
    }
    case Op::Time: return env.t;
    case Op::Neg: return -ev(0);
    case Op::Add: return ev(0) + ev(1);
    case Op::Sub: return ev(0) - ev(1);
    case Op::Mul: return ev(0) * ev(1);
    case Op::Div: return ev(0) / ev(1);
    case Op::Pow: return std::pow(ev(0), ev(1));
    case Op::Der: throw std::logic_error("eval: der() left in an expression");
    case Op::Call: break;
  }
  const double x = ev(0);
  const double y = e->args.size() > 1 ? ev(1) : 0.0;
  switch (e->fn) {
    case Fn::Sin: return std::sin(x);
    case Fn::Cos: return std::cos(x);
    case Fn::Tan: return std::tan(x);
    case Fn::Asin: return std::asin(x);
    case Fn::Acos: return std::acos(x);
    case Fn::Atan: return std::atan(x);
    case Fn::Atan2: return std::atan2(x, y);
    case Fn::Sinh: return std::sinh(x);
    case Fn::Cosh: return std::cosh(x);
    case Fn::Tanh: return std::tanh(x);
    case Fn::Exp: return std::exp(x);
    case Fn::Log: return std::log(x);
    case Fn::Sqrt: return std::sqrt(x);
    case Fn::Abs: return std::fabs(x);
    case Fn::Sign: return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
    case Fn::Min: return std::fmin(x, y);
    case Fn::Max: return std::fmax(x, y);
    case Fn::Step: return x >= 0 ? 1.0 : 0.0;
    case Fn::Select: return x >= 0 ? 1.0 : 0.0;
    case Fn::Frozen: return x;
  }
  throw std::logic_error("eval: bad function");
}

/// The model's parameter values: each parameter's expression over earlier ones.
inline std::map<int, double> param_values(const std::vector<ir::Parameter>& params) {
  Env env;
  for (std::size_t i = 0; i < params.size(); ++i) env.params[static_cast<int>(i)] = eval(params[i].value, env);
  return env.params;
}
inline std::map<int, double> param_values(const ir::BondGraph& g) { return param_values(g.params); }

/// Evaluates a reduced system's assignments in order at time t, for the given
/// values of states (and, for a DAE, algebraic and yp unknowns) by model name.
/// The returned Env holds every variable computed.
inline Env evaluate(const ir::ReducedSystem& r, const std::map<std::string, double>& known, double t = 0.0) {
  Env env;
  env.t = t;
  env.params = param_values(r.graph);
  for (const auto& [name, value] : known) {
    int id = var_id(r.graph, name);
    if (id < 0) throw std::out_of_range("evaluate: no variable `" + name + "`");
    env.vars[id] = value;
  }
  for (const ir::Assignment& a : r.assignments) {
    if (a.block < 0) {
      env.vars[a.var] = eval(a.value, env);
      continue;
    }
    // A numerically solved block: evaluate A and b, solve by Cramer-free
    // Gauss-Jordan with partial pivoting (independent of mbgrt::solve_linear).
    const ir::LinearBlock& lb = r.linear_blocks[static_cast<std::size_t>(a.block)];
    if (env.vars.count(lb.unknowns[0])) continue;  // solved with an earlier unknown of this block
    std::size_t n = lb.unknowns.size();
    std::vector<std::vector<double>> m(n, std::vector<double>(n + 1));
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) m[i][j] = eval(lb.a[i * n + j], env);
      m[i][n] = eval(lb.b[i], env);
    }
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t p = k;
      for (std::size_t i = k + 1; i < n; ++i)
        if (std::abs(m[i][k]) > std::abs(m[p][k])) p = i;
      std::swap(m[k], m[p]);
      for (std::size_t i = 0; i < n; ++i) {
        if (i == k) continue;
        double f = m[i][k] / m[k][k];
        for (std::size_t j = k; j <= n; ++j) m[i][j] -= f * m[k][j];
      }
    }
    for (std::size_t i = 0; i < n; ++i) env.vars[lb.unknowns[i]] = m[i][n] / m[i][i];
  }
  return env;
}

/// The number N in the reduce log line "alias elimination: N equation(s) ...".
inline int alias_count(const ir::ReducedSystem& r) {
  for (const std::string& line : r.log) {
    int n = -1;
    if (std::sscanf(line.c_str(), "alias elimination: %d", &n) == 1) return n;
  }
  return -1;
}

}  // namespace mbgc_test
