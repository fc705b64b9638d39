// multibody/rewrite.cpp — the quantities user expressions name, replaced by their definitions.
#include "multibody/rewrite.hpp"

#include <memory>
#include <type_traits>
#include <variant>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

QuantityRewriter::QuantityRewriter(const Quantities& quantities, const Model& m, ir::Diagnostics& diags)
    : quantities_(quantities), m_(m), diags_(diags) {
  for (const Joint& j : m.joints) joints_.insert(j.decl->name);
}

/// `bob.positon`: a name under a body or joint that is none of its quantities,
/// points or generated parts is a typo; say what the body or joint offers.
void QuantityRewriter::check_known(const ir::Term& e) {
  std::size_t dot = e.name.find('.');
  if (dot == std::string::npos) return;
  const std::string owner = e.name.substr(0, dot);
  const bool is_body = owner != "ground" && m_.bodies.count(owner);
  const bool is_joint = joints_.count(owner) > 0;
  if (!is_body && !is_joint) return;
  if (quantities_.is_generated(e.name)) return;
  if (std::size_t last = e.name.rfind('.'); last != dot && quantities_.is_generated(e.name.substr(0, last))) return;
  std::vector<std::string> offered = quantities_.of(owner);
  if (is_body)
    for (const auto& [p, x] : m_.bodies.at(owner).points) offered.push_back(p);
  std::string rest = e.name.substr(dot + 1);
  std::string near = ir::closest_name(rest, offered);
  diags_.error(e.loc, fmt::format("{} `{}` has no quantity `{}`", is_body ? "body" : "joint", owner, rest),
               near.empty() ? fmt::format("`{}` offers {}", owner, fmt::join(offered, ", "))
                            : fmt::format("did you mean `{}.{}`?", owner, near));
}

E QuantityRewriter::expr(const E& e) {
  if (!e) return e;
  if (e->kind == ir::Term::Kind::Ref && e->ref.kind == ir::Ref::Kind::Name) {
    if (const E* definition = quantities_.find(e->name)) {
      used_.insert(e->name);
      return *definition;
    }
    check_known(*e);
    return e;
  }
  bool changed = false;
  std::vector<E> args;
  for (const auto& a : e->args) {
    args.push_back(expr(a));
    changed |= args.back() != a;
  }
  if (!changed) return e;
  auto copy = std::make_shared<ir::Term>(*e);
  copy->args = std::move(args);
  return copy;
}

ir::ExpandedStmt QuantityRewriter::statement(const ir::ExpandedStmt& s) {
  ir::ExpandedStmt out = s;
  std::visit(
      [&](auto& st) {
        using T = std::decay_t<decltype(st)>;
        if constexpr (std::is_same_v<T, ir::ExpandedSignal> || std::is_same_v<T, ir::ExpandedOutput>) {
          st.value = expr(st.value);
        } else if constexpr (std::is_same_v<T, ir::ExpandedElement>) {
          st.value = expr(st.value);
          for (ir::TermAttr& a : st.attrs) a.value = expr(a.value);
        }
      },
      out);
  return out;
}

std::vector<ir::ExpandedStmt> rewrite_user_statements(const ir::AstProgram& program, QuantityRewriter& rewrite) {
  std::vector<ir::ExpandedStmt> out;
  for (const ir::AstStmt& s : program.stmts)
    if (ir::ExpandedStmt e; ir::as_expanded(s, e)) out.push_back(rewrite.statement(e));
  return out;
}

}  // namespace mbgc::multibody::detail
