#include "reduce/nominal.hpp"

#include <algorithm>
#include <unordered_map>

namespace mbgc::reduce {

using namespace mbgc::ir;

void nominal_values(ReducedSystem& s) {
  s.nominal.clear();
  // A flexible body's mass matrix depends on its modal coordinates: its
  // nominal is the matrix at the initial state.
  std::unordered_map<int, Expr> initial;
  for (const StateVar& st : s.states) initial[st.var] = st.initial;
  auto at_start = [&](const Expr& e) -> Expr {
    bool other = false;
    Expr r = rewrite(e, [&](const Expr& x) -> Expr {
      if (x->op != Op::Var) return nullptr;
      if (auto it = initial.find(x->id); it != initial.end()) return it->second;
      other = true;
      return nullptr;
    });
    return other ? constant(1) : call(Fn::Abs, {r});
  };
  for (const StateVar& st : s.states) {
    const GraphNode& nd = s.graph.nodes[static_cast<std::size_t>(st.node)];
    const auto& vars = nd.state_vars;
    const auto k = static_cast<int>(std::find(vars.begin(), vars.end(), st.var) - vars.begin());
    Expr nominal = constant(1);
    if (nd.kind == NodeKind::I && nd.law == LawForm::Linear && k < nd.dim) {
      // one size for the element (a body): its largest diagonal entry, so that
      // a slender body's spin about its axis is not held tighter than its
      // translation (the crank-rocker's coupler, 0.012 kg m^2 beside 0.5 kg,
      // then failed IDA's Newton test on rounding noise in that momentum)
      Expr largest;
      for (int j = 0; j < (nd.value.is_scalar() ? 1 : nd.dim); ++j) {
        const Expr d = at_start(nd.value.is_scalar() ? nd.value.items[0] : nd.value.at(j, j));
        largest = largest ? call(Fn::Max, {largest, d}) : d;
      }
      nominal = largest;
    }
    else if (nd.kind == NodeKind::C && static_cast<std::size_t>(k) < nd.state_limits.size())
      nominal = constant(nd.state_limits[static_cast<std::size_t>(k)].first);
    s.nominal.push_back(nominal);
  }
}

}  // namespace mbgc::reduce
