#include "ir/expanded.hpp"

#include <type_traits>

namespace mbgc::ir {

ExpandedElement as_expanded(const AstElement& e) {
  ExpandedElement out;
  out.kind = e.kind;
  out.kind_loc = e.kind_loc;
  out.name = e.name;
  out.loc = e.loc;
  out.value = to_term(e.value);
  for (const AstAttr& a : e.attrs) out.attrs.push_back({a.key, a.loc, to_term(a.value)});
  return out;
}

bool as_expanded(const AstStmt& s, ExpandedStmt& out) {
  return std::visit(
      [&](const auto& st) {
        using T = std::decay_t<decltype(st)>;
        if constexpr (std::is_same_v<T, AstParam>)
          out = ExpandedParam{st.name, st.loc, to_term(st.value), st.unit, false, false, std::nullopt};
        else if constexpr (std::is_same_v<T, AstSignal>)
          out = ExpandedSignal{st.name, st.loc, to_term(st.value), st.unit, nullptr, false};
        else if constexpr (std::is_same_v<T, AstOutput>)
          out = ExpandedOutput{st.name, st.loc, to_term(st.value), st.unit, nullptr, nullptr};
        else if constexpr (std::is_same_v<T, AstElement>) out = as_expanded(st);
        else if constexpr (std::is_same_v<T, AstJunction>) {
          ExpandedJunction j{{st.type, st.kind_loc, st.name, st.loc, st.dim, st.dim_loc, {}, {}}, {}, false, -1};
          for (const AstEndpoint& e : st.inputs) j.inputs.push_back({e, -1, 0});
          for (const AstEndpoint& e : st.outputs) j.outputs.push_back({e, -1, 0});
          out = std::move(j);
        } else if constexpr (std::is_same_v<T, AstBond>)
          out = ExpandedBond{{st.name, st.loc, {st.from, -1, 0}, {st.to, -1, 0}, st.dim, st.dim_loc}, -1};
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
