#include "reduce/forward_diff.hpp"

#include <algorithm>
#include <unordered_set>
#include <vector>

namespace mbgc::reduce {

using namespace mbgc::ir;

ForwardDiff::ForwardDiff(const ReducedSystem& s) {
  for (std::size_t j = 0; j < s.states.size(); ++j) state_index_[s.states[j].var] = static_cast<int>(j);
  for (const Assignment& a : s.assignments) assignment_of_[a.var] = &a;
}

std::optional<ForwardDiff::Derivatives> ForwardDiff::of(const Expr& e) {
  Derivatives d;
  std::unordered_set<int> vars;
  collect_vars(e, vars);
  std::vector<int> sorted(vars.begin(), vars.end());
  std::sort(sorted.begin(), sorted.end());  // deterministic term order
  for (int u : sorted) {
    const Derivatives* du = of_var(u);
    if (!du) return std::nullopt;
    Expr partial;
    for (const auto& [j, duj] : *du) {
      if (!partial) partial = diff_var(e, u);
      auto [it, fresh] = d.try_emplace(j, constant(0));
      it->second = add(it->second, mul(partial, duj));
    }
  }
  std::erase_if(d, [](const auto& entry) { return is_zero(entry.second); });
  return d;
}

const ForwardDiff::Derivatives* ForwardDiff::of_var(int id) {
  if (auto it = memo_.find(id); it != memo_.end()) return it->second ? &*it->second : nullptr;
  std::optional<Derivatives> d = Derivatives{};
  if (auto s = state_index_.find(id); s != state_index_.end()) (*d)[s->second] = constant(1);
  else if (auto a = assignment_of_.find(id); a != assignment_of_.end())
    d = a->second->block >= 0 ? std::nullopt : of(a->second->value);
  // (anything else - a discrete variable, an input - does not depend on the states)
  auto& slot = memo_[id];
  slot = std::move(d);
  return slot ? &*slot : nullptr;
}

}  // namespace mbgc::reduce
