#include "codegen/shared_values.hpp"

#include <algorithm>
#include <set>

namespace mbgc::codegen {

using namespace mbgc::ir;

SharedValues find_shared_values(const ReducedSystem& s, const std::vector<const std::vector<int>*>& slices,
                                const std::vector<Expr>& results) {
  // The assignments are sorted: a slice's indices ascend, and so does their union.
  std::set<int> all;
  for (const std::vector<int>* slice : slices) all.insert(slice->begin(), slice->end());
  SharedValues out;
  out.assignments.assign(all.begin(), all.end());
  std::unordered_set<int> defined;
  for (int i : out.assignments) defined.insert(s.assignments[static_cast<std::size_t>(i)].var);
  std::unordered_set<int> read;
  collect_vars(results, read);
  for (int v : read)
    if (defined.count(v)) out.exported.insert(v);
  return out;
}

}  // namespace mbgc::codegen
