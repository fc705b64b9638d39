// multibody/rewrite.hpp — the quantities user expressions name, replaced by
// their definitions (`bob.position` -> the body's position expression). In:
// the Quantities table (read only), the Model (which owners are bodies and
// joints, and a body's points) and the diagnostics, where a name under a body
// or joint that is none of its quantities, points or generated parts is an
// error. Out: the rewritten expressions and statements, and the names of the
// quantities they read (used(), whose units the units pass states).
//
// The Expander rewrites a joint's drive loads and a force element's laws as it
// writes them, against the quantities defined so far; rewrite_user_statements
// then rewrites the user's own statements against the finished table.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/expanded.hpp"
#include "multibody/build.hpp"
#include "multibody/model.hpp"
#include "multibody/quantities.hpp"

namespace mbgc::multibody::detail {

class QuantityRewriter {
 public:
  QuantityRewriter(const Quantities& quantities, const Model& m, ir::Diagnostics& diags);

  /// `e` with every quantity it names replaced by its definition (`e` itself if it names none).
  E expr(const E& e);
  /// A user's statement with its values rewritten (signals, outputs, elements and their settings).
  ir::ExpandedStmt statement(const ir::ExpandedStmt& s);
  /// The quantities rewritten so far.
  const std::set<std::string>& used() const { return used_; }

 private:
  void check_known(const ir::Term& e);

  const Quantities& quantities_;
  const Model& m_;
  ir::Diagnostics& diags_;
  std::set<std::string> joints_;  // the joints' names
  std::set<std::string> used_;
};

/// The user's statements of `program` as layer-1 statements, rewritten by `rewrite`, in order.
std::vector<ir::ExpandedStmt> rewrite_user_statements(const ir::AstProgram& program, QuantityRewriter& rewrite);

}  // namespace mbgc::multibody::detail
