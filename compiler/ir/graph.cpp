#include "ir/graph.hpp"

namespace mbgc::ir {
const char* node_kind_name(NodeKind k) {
  switch (k) {
    case NodeKind::Se: return "Se";
    case NodeKind::Sf: return "Sf";
    case NodeKind::I: return "I";
    case NodeKind::C: return "C";
    case NodeKind::R: return "R";
    case NodeKind::TF: return "TF";
    case NodeKind::GY: return "GY";
    case NodeKind::MTF: return "MTF";
    case NodeKind::MGY: return "MGY";
    case NodeKind::Zero: return "0";
    case NodeKind::One: return "1";
    case NodeKind::CN: return "CN";
  }
  return "?";
}

int flow_sign(const BondGraph& g, int n, int b) {
  const GraphNode& node = g.nodes[static_cast<std::size_t>(n)];
  const Bond& bond = g.bonds[static_cast<std::size_t>(b)];
  bool into = bond.to == n;
  if (is_two_port(node.kind)) {
    bool port1 = !node.bonds.empty() && node.bonds[0] == b;
    return into == port1 ? 1 : -1;
  }
  bool source = node.kind == NodeKind::Se || node.kind == NodeKind::Sf;
  return into != source ? 1 : -1;
}
}  // namespace mbgc::ir
