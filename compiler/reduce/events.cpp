// reduce/events.cpp — see events.hpp.
#include "reduce/events.hpp"

#include <fmt/format.h>

#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace mbgc::reduce {

using namespace mbgc::ir;

namespace {

bool reads_variable(const Expr& x) {
  std::unordered_set<int> vars;
  collect_vars(x, vars);
  return !vars.empty();
}
/// x a function of time alone (t - t0, t0 - t, ...): its crossings are known before the run.
bool time_only(const Expr& x) { return depends_on_time(x) && !reads_variable(x); }

class Finder {
 public:
  explicit Finder(std::vector<EventRelation>& out) : out_(out) {}

  /// The steps in e, found first in an equation from `loc` (`origin`).
  void scan(const Expr& e, const SourceLoc& loc = {}, const std::string& origin = {}) {
    if (!e) return;
    std::vector<const Node*> stack{e.get()};
    while (!stack.empty()) {
      const Node* n = stack.back();
      stack.pop_back();
      if (!seen_.insert(n).second) continue;
      const Expr& x = n->args[0];
      if (n->op == Op::Call && n->fn == Fn::Step && (depends_on_time(x) || reads_variable(x))) {
        out_.push_back({Expr(n), x, time_only(x), loc, origin});
        continue;  // a step inside the argument of a step: its mode decides only where the outer one is
      }
      for (const Expr& a : n->args) stack.push_back(a.get());
    }
  }

 private:
  std::vector<EventRelation>& out_;
  std::unordered_set<const Node*> seen_;
};

/// min/max of arguments whose difference is a function of time alone, as steps.
class TimeKinks {
 public:
  Expr operator()(const Expr& e) {
    if (!e || !depends_on_time(e)) return e;
    if (auto it = memo_.find(e.get()); it != memo_.end()) return it->second.second;
    std::vector<Expr> args;
    for (const Expr& a : e->args) args.push_back((*this)(a));
    Expr r = with_operands(e, std::move(args));
    if (r->op == Op::Call && (r->fn == Fn::Min || r->fn == Fn::Max)) {
      const Expr &a = r->args[0], &b = r->args[1];
      const Expr d = sub(a, b);
      if (time_only(d)) {
        const Expr h = call(Fn::Step, {d});
        r = r->fn == Fn::Min ? add(a, mul(sub(b, a), h)) : add(b, mul(d, h));
      }
    }
    memo_.emplace(e.get(), std::make_pair(e, r));  // the key kept alive: no new node reuses its address
    return r;
  }

 private:
  std::unordered_map<const Node*, std::pair<Expr, Expr>> memo_;
};

}  // namespace

void steps_for_time_kinks(ReducedSystem& s) {
  TimeKinks f;
  for (Assignment& a : s.assignments) a.value = f(a.value);
  for (LinearBlock& lb : s.linear_blocks) {
    for (Expr& e : lb.a) e = f(e);
    for (Expr& e : lb.b) e = f(e);
  }
  for (Expr& e : s.state_derivative) e = f(e);
  for (Expr& e : s.jacobian) e = f(e);
  for (Residual& r : s.residuals) r.value = f(r.value);
  for (Output& o : s.graph.outputs) o.value = f(o.value);
  for (DrawnBody& d : s.graph.drawings) d.for_each_expr([&](Expr& e) { e = f(e); });
  for (ConstraintRow& row : s.constraints) {
    row.g = f(row.g);
    row.gdot = f(row.gdot);
  }
  for (ContactRow& c : s.contacts) {
    c.gap = f(c.gap);
    c.rate = f(c.rate);
    for (Expr& x : c.tangent_rate)
      if (x) x = f(x);
  }
}

std::vector<EventRelation> find_events(const ReducedSystem& s) {
  std::vector<EventRelation> events;
  Finder f(events);
  for (const Assignment& a : s.assignments) f.scan(a.value, a.loc, a.origin);
  for (const LinearBlock& lb : s.linear_blocks) {
    for (const Expr& e : lb.a) f.scan(e);
    for (const Expr& e : lb.b) f.scan(e);
  }
  for (const Expr& e : s.state_derivative) f.scan(e);
  for (const Residual& r : s.residuals) f.scan(r.value, r.loc, r.origin);
  for (const Output& o : s.graph.outputs) f.scan(o.value, o.loc, "output " + o.name);
  for (const ConstraintRow& row : s.constraints) {
    f.scan(row.g);
    f.scan(row.gdot);
  }
  for (std::size_t c = 0; c < s.contacts.size(); ++c) {
    const ContactRow& row = s.contacts[c];
    const Expr closed = var(row.closed);
    // a unilateral contact while closed: its normal force, which must not pull
    const Expr arg = row.compliant ? row.gap
                                   : add(mul(closed, row.normal_force), mul(sub(constant(1), closed), row.gap));
    const std::string element = row.name.substr(0, row.name.rfind('.'));
    events.push_back({closed, arg, false, row.loc, fmt::format("contact {}", element), static_cast<int>(c)});
    if (!row.friction) continue;
    // Its friction: while stuck, mu push - |friction| (sliding starts where it
    // falls through 0); while sliding, the sliding speed along its direction
    // (it sticks where that falls through 0); while open, 1 (nothing happens).
    const Expr stick = var(row.stick);
    const Expr& f1 = row.tangent_force[0];
    const Expr& f2 = row.tangent_force[1];
    const Expr margin = sub(mul(row.friction, row.normal_force), call(Fn::Sqrt, {add(mul(f1, f1), mul(f2, f2))}));
    const Expr along = add(mul(row.tangent_rate[0], var(row.slip1)), mul(row.tangent_rate[1], var(row.slip2)));
    const Expr friction = add(mul(stick, margin), mul(sub(constant(1), stick), along));
    const Expr friction_arg = add(mul(closed, friction), sub(constant(1), closed));
    events.push_back({stick, friction_arg, false, row.loc, fmt::format("friction {}", element), static_cast<int>(c), true});
  }
  return events;
}

}  // namespace mbgc::reduce
