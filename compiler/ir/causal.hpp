// ir/causal.hpp — the graph after causality assignment, with the SCAP report.
#pragma once

#include <string>
#include <vector>

#include "ir/graph.hpp"

namespace mbgc::ir {

struct CausalityReport {
  std::vector<int> integral;     // storage nodes in integral causality (their states are states)
  std::vector<int> derivative;   // storage nodes in derivative causality
  std::vector<int> chosen;       // bonds whose causality was an arbitrary choice (SCAP steps 3-4)
  std::vector<std::string> steps;  // the SCAP log, one line per decision, for --dump=causality
};

struct CausalGraph {
  BondGraph graph;               // bonds carry effort_setter
  CausalityReport report;
};

/// True if node `n` computes the effort on bond `b` (the causal stroke is at the other end).
inline bool sets_effort(const BondGraph& g, int n, int b) {
  return g.bonds[static_cast<std::size_t>(b)].effort_setter == n;
}
/// The other end of bond b as seen from node n.
inline int other_end(const BondGraph& g, int n, int b) {
  const Bond& bond = g.bonds[static_cast<std::size_t>(b)];
  return bond.from == n ? bond.to : bond.from;
}

}  // namespace mbgc::ir
