#include "reduce/sparsity.hpp"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

namespace mbgc::reduce {

using namespace mbgc::ir;

void residual_sparsity(ReducedSystem& s) {
  s.residual_pattern.clear();
  if (!s.dae) return;
  const std::size_t n = s.states.size() + s.algebraic.size();
  // the columns a variable stands for: y_k (states, then algebraic) or y'_k
  std::unordered_map<int, std::vector<int>> columns;
  for (std::size_t i = 0; i < s.states.size(); ++i) columns[s.states[i].var].push_back(static_cast<int>(i));
  for (std::size_t j = 0; j < s.algebraic.size(); ++j)
    columns[s.algebraic[j]].push_back(static_cast<int>(s.states.size() + j));
  for (std::size_t i = 0; i < s.derivative_unknowns.size(); ++i)
    if (s.derivative_unknowns[i] >= 0) columns[s.derivative_unknowns[i]].push_back(static_cast<int>(i));
  for (auto& [var, cols] : columns) std::sort(cols.begin(), cols.end());  // every list stays sorted from here
  const auto merge = [](std::vector<int>& into, const std::vector<int>& from) {
    std::vector<int> out;
    out.reserve(into.size() + from.size());
    std::set_union(into.begin(), into.end(), from.begin(), from.end(), std::back_inserter(out));
    into.swap(out);
  };
  const auto columns_of = [&](const std::unordered_set<int>& vars) {
    std::vector<int> out;
    for (int v : vars)
      if (auto it = columns.find(v); it != columns.end()) merge(out, it->second);
    return out;
  };
  // Assignments in evaluation order: each one's columns are its inputs'.
  std::unordered_set<int> blocks_done;
  for (int i : s.for_derivative) {
    const Assignment& a = s.assignments[static_cast<std::size_t>(i)];
    if (a.block >= 0 && !blocks_done.insert(a.block).second) continue;
    std::unordered_set<int> inputs;
    assignment_inputs(s, a, inputs);
    const std::vector<int> cols = columns_of(inputs);
    if (a.block < 0) {
      columns[a.var] = cols;
      continue;
    }
    for (int u : s.linear_blocks[static_cast<std::size_t>(a.block)].unknowns) columns[u] = cols;
  }
  s.residual_pattern.assign(n, {});
  for (std::size_t r = 0; r < s.residuals.size(); ++r) {
    std::unordered_set<int> vars;
    collect_vars(s.residuals[r].value, vars);
    for (int c : columns_of(vars)) s.residual_pattern[static_cast<std::size_t>(c)].push_back(static_cast<int>(r));
  }
}

}  // namespace mbgc::reduce
