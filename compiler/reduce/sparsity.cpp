#include "reduce/sparsity.hpp"

#include <algorithm>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace mbgc::reduce {

using namespace mbgc::ir;

namespace {

/// Per variable, the columns it reads (sorted); a variable without an entry
/// reads none.
using Columns = std::unordered_map<int, std::vector<int>>;

void merge(std::vector<int>& into, const std::vector<int>& from) {
  std::vector<int> out;
  out.reserve(into.size() + from.size());
  std::set_union(into.begin(), into.end(), from.begin(), from.end(), std::back_inserter(out));
  into.swap(out);
}

std::vector<int> columns_of(const Columns& columns, const std::unordered_set<int>& vars) {
  std::vector<int> out;
  for (int v : vars)
    if (auto it = columns.find(v); it != columns.end()) merge(out, it->second);
  return out;
}

bool block_depends_on_time(const LinearBlock& block) {
  return std::any_of(block.a.begin(), block.a.end(), [](const Expr& e) { return depends_on_time(e); }) ||
         std::any_of(block.b.begin(), block.b.end(), [](const Expr& e) { return depends_on_time(e); });
}

/// Carries `columns` through the assignments in `order`: each one reads what
/// its inputs read (a linear block's unknowns, all of the block's inputs),
/// and `time_column` where it reads t itself (none when it is absent).
void carry(const ReducedSystem& s, const std::vector<int>& order, Columns& columns,
           std::optional<int> time_column = std::nullopt) {
  std::unordered_set<int> blocks_done;
  for (int i : order) {
    const Assignment& a = s.assignments[static_cast<std::size_t>(i)];
    if (a.block >= 0 && !blocks_done.insert(a.block).second) continue;
    std::unordered_set<int> inputs;
    assignment_inputs(s, a, inputs);
    std::vector<int> cols = columns_of(columns, inputs);
    if (time_column) {
      const bool timed = a.block < 0 ? depends_on_time(a.value)
                                     : block_depends_on_time(s.linear_blocks[static_cast<std::size_t>(a.block)]);
      if (timed) merge(cols, {*time_column});
    }
    if (a.block < 0) {
      columns[a.var] = cols;
      continue;
    }
    for (int u : s.linear_blocks[static_cast<std::size_t>(a.block)].unknowns) columns[u] = cols;
  }
}

}  // namespace

void residual_sparsity(ReducedSystem& s) {
  s.residual_pattern.clear();
  if (!s.dae) return;
  const std::size_t n = s.states.size() + s.algebraic.size();
  // the columns a variable stands for: y_k (states, then algebraic) or y'_k
  Columns columns;
  for (std::size_t i = 0; i < s.states.size(); ++i) columns[s.states[i].var].push_back(static_cast<int>(i));
  for (std::size_t j = 0; j < s.algebraic.size(); ++j)
    columns[s.algebraic[j]].push_back(static_cast<int>(s.states.size() + j));
  for (std::size_t i = 0; i < s.derivative_unknowns.size(); ++i)
    if (s.derivative_unknowns[i] >= 0) columns[s.derivative_unknowns[i]].push_back(static_cast<int>(i));
  for (auto& [var, cols] : columns) std::sort(cols.begin(), cols.end());  // every list stays sorted from here
  carry(s, s.for_derivative, columns);
  s.residual_pattern.assign(n, {});
  for (std::size_t r = 0; r < s.residuals.size(); ++r) {
    std::unordered_set<int> vars;
    collect_vars(s.residuals[r].value, vars);
    for (int c : columns_of(columns, vars)) s.residual_pattern[static_cast<std::size_t>(c)].push_back(static_cast<int>(r));
  }
}

std::vector<StateReads> state_reads(const ReducedSystem& s, const std::vector<Expr>& values) {
  constexpr int kTime = -1;  // sorts before every state
  Columns columns;
  for (std::size_t i = 0; i < s.states.size(); ++i) columns[s.states[i].var] = {static_cast<int>(i)};
  std::vector<int> every(s.assignments.size());
  for (std::size_t i = 0; i < every.size(); ++i) every[i] = static_cast<int>(i);
  // Once through the assignments in their order, then again until nothing
  // changes: a second pass that finds nothing new confirms the order.
  for (Columns before; before != columns;) {
    before = columns;
    carry(s, every, columns, kTime);
  }
  std::vector<StateReads> out;
  out.reserve(values.size());
  for (const Expr& value : values) {
    std::unordered_set<int> vars;
    collect_vars(value, vars);
    std::vector<int> cols = columns_of(columns, vars);
    StateReads r;
    r.time = depends_on_time(value) || (!cols.empty() && cols.front() == kTime);
    r.states.assign(cols.begin() + (!cols.empty() && cols.front() == kTime ? 1 : 0), cols.end());
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace mbgc::reduce
