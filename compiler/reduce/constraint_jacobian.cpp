#include "reduce/constraint_jacobian.hpp"

#include "reduce/forward_diff.hpp"

namespace mbgc::reduce {

using namespace mbgc::ir;

std::optional<std::size_t> constraint_jacobian(ReducedSystem& s) {
  s.constraint_jacobian.clear();
  ForwardDiff d(s);
  for (std::size_t r = 0; r < s.constraints.size(); ++r) {
    std::optional<ForwardDiff::Derivatives> row = d.of(s.constraints[r].g);
    if (!row) return r;
    for (auto& [j, value] : *row) s.constraint_jacobian.push_back({static_cast<int>(r), j, std::move(value)});
  }
  return std::nullopt;
}

}  // namespace mbgc::reduce
