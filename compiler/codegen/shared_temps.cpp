// codegen/shared_temps.cpp — common subexpressions, defined before first use.
#include "codegen/shared_temps.hpp"

#include <fmt/format.h>

namespace mbgc::codegen {

using namespace mbgc::ir;

void SharedTemps::count(const Expr& e) {
  if (e->args.empty() || (e->op == Op::Neg && e->args[0]->args.empty())) return;
  if (known_.count(e)) return;  // computed once in initial()
  if (++uses_[e] > 1) return;   // children already counted through the first occurrence
  for (const Expr& a : e->args) count(a);
}

void SharedTemps::finish_counting() {
  for (const auto& [e, n] : uses_)
    if (n > 1) pending_.insert(e);
  uses_.clear();
}

bool SharedTemps::take_whole(const Expr& e) {
  if (!pending_.count(e) || temp.count(e)) return false;
  pending_.erase(e);
  return true;
}

std::string SharedTemps::print(const Expr& e, std::vector<CppStmt>& body) {
  std::unordered_set<const Node*> seen;
  std::function<void(const Expr&)> define = [&](const Expr& x) {
    if (x->args.empty() || !seen.insert(x.get()).second) return;
    // A temporary named after its whole sub-tree was walked defines nothing new below.
    if (!known_.count(x) && temp.count(x)) return;
    for (const Expr& a : x->args) define(a);
    if (pending_.count(x) && !temp.count(x)) {
      std::string name = fmt::format("cse{}", ++counter_);
      if (!announced_) body.push_back(CppStmt::comment("(cseN: a subexpression several equations below share)"));
      announced_ = true;
      body.push_back(CppStmt::local(name, print_with_temps(x, /*top=*/true)));
      temp[x] = name;
    }
  };
  define(e);
  return print_with_temps(e, false);
}

std::string SharedTemps::print_with_temps(const Expr& e, bool top) {
  if (temp.empty()) return to_cpp(e, names_, ops_);
  // Each defined temporary prints as its name, as a variable would; with
  // `top`, e itself is written out (its definition).
  const NamedNodes named = [&](const Expr& x) -> const std::string* {
    if (top && x.get() == e.get()) return nullptr;
    auto it = temp.find(x);
    return it == temp.end() ? nullptr : &it->second;
  };
  return to_cpp(e, names_, named, ops_);
}

}  // namespace mbgc::codegen
