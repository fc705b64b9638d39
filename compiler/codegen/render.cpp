// codegen/render.cpp — printing a method's typed statements.
#include "codegen/render.hpp"

#include <fmt/format.h>

namespace mbgc::codegen {

using namespace mbgc::ir;

void render(std::vector<CppStmt>& body, std::size_t from, const ExprNames& known, const Namer& names, CppOps* ops) {
  ExprNames named_here;  // by the statements printed so far
  const NamedNodes named = [&](const Expr& x) -> const std::string* {
    if (auto it = named_here.find(x); it != named_here.end()) return &it->second;
    auto it = known.find(x);
    return it == known.end() ? nullptr : &it->second;
  };
  auto print = [&](const Expr& e) { return to_cpp(e, names, named, ops); };
  std::vector<CppStmt> out(std::make_move_iterator(body.begin()), std::make_move_iterator(body.begin() + static_cast<long>(from)));
  for (std::size_t i = from; i < body.size(); ++i) {
    CppStmt& st = body[i];
    if (st.kind == CppStmt::Kind::Array) {
      std::vector<std::string> entries;
      for (const Expr& e : st.values) entries.push_back(print(e));
      const std::string head = fmt::format("double {}[{}] = ", st.name, entries.size());
      if (st.columns == 0) out.push_back(CppStmt::line(fmt::format("{}{{{}}};", head, fmt::join(entries, ", "))));
      else initialiser_lines(out, head, entries, st.columns, "};");
      continue;
    }
    if (st.value) {
      st.text = print(st.value);
      if (st.names_value) named_here[st.value] = st.name;
      st.value.reset();
    }
    out.push_back(std::move(st));
  }
  body = std::move(out);
}

}  // namespace mbgc::codegen
