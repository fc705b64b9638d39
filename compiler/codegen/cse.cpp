// codegen/cse.cpp — common subexpressions, defined before first use.
#include "codegen/cse.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <unordered_set>

namespace mbgc::codegen {

using namespace mbgc::ir;

namespace {

using ExprSet = std::unordered_set<Expr, ExprHash, ExprEqual>;

/// The values of a statement, in the order they are printed.
std::vector<const Expr*> values_of(const CppStmt& st) {
  std::vector<const Expr*> out;
  if (st.value) out.push_back(&st.value);
  for (const Expr& e : st.values) out.push_back(&e);
  return out;
}

class Pass {
 public:
  Pass(const ExprNames& known, int& counter) : known_(known), counter_(counter) {
    for (const auto& [e, name] : known) named_.insert(e);
  }

  /// How often each node is read: as a value, or as an operand of a node
  /// counted for the first time (a node used twice counts its operands once).
  void count(const Expr& e) {
    if (e->args.empty() || (e->op == Op::Neg && e->args[0]->args.empty())) return;
    if (known_.count(e)) return;
    if (++uses_[e] > 1) return;
    for (const Expr& a : e->args) count(a);
  }

  void finish_counting() {
    for (const auto& [e, n] : uses_)
      if (n > 1) pending_.insert(e);
    uses_.clear();
  }

  /// `st` and its group's definitions: the cseN its values need go to `defs`.
  void visit(CppStmt& st, std::vector<CppStmt>& defs) {
    bool whole = false;
    if (st.may_name != CppStmt::Naming::never && st.value && pending_.count(st.value) &&
        (st.may_name == CppStmt::Naming::always || !named_.count(st.value))) {
      pending_.erase(st.value);
      whole = true;
    }
    for (const Expr* e : values_of(st)) {
      std::unordered_set<const Node*> seen;
      define(*e, seen, defs);
    }
    if (whole) {
      st.names_value = true;
      named_.insert(st.value);
    }
  }

 private:
  void define(const Expr& x, std::unordered_set<const Node*>& seen, std::vector<CppStmt>& defs) {
    if (x->args.empty() || !seen.insert(x.get()).second) return;
    // A node named after its whole sub-tree was walked defines nothing new below.
    if (!known_.count(x) && named_.count(x)) return;
    for (const Expr& a : x->args) define(a, seen, defs);
    if (!pending_.count(x) || named_.count(x)) return;
    if (!announced_) defs.push_back(CppStmt::comment("(cseN: a subexpression several equations below share)"));
    announced_ = true;
    CppStmt def = CppStmt::local(fmt::format("cse{}", ++counter_), x);
    def.names_value = true;
    defs.push_back(std::move(def));
    named_.insert(x);
  }

  const ExprNames& known_;
  int& counter_;
  std::unordered_map<Expr, int, ExprHash, ExprEqual> uses_;
  ExprSet pending_;  // read more than once, not named yet
  ExprSet named_;    // the known ones, and those named so far
  bool announced_ = false;
};

}  // namespace

void share_subexpressions(std::vector<CppStmt>& body, std::size_t from, const ExprNames& known, int& counter) {
  Pass pass(known, counter);
  for (std::size_t i = from; i < body.size(); ++i)
    for (const Expr* e : values_of(body[i])) pass.count(*e);
  pass.finish_counting();
  std::vector<CppStmt> out(std::make_move_iterator(body.begin()), std::make_move_iterator(body.begin() + static_cast<long>(from)));
  std::vector<CppStmt> group, defs;
  auto flush = [&] {
    for (CppStmt& s : defs) out.push_back(std::move(s));
    for (CppStmt& s : group) out.push_back(std::move(s));
    defs.clear();
    group.clear();
  };
  for (std::size_t i = from; i < body.size(); ++i) {
    // (a statement of a group cannot name its value: a later one's definitions come before it)
    if (body[i].with_previous && body[i].may_name != CppStmt::Naming::never)
      throw std::logic_error("mbgc: a statement printed with the one before it may not name its value (codegen bug)");
    if (!body[i].with_previous) flush();
    pass.visit(body[i], defs);
    group.push_back(std::move(body[i]));
  }
  flush();
  body = std::move(out);
}

}  // namespace mbgc::codegen
