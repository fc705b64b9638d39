// reduce/row_facts.cpp — the efforts a tree's joint rows set to zero or
// confine to one direction.
#include "reduce/row_facts.hpp"

namespace mbgc::reduce {

using namespace mbgc::ir;

RowFacts::RowFacts(const TornLoop& loop, const std::unordered_map<int, std::vector<int>>& refs,
                   const std::unordered_map<int, int>& body, const std::unordered_set<int>& multipliers, int global_body)
    : loop_(loop), refs_(refs), body_(body), multipliers_(multipliers), global_body_(global_body),
      tears_(loop.tears.begin(), loop.tears.end()) {
  find_zeros();
  find_pairs();
}

namespace {
/// The one unknown of `refs` that e is a nonzero constant multiple of, or -1.
int multiple_of(const Expr& e, const std::vector<int>& refs) {
  std::vector<Expr> c;
  Expr rest;
  if (!affine_in(e, refs, c, rest) || !is_zero(rest)) return -1;
  int found = -1;
  for (std::size_t k = 0; k < refs.size(); ++k) {
    if (is_zero(c[k])) continue;
    double value = 0;
    if (found >= 0 || !is_const(c[k], &value) || value == 0) return -1;
    found = refs[k];
  }
  return found;
}
}  // namespace

/// A row that is one effort alone (times a constant) makes it zero; so is an
/// unknown that is a constant multiple of a zero, and one that is a
/// combination of zeros alone.
void RowFacts::find_zeros() {
  std::vector<int> work;
  for (std::size_t k = 0; k < loop_.tears.size(); ++k) {
    const int t = loop_.tears[k];
    if (multipliers_.count(t)) continue;
    const int w = multiple_of(loop_.tear_residuals[k], refs_.at(t));
    if (w >= 0 && !is_tear(w) && zero_.insert(w).second) work.push_back(w);
  }
  while (!work.empty()) {  // v = c w with v zero: w is zero
    const int v = work.back();
    work.pop_back();
    auto s = loop_.solution.find(v);
    if (s == loop_.solution.end()) continue;
    const int w = multiple_of(s->second, refs_.at(v));
    if (w >= 0 && !is_tear(w) && zero_.insert(w).second) work.push_back(w);
  }
  for (int u : loop_.order) {  // (the order computes every unknown after those it reads)
    if (zero_.count(u) || body_.at(u) == global_body_) continue;
    const std::vector<int>& refs = refs_.at(u);
    std::vector<Expr> c;
    Expr rest;
    if (refs.empty() || !affine_in(loop_.solution.at(u), refs, c, rest) || !is_zero(rest)) continue;
    bool all = true;
    for (std::size_t k = 0; k < refs.size() && all; ++k) all = is_zero(c[k]) || zero_.count(refs[k]);
    if (all) zero_.insert(u);
  }
  std::unordered_map<int, Expr> to_zero;
  for (int u : zero_) to_zero[u] = constant(0);
  zero_values_ = Substitution(std::move(to_zero));
}

/// A row that, once its zeros are dropped (and followed through unknowns that
/// are constant multiples of one other), reads two unknowns of its body.
void RowFacts::find_pairs() {
  for (std::size_t k = 0; k < loop_.tears.size(); ++k) {
    const int t = loop_.tears[k];
    if (multipliers_.count(t) || body_.at(t) < 0) continue;
    auto own = [&](int v) { return body_.at(v) == body_.at(t) && !is_tear(v) && loop_.solution.count(v); };
    Expr e = loop_.tear_residuals[k];
    std::vector<int> refs = refs_.at(t);
    for (int depth = 0; depth < 8; ++depth) {
      std::vector<Expr> c;
      Expr rest;
      if (!affine_in(e, refs, c, rest) || !is_zero(rest)) break;
      std::vector<std::pair<int, Expr>> all, terms;  // the terms; those not zero
      for (std::size_t j = 0; j < refs.size(); ++j)
        if (!is_zero(c[j])) {
          all.push_back({refs[j], c[j]});
          if (!zero_.count(refs[j])) terms.push_back({refs[j], c[j]});
        }
      if (all.size() == 1 && is_const(all[0].second) && own(all[0].first)) {  // follow v = c w
        e = loop_.solution.at(all[0].first);
        refs = refs_.at(all[0].first);
        continue;
      }
      if (terms.size() == 2 && own(terms[0].first) && own(terms[1].first) && !paired_.count(terms[0].first) &&
          !paired_.count(terms[1].first)) {
        const std::size_t index = pairs_.size();
        pairs_.push_back({body_.at(t), terms[0].first, terms[1].first, terms[0].second, terms[1].second});
        paired_[terms[0].first] = index;
        paired_[terms[1].first] = index;
      }
      break;
    }
  }
}

std::optional<std::pair<std::size_t, Expr>> RowFacts::multiple_of_pair(int y) const {
  if (pairs_.empty() || is_tear(y) || zero_.count(y)) return std::nullopt;
  auto s = loop_.solution.find(y);
  if (s == loop_.solution.end()) return std::nullopt;
  const std::vector<int>& refs = refs_.at(y);
  std::vector<Expr> c;
  Expr rest;
  if (refs.empty() || !affine_in(s->second, refs, c, rest) || !is_zero(rest)) return std::nullopt;
  std::optional<std::size_t> pair;
  Expr c1 = constant(0), c2 = constant(0);
  for (std::size_t k = 0; k < refs.size(); ++k) {
    if (is_zero(c[k]) || zero_.count(refs[k])) continue;
    auto p = paired_.find(refs[k]);
    if (p == paired_.end() || (pair && *pair != p->second)) return std::nullopt;
    pair = p->second;
    (pairs_[p->second].v1 == refs[k] ? c1 : c2) = c[k];
  }
  if (!pair) return std::nullopt;
  const Pair& q = pairs_[*pair];
  return std::make_pair(*pair, sub(mul(c2, q.a), mul(c1, q.b)));  // c1 v1 + c2 v2 = (a c2 - b c1) mu
}

}  // namespace mbgc::reduce
