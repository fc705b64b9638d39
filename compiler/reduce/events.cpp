// reduce/events.cpp — see events.hpp.
#include "reduce/events.hpp"

#include <unordered_set>

namespace mbgc::reduce {

using namespace mbgc::ir;

namespace {

class Finder {
 public:
  explicit Finder(std::vector<EventRelation>& out) : out_(out) {}

  void scan(const Expr& e) {
    if (!e) return;
    std::vector<const Node*> stack{e.get()};
    while (!stack.empty()) {
      const Node* n = stack.back();
      stack.pop_back();
      if (!seen_.insert(n).second) continue;
      if (n->op == Op::Call && n->fn == Fn::Step && changes(n->args[0])) {
        out_.push_back({Expr(n), n->args[0], is_time_event(n->args[0])});
        continue;  // a step inside the argument of a step: its mode decides only where the outer one is
      }
      for (const Expr& a : n->args) stack.push_back(a.get());
    }
  }

 private:
  static bool changes(const Expr& x) {
    std::unordered_set<int> vars;
    collect_vars(x, vars);
    return !vars.empty() || depends_on_time(x);
  }
  /// x = t - t0 (or any x whose rate is 1 and that reads no variable).
  static bool is_time_event(const Expr& x) {
    std::unordered_set<int> vars;
    collect_vars(x, vars);
    return vars.empty() && is_one(diff_time(x));
  }

  std::vector<EventRelation>& out_;
  std::unordered_set<const Node*> seen_;
};

}  // namespace

std::vector<EventRelation> find_events(const ReducedSystem& s) {
  std::vector<EventRelation> events;
  Finder f(events);
  for (const Assignment& a : s.assignments) f.scan(a.value);
  for (const LinearBlock& lb : s.linear_blocks) {
    for (const Expr& e : lb.a) f.scan(e);
    for (const Expr& e : lb.b) f.scan(e);
  }
  for (const Expr& e : s.state_derivative) f.scan(e);
  for (const Residual& r : s.residuals) f.scan(r.value);
  for (const Output& o : s.graph.outputs) f.scan(o.value);
  for (const ConstraintRow& row : s.constraints) {
    f.scan(row.g);
    f.scan(row.gdot);
  }
  return events;
}

}  // namespace mbgc::reduce
