#include "ir/expanded.hpp"

#include <type_traits>

namespace mbgc::ir {

bool as_expanded(const AstStmt& s, ExpandedStmt& out) {
  return std::visit(
      [&](const auto& st) {
        using T = std::decay_t<decltype(st)>;
        if constexpr (std::is_same_v<T, AstParam>) out = ExpandedParam{st, false, false};
        else if constexpr (std::is_same_v<T, AstSignal>) out = ExpandedSignal{st, nullptr, false};
        else if constexpr (std::is_same_v<T, AstOutput>) out = ExpandedOutput{st, nullptr, nullptr};
        else if constexpr (std::is_same_v<T, AstElement>) out = as_expanded(st);
        else if constexpr (std::is_same_v<T, AstJunction>) out = ExpandedJunction{st, {}, false};
        else if constexpr (std::is_constructible_v<ExpandedStmt, T>) out = st;
        else return false;
        return true;
      },
      s);
}

ExpandedProgram as_expanded(const AstProgram& program) {
  ExpandedProgram out;
  for (const AstStmt& s : program.stmts) {
    ExpandedStmt e;
    if (as_expanded(s, e)) out.stmts.push_back(std::move(e));
  }
  return out;
}

}  // namespace mbgc::ir
