// reduce/row_facts.hpp — what a tree's joint rows say of the loop's solution,
// read before the loop is eliminated (reduce/tree_elimination uses it).
//
// A joint's rows (the tears' residuals) are its free directions' efforts set
// to what the joint's elements give them. Where a direction is free with
// nothing on it, the row is one effort alone: that effort is zero once the
// loop is solved, and so is every unknown that is a combination of such
// efforts only (a ball joint passes no torque to its parent). Where a row
// reads two efforts, a v1 + b v2 = 0 (a universal joint: the torque across
// its first axis, cos(beta) t1 + sin(beta) t2), they are confined to one
// direction, (v1, v2) = (-b, a) mu, and whatever reads only them is a
// multiple of mu. Both are exact.
#pragma once

#include <cstddef>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "ir/expr.hpp"
#include "reduce/tree_elimination.hpp"

namespace mbgc::reduce {

class RowFacts {
 public:
  /// refs: each unknown of the loop -> the loop's unknowns its equation
  /// reads; body: each unknown -> its body (negative: none, or
  /// `global_body` for what only the cut joints' rows read); the cut
  /// joints' multipliers have no rows of this kind.
  RowFacts(const TornLoop& loop, const std::unordered_map<int, std::vector<int>>& refs,
           const std::unordered_map<int, int>& body, const std::unordered_set<int>& multipliers, int global_body);

  /// Does unknown u vanish at the solution?
  bool zero(int u) const { return zero_.count(u) > 0; }
  /// e with the unknowns that vanish at the solution set to 0.
  ir::Expr without_zeros(const ir::Expr& e) { return zero_values_(e); }

  /// a v1 + b v2 = 0 at the solution, v1 and v2 unknowns of one body.
  struct Pair {
    int body, v1, v2;
    ir::Expr a, b;
  };
  const Pair& pair(std::size_t k) const { return pairs_[k]; }
  /// If unknown y (not a tear) reads nothing but one pair's two unknowns
  /// (and zeros): that pair, and the multiple of its mu that y is.
  std::optional<std::pair<std::size_t, ir::Expr>> multiple_of_pair(int y) const;

 private:
  void find_zeros();
  void find_pairs();
  bool is_tear(int u) const { return tears_.count(u) > 0; }

  const TornLoop& loop_;
  const std::unordered_map<int, std::vector<int>>& refs_;
  const std::unordered_map<int, int>& body_;
  const std::unordered_set<int>& multipliers_;
  const int global_body_;
  std::unordered_set<int> tears_;
  std::unordered_set<int> zero_;
  ir::Substitution zero_values_{{}};  // each zero -> 0
  std::vector<Pair> pairs_;
  std::unordered_map<int, std::size_t> paired_;  // v1 or v2 -> its pair
};

}  // namespace mbgc::reduce
