// ir/print.hpp — human-readable dumps of each IR (mbgc --dump=...). Stable
// text: golden tests compare it byte for byte.
#pragma once

#include <string>

#include "ir/ast.hpp"
#include "ir/expanded.hpp"
#include "ir/causal.hpp"
#include "ir/equations.hpp"
#include "ir/reduced.hpp"

namespace mbgc::ir {

std::string print_ast(const AstProgram& program);
/// The program after the multibody expansion (mbgc --dump=expanded).
std::string print_expanded(const ExpandedProgram& program);
std::string print_graph(const BondGraph& graph);
/// Graphviz: nodes, bonds as half-arrows (power direction), bond numbers,
/// dimensions, and — once causality is assigned — the causal stroke end.
std::string print_graph_dot(const BondGraph& graph, bool with_causality);
std::string print_causality(const CausalGraph& causal);
std::string print_equations(const EquationSystem& system);
std::string print_reduced(const ReducedSystem& system);

/// Names for dumps: variables and parameters by their model names.
Namer model_namer(const BondGraph& graph);

}  // namespace mbgc::ir
