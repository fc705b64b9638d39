// graph/build_graph.hpp — pass 3: resolved model -> multibond graph.
//
// Attaches bonds to element ports, infers every multibond's dimension (from
// element shapes, junctions and declared [n]; a conflict is an error), creates
// the scalar variables (efforts, flows, states, signals) and lowers element
// laws, signals and outputs to expressions over them.
#pragma once

#include "ir/diagnostics.hpp"
#include "ir/graph.hpp"
#include "ir/resolved.hpp"

namespace mbgc::graph {

ir::BondGraph build_graph(const ir::ResolvedModel& model, const ir::SourceManager& sources,
                          ir::Diagnostics& diags);

}  // namespace mbgc::graph
