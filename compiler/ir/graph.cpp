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
  }
  return "?";
}
}  // namespace mbgc::ir
