// reduce/tree_elimination.cpp — a tree's algebraic loop, eliminated leaves first.
#include "reduce/tree_elimination.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <set>

#include <fmt/format.h>

#include "reduce/row_facts.hpp"

namespace mbgc::reduce {
namespace {

using namespace mbgc::ir;

/// sum_w coef[w] * w + rest, over a body's basis variables (its joint
/// accelerations and the parent unknowns it reads).
struct Form {
  std::map<int, Expr> coef;
  Expr rest = constant(0);

  void add_term(int w, const Expr& c) {
    if (is_zero(c)) return;
    auto [it, fresh] = coef.emplace(w, c);
    if (!fresh) it->second = add(it->second, c);
  }
  /// this += s * f
  void add_scaled(const Form& f, const Expr& s) {
    for (const auto& [w, c] : f.coef) add_term(w, mul(s, c));
    rest = add(rest, mul(s, f.rest));
  }
  Expr value() const {
    Expr e = rest;
    for (const auto& [w, c] : coef) e = add(e, mul(c, var(w)));
    return e;
  }
};

class Eliminator {
 public:
  Eliminator(const TornLoop& loop, const TreeLayout& tree, BondGraph& graph)
      : loop_(loop), tree_(tree), graph_(graph), depth_(tree.parent.size(), -1) {}

  std::optional<TreeElimination> run(std::string* why) {
    if (!assign_bodies(why) || !check_structure(why)) return std::nullopt;
    facts_.emplace(loop_, refs_, body_, multipliers_, kGlobal);
    std::vector<int> bodies(in_loop_.begin(), in_loop_.end());
    std::stable_sort(bodies.begin(), bodies.end(), [&](int a, int b) { return depth_[a] > depth_[b]; });
    for (int n : bodies)
      if (!inward(n, why)) return std::nullopt;
    TreeElimination out;
    if (!multipliers_.empty() && !multiplier_system(out, why)) return std::nullopt;
    std::reverse(bodies.begin(), bodies.end());
    std::stable_sort(bodies.begin(), bodies.end(), [&](int a, int b) { return depth_[a] < depth_[b]; });
    for (int n : bodies) outward(n);
    for (int u : loop_.order)  // what only the cut joints' rows read, last
      if (global_.count(u)) outward_.push_back({u, loop_.solution.at(u), loop_.source.at(u).first, loop_.source.at(u).second, -1});
    out.assignments = std::move(inward_);
    for (Assignment& a : outward_) out.assignments.push_back(std::move(a));
    out.bodies = static_cast<int>(in_loop_.size());
    out.temporaries = temporaries_;
    for (const auto& [u, b] : body_)
      if (b >= 0) out.body_of[u] = b;
    for (const auto& [t, b] : temporary_body_) out.body_of[t] = b;
    return out;
  }

 private:
  int depth(int n) {
    if (n < 0) return 0;
    if (depth_[static_cast<std::size_t>(n)] < 0) depth_[static_cast<std::size_t>(n)] = 1 + depth(tree_.parent[static_cast<std::size_t>(n)]);
    return depth_[static_cast<std::size_t>(n)];
  }
  int parent(int n) const { return tree_.parent[static_cast<std::size_t>(n)]; }
  const std::string& body_name(int n) const { return tree_.names[static_cast<std::size_t>(n)]; }

  /// Which body every unknown belongs to: the layout's, else (a bond-graph
  /// element that joins a body's block, say a motor's rotor on a joint's
  /// drive) the deepest body of the unknowns it is related to.
  bool assign_bodies(std::string* why) {
    std::vector<int>& all = all_;
    all = loop_.tears;
    all.insert(all.end(), loop_.order.begin(), loop_.order.end());
    const std::unordered_set<int> unknowns(all.begin(), all.end());
    for (std::size_t k = 0; k < loop_.tears.size(); ++k) {
      refs_[loop_.tears[k]] = loop_vars(loop_.tear_residuals[k], unknowns);
      tear_index_[loop_.tears[k]] = k;
    }
    for (int u : loop_.order) refs_[u] = loop_vars(loop_.solution.at(u), unknowns);
    std::unordered_map<int, std::vector<int>>& readers = readers_;
    for (int u : all)
      for (int w : refs_[u]) readers[w].push_back(u);
    // The cut joints' multipliers, and what only their rows read (directly or
    // through each other: the rows' rates and their derivatives), belong to
    // no body: they are solved for after the inward pass.
    multipliers_.insert(loop_.multipliers.begin(), loop_.multipliers.end());
    global_ = multipliers_;
    for (bool grew = true; grew;) {
      grew = false;
      for (int u : loop_.order) {
        if (global_.count(u) || readers[u].empty()) continue;
        if (std::all_of(readers[u].begin(), readers[u].end(), [&](int r) { return global_.count(r) > 0; }))
          global_.insert(u), grew = true;
      }
    }
    for (int u : all) {
      if (global_.count(u)) {
        body_[u] = kGlobal;
        continue;
      }
      auto it = tree_.body_of.find(u);
      body_[u] = it == tree_.body_of.end() ? -1 : it->second;
      if (body_[u] >= 0) depth(body_[u]);
    }
    for (bool changed = true; changed;) {
      changed = false;
      for (int u : all) {
        if (body_[u] >= 0 || body_[u] == kGlobal) continue;
        int best = -1;
        auto consider = [&](int w) {
          int b = body_[w];
          if (b >= 0 && (best < 0 || depth(b) > depth(best))) best = b;
        };
        for (int w : refs_[u]) consider(w);
        for (int w : readers[u]) consider(w);
        if (best >= 0) body_[u] = best, changed = true;
      }
    }
    for (int u : all) {
      if (body_[u] == kGlobal) continue;
      if (body_[u] < 0) {
        *why = fmt::format("`{}` belongs to no body of the tree", graph_.vars[static_cast<std::size_t>(u)].name);
        return false;
      }
      in_loop_.insert(body_[u]);
    }
    for (int t : loop_.tears)
      if (body_[t] >= 0) tears_of_[body_[t]].push_back(t);
    for (int u : loop_.order)
      if (body_[u] >= 0) order_of_[body_[u]].push_back(u);
    return true;
  }

  /// The loop's unknowns e reads, sorted.
  static std::vector<int> loop_vars(const Expr& e, const std::unordered_set<int>& unknowns) {
    std::unordered_set<int> vars;
    collect_vars(e, vars);
    std::vector<int> out;
    for (int u : vars)
      if (unknowns.count(u)) out.push_back(u);
    std::sort(out.begin(), out.end());
    return out;
  }

  /// Whether m is an ancestor of n (its parent, its parent's parent, ...).
  bool is_ancestor(int m, int n) const {
    for (int k = parent(n); k >= 0; k = parent(k))
      if (k == m) return true;
    return false;
  }

  /// A body's equations read its own unknowns, its parent's (X) and its
  /// children's (each child's outputs Y); anything else is not a tree. An
  /// ancestor's unknown is read like the parent's: it joins the X of every
  /// body on the way up, so each of them carries it in its affine forms (a
  /// body on a prismatic joint shares its parent's angular velocity, and
  /// after alias elimination its children read the grandparent's).
  bool check_structure(std::string* why) {
    for (int u : all_) {  // in the loop's order: the first offence reported is always the same
      const int n = body_.at(u);
      if (n == kGlobal) continue;  // a cut joint's row reads bodies anywhere
      for (int w : refs_.at(u)) {
        const int m = body_.at(w);
        if (m == n || multipliers_.count(w)) continue;
        if (m == kGlobal) {
          *why = fmt::format("`{}` (body {}) reads `{}`, which only the cut joints' rows should read",
                             graph_.vars[static_cast<std::size_t>(u)].name, body_name(n), graph_.vars[static_cast<std::size_t>(w)].name);
          return false;
        }
        if (m == parent(n)) x_[n].insert(w);
        else if (parent(m) == n) outputs_[m].insert(w), reads_child_.insert(u);
        else if (m >= 0 && is_ancestor(m, n))
          for (int k = n; k != m; k = parent(k)) x_[k].insert(w);
        else {
          *why = fmt::format("`{}` (body {}) reads `{}` (body {}), neither its parent nor a child",
                             graph_.vars[static_cast<std::size_t>(u)].name, body_name(n),
                             graph_.vars[static_cast<std::size_t>(w)].name, body_name(m));
          return false;
        }
      }
    }
    return true;
  }

  /// A temporary for `e` (constants and leaves stay as they are).
  Expr name(const Expr& e, int n, const char* what) {
    if (e->op == Op::Const || e->op == Op::Param || e->op == Op::Var) return e;
    const int id = graph_.add_var(fmt::format("{}.{}{}", body_name(n), what, ++count_[n]), VarKind::Auxiliary, loc_[n]);
    temporary_body_[id] = n;
    inward_.push_back({id, e, loc_[n],
                       fmt::format("{}, body {}: {}", kTreeEliminationOrigin, body_name(n), what_text(what)), -1});
    ++temporaries_;
    return var(id);
  }
  static const char* what_text(const char* what) {
    const std::string w = what;
    if (w == "pivot") return "1 / pivot of the joint's accelerations";
    if (w == "factor") return "elimination factor";
    if (w == "row") return "reduced row of the joint's equations";
    if (w == "accel") return "joint acceleration as an affine function of the parent's motion";
    if (w == "column") return "the cut joints' columns: an unknown their rows read, affine in their multipliers";
    if (w == "norm") return "1 / squared length of the one direction a joint's row leaves two efforts";
    return "what the parent reads of this body, as an affine function of the parent's motion (articulated inertia and bias)";
  }
  void name_all(Form& f, int n, const char* what) {
    for (auto& [w, c] : f.coef) c = name(c, n, what);
    f.rest = name(f.rest, n, what);
  }

  /// e as a Form over body n's basis, or false. It is first written over
  /// the basis and the body's own unknowns, its children's outputs summed
  /// there (each child's output is affine in this body's unknowns); each own
  /// unknown is then replaced by its form once, however many children read
  /// it: two children cost one substitution, as the articulated-body
  /// algorithm sums its children's inertias before transforming them.
  bool form_of(const Expr& e, int n, const std::vector<int>& refs, Form& out, int u) {
    std::vector<Expr> c;
    Expr rest;
    if (!affine_in(e, refs, c, rest)) return false;
    Form shallow;  // over the basis and body n's unknowns
    shallow.rest = rest;
    std::set<int> sums_added;  // the children whose output sum u reads: each sum substituted once
    for (std::size_t k = 0; k < refs.size(); ++k) {
      const int w = refs[k];
      if (is_zero(c[k])) continue;
      if (facts_->zero(w) && body_.at(w) != n) continue;  // read once solved: 0
      if (auto g = group_of_.find(w); g != group_of_.end() && g->second == u) {  // in a sum this unknown reads
        const int child = body_.at(w);
        if (sums_added.insert(child).second) add_form(group_form_.at({u, child}), shallow);
        continue;
      }
      if (basis_.count(w) || body_.at(w) == n) shallow.add_term(w, c[k]);
      else shallow.add_scaled(out_form_.at(w), c[k]);  // a child's output: affine in this body's unknowns
    }
    out = Form{};
    out.rest = shallow.rest;
    for (const auto& [x, kx] : shallow.coef) {
      if (basis_.count(x)) {
        out.add_term(x, kx);
        continue;
      }
      auto it = form_.find(x);
      if (it == form_.end()) {
        missing_ = x;
        return false;
      }
      out.add_scaled(it->second, kx);
    }
    return true;
  }

  /// out += y.
  static void add_form(const Form& y, Form& out) {
    for (const auto& [x, kx] : y.coef) out.add_term(x, kx);
    out.rest = add(out.rest, y.rest);
  }

  /// Body n's unknowns (other than its tears) in an order that computes
  /// them: after the unknowns they read, and one that reads a child's
  /// output after every unknown of n that the child reads (once the child's
  /// joint accelerations are eliminated, its output depends on all of them).
  bool sort_body(int n, std::string* why) {
    std::vector<int>& out = order_[n];
    std::unordered_map<int, int> state;  // 1 visiting, 2 done
    bool ok = true;
    std::function<void(int)> visit = [&](int u) {
      int& st = state[u];
      if (st == 2 || !ok) return;
      if (st == 1) {
        ok = false;
        *why = fmt::format("the unknowns of body {} depend on each other through `{}`", body_name(n),
                           graph_.vars[static_cast<std::size_t>(u)].name);
        return;
      }
      st = 1;
      for (int w : refs_.at(u)) {
        const int m = body_.at(w);
        if (m == n && loop_.solution.count(w)) visit(w);
        else if (m >= 0 && m != n && parent(m) == n)
          for (int x : x_[m])  // (an ancestor's unknown in a child's X is not this body's to order)
            if (loop_.solution.count(x) && body_.at(x) == n) visit(x);
      }
      state[u] = 2;
      out.push_back(u);
    };
    for (int u : order_of_[n]) visit(u);
    return ok;
  }

  bool inward(int n, std::string* why) {
    const std::vector<int>& tears = tears_of_[n];
    const std::vector<int>& others = order_of_[n];
    if (!tears.empty()) loc_[n] = loop_.source.at(tears[0]).first;
    else if (!others.empty()) loc_[n] = loop_.source.at(others.back()).first;
    basis_.clear();
    basis_.insert(tears.begin(), tears.end());
    basis_.insert(x_[n].begin(), x_[n].end());
    basis_.insert(multipliers_.begin(), multipliers_.end());
    auto fail = [&](int u) {
      if (missing_ >= 0)
        *why = fmt::format("`{}` (body {}) reads `{}` before it is known", graph_.vars[static_cast<std::size_t>(u)].name,
                           body_name(n), graph_.vars[static_cast<std::size_t>(missing_)].name);
      else
        *why = fmt::format("`{}` (body {}) is not affine in the body's joint accelerations and its parent's motion",
                           graph_.vars[static_cast<std::size_t>(u)].name, body_name(n));
      return false;
    };
    if (!sort_body(n, why)) return false;
    for (int u : order_[n]) {
      Form f;
      if (!form_of(loop_.solution.at(u), n, refs_.at(u), f, u)) return fail(u);
      form_.emplace(u, std::move(f));
    }
    // The joint's equations, D T + C X + d = 0, solved for T by elimination
    // without pivoting (D is an articulated inertia about the joint's free
    // directions: positive definite for a body with mass).
    std::vector<Form> rows;
    for (int t : tears) {
      Form r;
      if (!form_of(loop_.tear_residuals[tear_index_.at(t)], n, refs_.at(t), r, t)) return fail(t);
      rows.push_back(std::move(r));
    }
    const std::size_t m = tears.size();
    std::vector<Expr> inv(m);
    for (std::size_t k = 0; k < m; ++k) {
      const int tk = tears[k];
      std::size_t p = k;
      while (p < m && !rows[p].coef.count(tk)) ++p;
      if (p == m) {
        *why = fmt::format("the joint accelerations of body {} do not enter its joint's equations", body_name(n));
        return false;
      }
      std::swap(rows[k], rows[p]);
      inv[k] = name(div(constant(1), rows[k].coef.at(tk)), n, "pivot");
      for (std::size_t r = k + 1; r < m; ++r) {
        auto a = rows[r].coef.find(tk);
        if (a == rows[r].coef.end()) continue;
        Expr factor = name(mul(a->second, inv[k]), n, "factor");
        rows[r].coef.erase(a);
        Form scaled;
        for (const auto& [w, c] : rows[k].coef)
          if (w != tk) scaled.add_term(w, c);
        scaled.rest = rows[k].rest;
        rows[r].add_scaled(scaled, neg(factor));
        name_all(rows[r], n, "row");
      }
    }
    for (std::size_t k = m; k-- > 0;) {
      const int tk = tears[k];
      Form s;
      s.rest = rows[k].rest;
      for (const auto& [w, c] : rows[k].coef) {
        if (w == tk) continue;
        if (auto j = t_form_.find(w); j != t_form_.end()) s.add_scaled(j->second, c);
        else s.add_term(w, c);
      }
      Form t;
      t.add_scaled(s, neg(inv[k]));
      name_all(t, n, "accel");
      t_form_.emplace(tk, std::move(t));
    }
    // What the parent reads of this body, in terms of the parent's unknowns.
    // Outputs that one equation of the parent reads only as a sum with
    // constant coefficients (the torques a joint's two feeds put on the
    // parent's omega junction) are passed on as that sum: one form, not one
    // per output.
    std::map<int, std::vector<std::pair<int, Expr>>> sums;  // parent unknown -> (output, coefficient)
    for (int y : outputs_[n]) {
      if (facts_->zero(y)) continue;
      const int u = sole_parent_reader(y, n);
      Expr c;
      if (u >= 0 && !t_form_.count(y) && constant_coefficient(u, y, c)) sums[u].push_back({y, c});
    }
    std::set<int> in_sum;
    for (auto it = sums.begin(); it != sums.end();) {
      if (it->second.size() < 2) {
        it = sums.erase(it);
        continue;
      }
      for (const auto& [y, c] : it->second) in_sum.insert(y);
      ++it;
    }
    // An output that is a combination of others (the moment of the force
    // the parent reads, through the lever arm's MTF) is that combination of
    // their eliminated forms.
    std::map<int, std::vector<std::pair<int, Expr>>> derived;  // output -> (primary output, coefficient)
    for (int y : outputs_[n]) {
      std::vector<std::pair<int, Expr>> of;
      if (combination_of_outputs(y, n, in_sum, of)) derived.emplace(y, std::move(of));
    }
    std::map<int, std::pair<std::size_t, Expr>> of_mu;  // output -> (pair, its multiple of mu)
    for (int y : outputs_[n])
      if (auto m = facts_->multiple_of_pair(y); m && !derived.count(y)) of_mu.emplace(y, *m);
    for (const auto& [y, m] : of_mu) {
      if (mu_form_.count(m.first)) continue;
      const RowFacts::Pair& q = facts_->pair(m.first);
      Form num;  // a v2 - b v1
      num.add_scaled(form_.at(q.v2), q.a);
      num.add_scaled(form_.at(q.v1), neg(q.b));
      Form mu;
      mu.add_scaled(eliminated(num), name(div(constant(1), add(mul(q.a, q.a), mul(q.b, q.b))), n, "norm"));
      name_all(mu, n, "out");
      mu_form_.emplace(m.first, std::move(mu));
    }
    // y's eliminated form, scaled, added to `into` when it is built from
    // forms already eliminated (the combination of other outputs, or the
    // multiple of a confined pair's mu); false for any other output.
    auto add_after = [&](int y, const Expr& scale, Form& into) {
      if (auto d = derived.find(y); d != derived.end()) {
        for (const auto& [x, c] : d->second) into.add_scaled(out_form_.at(x), mul(scale, c));
        return true;
      }
      if (auto m = of_mu.find(y); m != of_mu.end()) {
        into.add_scaled(mu_form_.at(m->second.first), mul(scale, m->second.second));
        return true;
      }
      return false;
    };
    for (int y : outputs_[n]) {  // those eliminated from their own forms
      if (auto t = t_form_.find(y); t != t_form_.end()) {
        out_form_.emplace(y, t->second);
        continue;
      }
      if (in_sum.count(y) || derived.count(y) || of_mu.count(y)) continue;
      if (facts_->zero(y)) {
        out_form_.emplace(y, Form{});
        continue;
      }
      Form o = eliminated(form_.at(y));
      name_all(o, n, "out");
      out_form_.emplace(y, std::move(o));
    }
    // Those built from eliminated forms: the multiples of a pair's mu first,
    // since a combination of outputs may read one (a planar joint below a
    // moving body: its confined pair's outputs, and their combination).
    for (const bool combinations : {false, true}) {
      for (int y : outputs_[n]) {
        Form o;
        if (in_sum.count(y) || derived.count(y) != combinations || !add_after(y, constant(1), o)) continue;
        name_all(o, n, "out");
        out_form_.emplace(y, std::move(o));
      }
    }
    for (const auto& [u, members] : sums) {
      Form sum;    // summed before the joint accelerations are eliminated: one coefficient per acceleration
      Form after;  // the members built from eliminated forms
      for (const auto& [y, c] : members) {
        if (!add_after(y, c, after)) sum.add_scaled(form_.at(y), c);
        group_of_[y] = u;
      }
      Form z = eliminated(sum);
      add_form(after, z);
      name_all(z, n, "out");
      group_form_.emplace(std::make_pair(u, n), std::move(z));
    }
    return true;
  }

  /// Is output y of body n a combination, free of the loop's unknowns, of
  /// other outputs of n that are passed on alone (not in a sum, not tears)?
  bool combination_of_outputs(int y, int n, const std::set<int>& in_sum, std::vector<std::pair<int, Expr>>& of) const {
    auto s = loop_.solution.find(y);
    if (s == loop_.solution.end() || t_form_.count(y) || facts_->zero(y)) return false;
    const std::vector<int>& refs = refs_.at(y);
    std::vector<Expr> c;
    Expr rest;
    if (refs.empty() || !affine_in(s->second, refs, c, rest) || !is_zero(rest)) return false;
    for (std::size_t k = 0; k < refs.size(); ++k) {
      if (is_zero(c[k])) continue;
      const int x = refs[k];
      if (x == y || !outputs_.at(n).count(x) || in_sum.count(x) || t_form_.count(x) || body_.at(x) != n) return false;
      of.push_back({x, c[k]});
    }
    // (a primary output is computed from its own form: it reads no output)
    for (const auto& [x, cx] : of)
      for (int r : refs_.at(x))
        if (outputs_.at(n).count(r)) return false;
    return !of.empty();
  }

  /// f with the body's joint accelerations replaced by their forms.
  Form eliminated(const Form& f) const {
    Form o;
    o.rest = f.rest;
    for (const auto& [w, c] : f.coef) {
      if (auto t = t_form_.find(w); t != t_form_.end()) o.add_scaled(t->second, c);
      else o.add_term(w, c);
    }
    return o;
  }

  /// The one unknown of n's parent whose equation reads y, or -1.
  int sole_parent_reader(int y, int n) const {
    int found = -1;
    auto it = readers_.find(y);
    if (it == readers_.end()) return -1;
    for (int u : it->second) {
      if (body_.at(u) == n) continue;
      if (body_.at(u) != parent(n) || found >= 0) return -1;
      found = u;
    }
    return found;
  }

  /// The coefficient of y in u's equation, if it is a constant.
  bool constant_coefficient(int u, int y, Expr& c) const {
    const Expr& e = tear_index_.count(u) ? loop_.tear_residuals[tear_index_.at(u)] : loop_.solution.at(u);
    std::vector<Expr> coef;
    Expr rest;
    if (!affine_in(e, {y}, coef, rest) || !is_const(coef[0])) return false;
    c = coef[0];
    return true;
  }

  /// Unknown u affine in the multipliers alone (its body's X and tears
  /// replaced by theirs, up to the root), coefficients named.
  const Form& lambda_form(int u) {
    if (auto it = lambda_form_.find(u); it != lambda_form_.end()) return it->second;
    Form out;
    auto substitute = [&](const Form& f) {
      out.rest = f.rest;
      for (const auto& [w, c] : f.coef) {
        if (multipliers_.count(w)) out.add_term(w, c);
        else out.add_scaled(lambda_form(w), c);
      }
    };
    const int n = body_.at(u);
    if (multipliers_.count(u)) {
      out.add_term(u, constant(1));
    } else if (n == kGlobal || (!t_form_.count(u) && !form_.count(u))) {
      // read by the cut joints' rows only: its own equation, over the loop's unknowns
      const std::vector<int>& refs = refs_.at(u);
      std::vector<Expr> c;
      Expr rest;
      affine_in(loop_.solution.at(u), refs, c, rest);  // (affine: the loop was torn linearly)
      out.rest = rest;
      for (std::size_t k = 0; k < refs.size(); ++k)
        if (!is_zero(c[k])) out.add_scaled(lambda_form(refs[k]), c[k]);
    } else {
      substitute(t_form_.count(u) ? t_form_.at(u) : form_.at(u));
    }
    if (n >= 0) name_all(out, n, "column");
    return lambda_form_.emplace(u, std::move(out)).first->second;
  }

  /// Whether variable u is an effort of a cut joint's CN (LawForm::Stabilised).
  bool of_cut_joint(int u) const {
    const Variable& v = graph_.vars[static_cast<std::size_t>(u)];
    if (v.kind != VarKind::Effort || v.of < 0) return false;
    const Bond& b = graph_.bonds[static_cast<std::size_t>(v.of)];
    for (int end : {b.from, b.to}) {
      const GraphNode& node = graph_.nodes[static_cast<std::size_t>(end)];
      if (node.kind == NodeKind::CN && node.law == LawForm::Stabilised) return true;
    }
    return false;
  }

  /// The cut joints' rows, affine in the multipliers: A lambda + b = 0.
  bool multiplier_system(TreeElimination& out, std::string* why) {
    LinearBlock lb;
    for (std::size_t k = 0; k < loop_.tears.size(); ++k) {
      const int t = loop_.tears[k];
      if (!multipliers_.count(t)) continue;
      lb.unknowns.push_back(t);
    }
    for (int t : lb.unknowns) {
      const std::size_t k = static_cast<std::size_t>(std::find(loop_.tears.begin(), loop_.tears.end(), t) - loop_.tears.begin());
      const std::vector<int>& refs = refs_.at(t);
      std::vector<Expr> c;
      Expr rest;
      if (!affine_in(loop_.tear_residuals[k], refs, c, rest)) {
        *why = fmt::format("the row of `{}` is not affine in the loop's unknowns", graph_.vars[static_cast<std::size_t>(t)].name);
        return false;
      }
      Form row;
      row.rest = rest;
      for (std::size_t r = 0; r < refs.size(); ++r)
        if (!is_zero(c[r])) row.add_scaled(lambda_form(refs[r]), c[r]);
      for (int l : lb.unknowns) lb.a.push_back(row.coef.count(l) ? row.coef.at(l) : constant(0));
      lb.b.push_back(neg(row.rest));
    }
    for (int t : lb.unknowns)
      inward_.push_back({t, nullptr, loop_.source.at(t).first,
                         fmt::format("cut joints: {} multiplier{} from their rows at acceleration level, an {}x{} system "
                                     "solved at run time",
                                     lb.unknowns.size(), lb.unknowns.size() == 1 ? "" : "s", lb.unknowns.size(), lb.unknowns.size()),
                         0});
    lb.rank_revealing = true;
    lb.cut_joints = std::any_of(lb.unknowns.begin(), lb.unknowns.end(), [&](int u) { return of_cut_joint(u); });
    out.multipliers = std::move(lb);
    return true;
  }

  void outward(int n) {
    for (int t : tears_of_[n]) {
      const auto& [loc, origin] = loop_.source.at(t);
      outward_.push_back({t, t_form_.at(t).value(), loc,
                          fmt::format("joint acceleration of body {} from its parent's motion (articulated-body form)",
                                      body_name(n)),
                          -1});
    }
    for (int u : order_[n]) {
      const auto& [loc, origin] = loop_.source.at(u);
      if (facts_->zero(u)) outward_.push_back({u, constant(0), loc, origin + " [zero: a free joint direction's effort]", -1});
      else if (reads_child_.count(u)) outward_.push_back({u, form_.at(u).value(), loc, origin + " [after the body's elimination]", -1});
      else outward_.push_back({u, facts_->without_zeros(loop_.solution.at(u)), loc, origin, -1});
    }
  }

  const TornLoop& loop_;
  const TreeLayout& tree_;
  BondGraph& graph_;
  std::vector<int> depth_;
  std::vector<int> all_;                            // the loop's unknowns: tears, then the others in order
  std::unordered_map<int, std::vector<int>> refs_;  // unknown -> the loop's unknowns its equation reads
  std::unordered_map<int, int> body_;               // unknown -> body
  std::set<int> in_loop_;                           // bodies with unknowns in the loop
  std::map<int, std::set<int>> x_;                  // body -> its parent's unknowns it reads
  std::map<int, std::set<int>> outputs_;            // body -> its unknowns its parent reads
  std::unordered_set<int> reads_child_;             // unknowns whose equation reads a child's output
  std::set<int> basis_;                             // the body being eliminated: tears and X
  std::map<int, std::vector<int>> order_;           // body -> its unknowns but the tears, in evaluation order
  std::unordered_map<int, std::vector<int>> tears_of_;   // body -> its tears, in the loop's order
  std::unordered_map<int, std::vector<int>> order_of_;   // body -> its other unknowns, in the loop's order
  std::unordered_map<int, std::size_t> tear_index_;      // tear -> its index in loop_.tears
  std::unordered_map<int, Form> form_;              // unknown -> affine in its body's basis
  std::unordered_map<int, Form> t_form_;            // tear -> affine in its body's X
  std::unordered_map<int, Form> out_form_;          // output -> affine in its parent's unknowns
  std::unordered_map<int, std::vector<int>> readers_;  // unknown -> the loop's unknowns whose equation reads it
  std::unordered_map<int, int> group_of_;           // output passed on in a sum -> the parent unknown that reads the sum
  std::map<std::pair<int, int>, Form> group_form_;  // (parent unknown, child) -> the sum's form
  std::map<int, int> count_;                        // body -> temporaries so far
  std::map<int, SourceLoc> loc_;                    // body -> model line for its temporaries
  std::vector<Assignment> inward_, outward_;
  int temporaries_ = 0;
  std::unordered_map<int, int> temporary_body_;     // temporary -> its body
  int missing_ = -1;  // an unknown read before its form was known (for the diagnosis)
  static constexpr int kGlobal = -2;                // body_ of the multipliers and what only their rows read
  std::unordered_set<int> multipliers_, global_;    // the cut joints' multipliers; they and what only their rows read
  std::optional<RowFacts> facts_;                   // what the joints' rows say: zeros, pairs confined to one direction
  std::map<std::size_t, Form> mu_form_;              // pair -> mu, eliminated, affine in the parent's motion
  std::unordered_map<int, Form> lambda_form_;       // unknown -> affine in the multipliers alone
};

}  // namespace

std::optional<TreeElimination> eliminate_along_tree(const TornLoop& loop, const TreeLayout& tree, BondGraph& graph,
                                                    std::string* why_not) {
  Eliminator e(loop, tree, graph);
  std::string why;
  auto out = e.run(&why);
  if (!out && why_not) *why_not = why;
  return out;
}

}  // namespace mbgc::reduce
