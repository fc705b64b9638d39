// codegen/derived_constants.cpp — see derived_constants.hpp.
#include "codegen/derived_constants.hpp"

#include <fmt/format.h>
#include <functional>
#include <unordered_map>
#include <unordered_set>

namespace mbgc::codegen {

using namespace mbgc::ir;

void find_derived_constants(const ReducedSystem& s, ExprNames& names, std::vector<Expr>& order) {
  // Expressions are DAGs (derivatives and torn loops share sub-trees):
  // every walk here remembers the nodes it has seen.
  std::unordered_map<const Node*, bool> param_memo, costly_memo;
  std::function<bool(const Expr&)> param_only = [&](const Expr& e) {
    if (auto it = param_memo.find(e.get()); it != param_memo.end()) return it->second;
    bool r = !(e->op == Op::Var || e->op == Op::Time || e->op == Op::Der);
    for (const Expr& a : e->args)
      if (r && !param_only(a)) r = false;
    return param_memo[e.get()] = r;
  };
  // Only what costs something at run time (a division, a power, a function
  // call) is worth a member: -m * g reads better where it is used.
  std::function<bool(const Expr&)> costly = [&](const Expr& e) {
    if (auto it = costly_memo.find(e.get()); it != costly_memo.end()) return it->second;
    bool r = e->op == Op::Div || e->op == Op::Pow || e->op == Op::Call;
    for (const Expr& a : e->args)
      if (!r && costly(a)) r = true;
    return costly_memo[e.get()] = r;
  };
  std::unordered_set<const Node*> scanned;
  std::function<void(const Expr&)> scan = [&](const Expr& e) {
    if (!scanned.insert(e.get()).second) return;
    bool trivial = e->args.empty() || (e->op == Op::Neg && e->args[0]->args.empty());
    if (!trivial && param_only(e) && costly(e)) {
      if (!names.count(e)) {
        names[e] = fmt::format("derived{}_", order.size() + 1);
        order.push_back(e);
      }
      return;
    }
    for (const Expr& a : e->args) scan(a);
  };
  for (const Assignment& a : s.assignments) {
    if (a.block < 0) scan(a.value);
  }
  for (const LinearBlock& lb : s.linear_blocks) {
    for (const Expr& e : lb.a) scan(e);
    for (const Expr& e : lb.b) scan(e);
  }
  for (const Expr& e : s.state_derivative) scan(e);
  for (const Expr& e : s.jacobian) scan(e);
  for (const Residual& r : s.residuals) scan(r.value);
  for (const Output& o : s.graph.outputs) scan(o.value);
}

}  // namespace mbgc::codegen
