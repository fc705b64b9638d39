// codegen/shared_temps.hpp — common subexpressions of one generated function.
//
// Every non-trivial subexpression that the function's expressions use more
// than once is defined once, as `const double cseN = ...;`, right before its
// first use, innermost first. Names known before the function starts (the
// derived constants, members computed in initial()) are printed as they are.
#pragma once

#include <functional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "codegen/cpp.hpp"
#include "ir/expr.hpp"

namespace mbgc::codegen {

using ExprNames = std::unordered_map<ir::Expr, std::string, ir::ExprHash, ir::ExprEqual>;

class SharedTemps {
 public:
  /// `names` prints variables and parameters; `counter` numbers the cseN
  /// names (shared by the functions of one file, so that each name is unique);
  /// `ops` is where the printed operations are counted.
  SharedTemps(const ExprNames& known, const ir::Namer& names, int& counter, ir::CppOps* ops)
      : known_(known), names_(names), counter_(counter), ops_(ops), temp(known.begin(), known.end()) {}

  /// First pass: every expression the function will print.
  void count(const ir::Expr& e);
  void finish_counting();

  /// `e` in C++, after defining (into `body`) the shared temporaries it needs.
  std::string print(const ir::Expr& e, std::vector<CppStmt>& body);

  /// An assignment whose whole value recurs: it becomes the shared name itself
  /// (`hub_f = hub_p / J_hub`, reused, rather than a cseN copy). Call before
  /// print(e), then name_whole(e, name) after its definition.
  bool take_whole(const ir::Expr& e);
  /// The same without asking whether e is named already (a derived constant
  /// always gets its member's name).
  bool take_pending(const ir::Expr& e) { return pending_.erase(e) > 0; }
  void name_whole(const ir::Expr& e, const std::string& name) { temp[e] = name; }

 private:
  std::string print_with_temps(const ir::Expr& e, bool top);

  const ExprNames& known_;
  const ir::Namer& names_;
  int& counter_;
  ir::CppOps* ops_;
  std::unordered_map<ir::Expr, int, ir::ExprHash, ir::ExprEqual> uses_;
  std::unordered_set<ir::Expr, ir::ExprHash, ir::ExprEqual> pending_;
  bool announced_ = false;  // the note on cseN names is printed

 public:
  ExprNames temp;  // every name defined so far (the known ones included)
};

}  // namespace mbgc::codegen
