#include "codegen/shared_values.hpp"

#include <algorithm>
#include <iterator>
#include <set>

namespace mbgc::codegen {

using namespace mbgc::ir;

SharedValues find_shared_values(const ReducedSystem& s, const std::vector<const std::vector<int>*>& slices,
                                const std::vector<Expr>& results, Sharing sharing) {
  // The assignments every slice has, or any (a slice's indices ascend, so do
  // their intersection and union; each slice is closed under what its
  // assignments read, so are they).
  SharedValues out;
  if (slices.empty()) return out;
  out.assignments = *slices.front();
  for (std::size_t k = 1; k < slices.size(); ++k) {
    std::vector<int> both;
    if (sharing == Sharing::common)
      std::set_intersection(out.assignments.begin(), out.assignments.end(), slices[k]->begin(), slices[k]->end(),
                            std::back_inserter(both));
    else
      std::set_union(out.assignments.begin(), out.assignments.end(), slices[k]->begin(), slices[k]->end(),
                     std::back_inserter(both));
    out.assignments = std::move(both);
  }
  std::unordered_set<int> defined;
  for (int i : out.assignments) defined.insert(s.assignments[static_cast<std::size_t>(i)].var);
  // what the results and each method's own remaining assignments read of them
  std::unordered_set<int> read;
  collect_vars(results, read);
  const std::set<int> shared(out.assignments.begin(), out.assignments.end());
  for (const std::vector<int>* slice : slices)
    for (int i : *slice)
      if (!shared.count(i)) assignment_inputs(s, s.assignments[static_cast<std::size_t>(i)], read);
  for (int v : read)
    if (defined.count(v)) out.exported.insert(v);
  return out;
}

std::vector<int> SharedValues::rest_of(const std::vector<int>& slice) const {
  std::vector<int> rest;
  std::set_difference(slice.begin(), slice.end(), assignments.begin(), assignments.end(), std::back_inserter(rest));
  return rest;
}

}  // namespace mbgc::codegen
