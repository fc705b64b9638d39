#include "units/check.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace mbgc::units {
namespace {

using ir::Expr;
using ir::Fn;
using ir::Op;

/// c * u: a term of a linear form over the unknown dimensions' exponents.
struct Term {
  int unknown;
  Rational coef;
};

/// The dimension of an expression as a product of powers of unknowns and a
/// known constant: D * prod(u_i ^ c_i). `wild`: a number, which takes the
/// dimension of whatever it is added to (`x + 1`, `max(x, 0)`). In a product
/// it may carry a unit of its own (`R r { e = 0.5 * f^2 }`, `param It = m *
/// 1.01 / 12` for a rod of 1 m, a parameter the compiler folded into its
/// value), so it is an unknown of that product: a number without a unit is
/// never taken to have none. A function's value (`sin`, `step`) is a number
/// of no unit in a product (`L * cos(q)` is a length), but on its own any:
/// `Se f = step(0, 1)` is 1 N from t = 0, `heaviside(t)` once folded.
struct Form {
  std::vector<Term> terms;  // sorted by unknown, no zero coefficient
  Dimension constant;
  bool wild = false;
  bool function = false;  // wild: a function's value

  static Form known(Dimension d) { return {{}, d.without_angle(), false, false}; }
  static Form unknown(int u) { return {{{u, 1}}, {}, false, false}; }
  static Form number() { return {{}, {}, true, false}; }
  static Form function_value() { return {{}, {}, true, true}; }
  /// Exponents small enough to compute with exactly (`x^999^999` is not checked).
  bool is_small() const {
    for (const Term& t : terms)
      if (!t.coef.is_small()) return false;
    return constant.is_small();
  }
};

/// a * b^k (k = -1: a / b)
Form combine(const Form& a, const Form& b, Rational k) {
  Form out;
  out.constant = a.constant * b.constant.pow(k);
  std::size_t i = 0, j = 0;
  while (i < a.terms.size() || j < b.terms.size()) {
    if (j == b.terms.size() || (i < a.terms.size() && a.terms[i].unknown < b.terms[j].unknown)) {
      out.terms.push_back(a.terms[i++]);
    } else if (i == a.terms.size() || b.terms[j].unknown < a.terms[i].unknown) {
      out.terms.push_back({b.terms[j].unknown, b.terms[j].coef * k});
      ++j;
    } else {
      Rational c = a.terms[i].coef + b.terms[j].coef * k;
      if (!c.is_zero()) out.terms.push_back({a.terms[i].unknown, c});
      ++i;
      ++j;
    }
  }
  return out;
}

Form power(const Form& a, Rational k) {
  Form out;
  out.constant = a.constant.pow(k);
  if (k.is_zero()) return out;
  for (const Term& t : a.terms) out.terms.push_back({t.unknown, t.coef * k});
  return out;
}

/// Up to a few ids, sorted: the declared units a solution rests on.
using Reasons = std::vector<int>;
void merge(Reasons& into, const Reasons& from) {
  for (int r : from)
    if (into.size() < 8 && std::find(into.begin(), into.end(), r) == into.end()) into.push_back(r);
  std::sort(into.begin(), into.end());
}

/// The system of equations between unknown dimensions, kept solved: each
/// solved unknown is a form over unsolved ones only, with the declared units
/// (by parameter) it was found from, so that a contradiction can name them.
class Solver {
 public:
  explicit Solver(std::size_t n) : solved_(n), reasons_(n), used_in_(n) {}

  /// A new unknown, which nothing fixes yet.
  int fresh() {
    solved_.emplace_back();
    reasons_.emplace_back();
    used_in_.emplace_back();
    return static_cast<int>(solved_.size()) - 1;
  }

  /// `f` with every solved unknown replaced by its solution; the declared
  /// units those rest on join `why` if given.
  Form reduce(const Form& f, Reasons* why = nullptr) const {
    Form out = Form::known(f.constant);
    out.wild = f.wild;
    out.function = f.function;
    for (const Term& t : f.terms) {
      const std::optional<Form>& s = solved_[static_cast<std::size_t>(t.unknown)];
      out = s ? combine(out, *s, t.coef) : combine(out, Form::unknown(t.unknown), t.coef);
      if (s && why) merge(*why, reasons_[static_cast<std::size_t>(t.unknown)]);
    }
    return out;
  }

  /// The declared units (parameter ids) the next requirements come from.
  void because(Reasons r) { because_ = std::move(r); }
  /// After a contradiction: the declared units its two sides rest on.
  const Reasons& last_reasons() const { return last_reasons_; }

  /// Adds `f` = none; false when that contradicts what is known.
  bool require_none(const Form& given) {
    if (!given.is_small()) return true;  // not checked
    Reasons why = because_;
    Form f = reduce(given, &why);
    if (!f.is_small()) return true;
    if (f.terms.empty()) {
      last_reasons_ = why;
      return f.constant.without_angle().is_none();
    }
    // the pivot: the unknown that the fewest solutions mention (cheap to substitute)
    std::size_t p = 0;
    for (std::size_t i = 1; i < f.terms.size(); ++i)
      if (used_in_[static_cast<std::size_t>(f.terms[i].unknown)].size() <
          used_in_[static_cast<std::size_t>(f.terms[p].unknown)].size())
        p = i;
    const int u = f.terms[p].unknown;
    const Rational c = f.terms[p].coef;
    // u = -(f - c u) / c
    Form rest = f;
    rest.terms.erase(rest.terms.begin() + static_cast<std::ptrdiff_t>(p));
    Form solution = power(rest, Rational(-1) / c);
    if (!solution.is_small()) return true;  // not checked
    // the solutions that mention u, with u replaced: all small, or the requirement is not taken
    std::vector<std::pair<int, Form>> updated;
    std::unordered_set<int> seen;
    for (int user : used_in_[static_cast<std::size_t>(u)]) {
      const Form& s = *solved_[static_cast<std::size_t>(user)];
      auto it = std::find_if(s.terms.begin(), s.terms.end(), [u](const Term& t) { return t.unknown == u; });
      if (it == s.terms.end() || !seen.insert(user).second) continue;  // listed twice
      Form rest_of_user = s;
      rest_of_user.terms.erase(rest_of_user.terms.begin() + (it - s.terms.begin()));
      Form replaced = combine(rest_of_user, solution, it->coef);
      if (!replaced.is_small()) return true;
      updated.emplace_back(user, std::move(replaced));
    }
    for (auto& [user, form] : updated) {
      solved_[static_cast<std::size_t>(user)] = std::move(form);
      merge(reasons_[static_cast<std::size_t>(user)], why);
      for (const Term& t : solution.terms) used_in_[static_cast<std::size_t>(t.unknown)].push_back(user);
    }
    used_in_[static_cast<std::size_t>(u)].clear();
    for (const Term& t : solution.terms) used_in_[static_cast<std::size_t>(t.unknown)].push_back(u);
    solved_[static_cast<std::size_t>(u)] = std::move(solution);
    reasons_[static_cast<std::size_t>(u)] = std::move(why);
    return true;
  }

  /// a = b; false when that contradicts what is known. A number agrees with anything.
  bool unify(const Form& a, const Form& b) {
    if (a.wild || b.wild) return true;
    return require_none(combine(a, b, -1));
  }

  std::optional<Dimension> value(int u) const {
    Form f = reduce(Form::unknown(u));
    if (!f.terms.empty()) return std::nullopt;
    return f.constant;
  }

 private:
  std::vector<std::optional<Form>> solved_;
  std::vector<Reasons> reasons_;  // of each solved unknown
  std::vector<std::vector<int>> used_in_;
  Reasons because_, last_reasons_;
};

/// A rational close to `x` with a small denominator (an exponent as written: 2, 0.5, 1.5).
std::optional<Rational> small_rational(double x) {
  for (int den = 1; den <= 12; ++den) {
    double n = x * den;
    if (std::abs(n - std::round(n)) < 1e-9 && std::abs(n) < 1000) return Rational(static_cast<int>(std::round(n)), den);
  }
  return std::nullopt;
}

class Checker {
 public:
  Checker(const ir::EquationSystem& sys, ir::Diagnostics& diags)
      : sys_(sys), g_(sys.graph), diags_(diags), solver_(g_.params.size() + g_.vars.size()) {
    names_.var = [this](int id) { return g_.vars[static_cast<std::size_t>(id)].name; };
    names_.param = [this](int id) { return g_.params[static_cast<std::size_t>(id)].name; };
    for (const ir::GraphNode& n : g_.nodes)
      if (n.generated || constant_modulus(n)) unread_locs_.insert(loc_key(n.loc));
      else if (ir::is_junction(n.kind)) junction_locs_.insert(loc_key(n.loc));
  }

  UnitReport run(bool strict) {
    // What the model states first, so that a contradiction is found at an equation.
    for (std::size_t i = 0; i < g_.params.size(); ++i)
      if (g_.params[i].unit || g_.params[i].stated) {
        solver_.because({static_cast<int>(i)});
        const ir::Parameter& p = g_.params[i];
        solver_.require_none(combine(param(i), p.unit ? declared(*p.unit) : Form::known(*p.stated), -1));
      }
    solver_.because({});
    for (const ir::Signal& s : g_.signals)
      if (s.unit) solver_.require_none(combine(Form::unknown(var_unknown(s.var)), declared(*s.unit), -1));
    for (std::size_t i = 0; i < g_.params.size(); ++i) {
      const ir::Parameter& p = g_.params[i];
      if (!p.value || p.literal || p.generated) continue;
      site_ = {p.loc, fmt::format("param {} = {}", p.name, text(p.value)), {p.value}};
      agree(param(i), form(p.value), "the parameter", "its value");
    }
    for (const ir::Bond& b : g_.bonds)
      for (std::size_t k = 0; k < b.effort_vars.size() && k < b.flow_vars.size(); ++k) {
        Form ef = combine(Form::unknown(var_unknown(b.effort_vars[k])), Form::unknown(var_unknown(b.flow_vars[k])), 1);
        site_ = {b.loc, fmt::format("bond {}", b.name), {}};
        agree(ef, Form::known(dim::power()), "its effort times its flow", "a power");
      }
    for (const ir::StateVar& s : sys_.states) {
      if (s.der < 0) continue;
      Form rate = combine(Form::unknown(var_unknown(s.var)), Form::known(dim::time()), -1);
      solver_.unify(Form::unknown(var_unknown(s.der)), rate);
    }
    // What the multibody layer states of its quantities (`arm.position` is m):
    // where a user's expression reads one, it is that, whatever it is made of
    // (the layer's folded geometry is not read: a point at [1, 0, 0] is R's
    // first column, whose 1 m is gone).
    for (const ir::UnitCheck& c : g_.unit_checks)
      if (c.quantity)
        for (const Expr& item : c.items)
          if (item->op != Op::Const && item->op != Op::Param && item->op != Op::Time) {
            memo_[item.get()] = Form::known(c.dimension);
            with_angle_.emplace(item.get(), c.dimension);
          }
    // The junctions first, then the elements' laws in the order written, then
    // the signals: what contradicts the ones before it is the one reported.
    std::unordered_set<long long> signal_locs;
    for (const ir::Signal& s : g_.signals) signal_locs.insert(loc_key(s.loc));
    for (bool junctions : {true, false})
      for (const ir::Equation& e : sys_.equations) {
        if (junction_locs_.count(loc_key(e.loc)) != static_cast<std::size_t>(junctions)) continue;
        if (signal_locs.count(loc_key(e.loc))) continue;
        // A contact's equation switches between modes (`closed * (g'' + ...) + (1 - closed) * e`):
        // each mode's side has its own unit, so it is not checked.
        if (mentions_discrete(e.lhs) || mentions_discrete(e.rhs)) continue;
        if (unread_locs_.count(loc_key(e.loc))) continue;
        site_ = {e.loc, e.origin.empty() ? fmt::format("{} = {}", text(e.lhs), text(e.rhs)) : e.origin, {e.lhs, e.rhs}};
        agree(form(e.lhs), form(e.rhs), fmt::format("`{}`", text(e.lhs)), fmt::format("`{}`", text(e.rhs)));
      }
    for (const ir::Signal& s : g_.signals) {
      if (s.generated) continue;
      site_ = {s.loc, fmt::format("signal {}", s.name), {s.value}};
      agree(Form::unknown(var_unknown(s.var)), form(s.value), "the signal", "its value");
    }
    // A storage's initial value given as its state (`q0 = 10 {mm}`, `p0`) is
    // that state: a user's element only (the layer's poses are its own). Not
    // through e0 or f0: `p0 = I * f0` folds `I * 1` to I, and the 1's unit with it.
    for (const ir::StateVar& s : sys_.states) {
      if (s.node < 0 || !s.initial) continue;
      const ir::GraphNode& n = g_.nodes[static_cast<std::size_t>(s.node)];
      if (n.generated || !n.initial_is_state) continue;
      const std::string state = g_.vars[static_cast<std::size_t>(s.var)].name;
      site_ = {n.loc, fmt::format("the initial value of `{}`", state), {s.initial},
               fmt::format("`{}` starts at its element's q0 or p0: check the unit written there", state)};
      agree(Form::unknown(var_unknown(s.var)), form(s.initial), fmt::format("`{}`", state), "its initial value");
    }
    for (const ir::UnitCheck& c : g_.unit_checks) {
      if (c.quantity) continue;  // taken first
      site_ = {c.loc, c.what, c.items,
               fmt::format("its value must be in {}: check the units of what it reads", format(c.dimension))};
      for (const Expr& item : c.items) {
        Form f = form(item);
        if (!solver_.unify(f, Form::known(c.dimension)))
          report(fmt::format("it is {}, and its value is {}", format(c.dimension), shown(f)));
      }
    }
    // A value the run writes or computes is in SI: a unit that needs a factor cannot be its own.
    for (const ir::Output& o : g_.outputs)
      if (o.unit && !o.unit->unit.is_si()) not_si(*o.unit, "output", o.name);
    for (const ir::Signal& s : g_.signals)
      if (s.unit && !s.unit->unit.is_si()) not_si(*s.unit, "signal", s.name);
    UnitReport report;
    for (const ir::Output& o : g_.outputs) {
      site_ = {o.loc, fmt::format("output {}", o.name), {o.value}};
      Form f = form(o.value);
      if (o.unit)
        agree(f, declared(*o.unit), "its value",
              fmt::format("its unit {{{}}} is {}", o.unit->unit.text, format(o.unit->unit.dimension)));
      Form r = solver_.reduce(f);
      report.outputs.push_back(r.terms.empty() && !r.wild ? std::optional<Dimension>(shown_with_angle(o.value, r.constant)) : std::nullopt);
    }
    for (std::size_t i = 0; i < g_.params.size(); ++i) {
      const std::optional<Dimension> given = given_dimension(g_.params[i]);
      report.params.push_back(given ? given : solver_.value(static_cast<int>(i)));
      if (strict && !report.params.back() && !g_.params[i].generated)
        diags_.error(g_.params[i].loc, fmt::format("the unit of parameter `{}` is neither declared nor inferred", g_.params[i].name),
                     "declare it after the value, e.g. {N/m} (--units strict)");
    }
    return report;
  }

 private:
  /// Where a contradiction is reported: the model line, what is there, and
  /// the expressions it reads (their declared parameters are noted).
  struct Site {
    ir::SourceLoc loc;
    std::string what;
    std::vector<Expr> exprs;
    std::string hint = {};  // empty: the general one
  };

  static long long loc_key(const ir::SourceLoc& l) {
    return (static_cast<long long>(l.file) << 40) + (static_cast<long long>(l.line) << 16) + l.col;
  }

  static bool constant_modulus(const ir::GraphNode& n) {
    if (n.law != ir::LawForm::Linear || n.value.items.empty()) return false;
    for (const Expr& item : n.value.items)
      if (!ir::is_const(item) || item->id >= 0) return false;  // a literal with a unit is read (`I mass = 2 {kg}`)
    return true;
  }

  bool mentions_discrete(const Expr& e) const {
    std::unordered_set<int> vars;
    ir::collect_vars(e, vars);
    for (int v : vars)
      if (g_.vars[static_cast<std::size_t>(v)].kind == ir::VarKind::Discrete) return true;
    return false;
  }

  int var_unknown(int var) const { return static_cast<int>(g_.params.size()) + var; }
  static Form param(std::size_t i) { return Form::unknown(static_cast<int>(i)); }
  static Form declared(const ir::DeclaredUnit& u) { return Form::known(u.unit.dimension); }

  std::string text(const Expr& e) const {
    std::string s = ir::to_string(e, names_);
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
  }

  /// What `f` is now, for a message: `N/m`, or `not yet known`.
  std::string shown(const Form& f) const {
    Form r = solver_.reduce(f);
    if (r.wild) return "a number";
    if (!r.terms.empty()) return "of a unit not fixed yet";
    return format(r.constant);
  }

  /// a = b at the current site; a contradiction is reported once per site.
  void agree(const Form& a, const Form& b, const std::string& a_name, const std::string& b_name) {
    if (solver_.unify(a, b)) return;
    // `b_name` may say what it is already: "its unit {deg} is rad"
    report(b_name.find(" is ") != std::string::npos ? fmt::format("{} is {}, {}", a_name, shown(a), b_name)
                                                    : fmt::format("{} is {}, {} is {}", a_name, shown(a), b_name, shown(b)));
  }

  void not_si(const ir::DeclaredUnit& u, const char* what, const std::string& name) {
    if (!reported_.insert(loc_key(u.loc)).second) return;  // a vector output's columns share it
    diags_.error(u.loc,
                 fmt::format("{} `{}` is computed and written in SI units, and {{{}}} is not one ({} in SI)", what,
                             name, u.unit.text, format(u.unit.dimension)),
                 fmt::format("declare it {{{}}}, or write the conversion in its value", format(u.unit.dimension)));
  }

  void report(const std::string& detail) {
    if (!reported_.insert(loc_key(site_.loc)).second) return;
    auto& d = diags_.error(site_.loc, fmt::format("the units of {} do not agree: {}", site_.what, detail),
                           !site_.hint.empty()
                               ? site_.hint
                               : "each side's unit follows, through the bond graph, from the units the model "
                                 "declares: check those; `mbgc --units report` lists what each parameter was "
                                 "inferred to be");
    // the declared units the two sides rest on, and those the site reads
    std::unordered_set<int> read(solver_.last_reasons().begin(), solver_.last_reasons().end());
    for (const Expr& e : site_.exprs) ir::collect_params(e, read);
    std::vector<int> ids(read.begin(), read.end());
    std::sort(ids.begin(), ids.end());
    for (int p : ids) {
      const ir::Parameter& par = g_.params[static_cast<std::size_t>(p)];
      if (par.unit) d.notes.push_back({par.unit->loc, fmt::format("`{}` is declared {}", par.name, par.unit->unit.text)});
    }
  }

  /// The dimension of `e`; an addition of things that disagree is reported at the site.
  Form form(const Expr& e) { return visit(e); }

  Form visit(const Expr& e) {
    const ir::Node* n = e.get();
    auto hit = memo_.find(n);
    if (hit != memo_.end()) return hit->second;
    Form f = compute(e);
    memo_.emplace(n, f);
    return f;
  }

  /// Two operands that must agree (a sum, min, atan2); the first's form.
  Form both(const Expr& a, const Expr& b) {
    Form fa = visit(a), fb = visit(b);
    if (fa.wild) return fb;
    if (fb.wild) return fa;
    if (!solver_.unify(fa, fb))
      report(fmt::format("`{}` is {} and `{}` is {}", text(a), shown(fa), text(b), shown(fb)));
    return fa;
  }

  /// What a function of a number returns (see Form).
  static Form function_result() { return Form::function_value(); }

  Form none_argument(const Expr& a, const char* fn) {
    Form fa = visit(a);
    if (!fa.wild && !solver_.require_none(fa))
      report(fmt::format("the argument of {} is {}, where a number (or an angle) is read", fn, shown(fa)));
    return function_result();
  }

  Form compute(const Expr& e) {
    const ir::Node* n = e.get();
    switch (n->op) {
      case Op::Const: return n->id >= 0 ? Form::known(literal_dimension(n->id)) : Form::number();  // `2 {mm}`: m
      case Op::Param: return param(static_cast<std::size_t>(n->id));
      case Op::Var: return Form::unknown(var_unknown(n->id));
      case Op::Time: return Form::known(dim::time());
      case Op::Neg: return visit(n->args[0]);
      case Op::Add: return both(n->args[0], n->args[1]);
      case Op::Sub: return both(n->args[0], n->args[1]);
      case Op::Mul:
      case Op::Div: {
        Form a = visit(n->args[0]), b = visit(n->args[1]);
        Rational k = n->op == Op::Mul ? 1 : -1;
        if (a.wild && b.wild) return Form::number();
        if (a.function) return power(b, k);  // `cos(q) * L`
        if (b.function) return a;
        if (a.wild || b.wild) {
          Form f = a.wild ? power(b, k) : a;
          return combine(f, Form::unknown(solver_.fresh()), 1);
        }
        return combine(a, b, k);
      }
      case Op::Pow: {
        Form a = visit(n->args[0]);
        double x = 0;
        if (ir::is_const(n->args[1], &x)) {
          if (a.wild || !a.is_small()) return Form::number();
          if (auto k = small_rational(x)) {
            Form f = power(a, *k);
            return f.is_small() ? f : Form::number();
          }
        }
        none_argument(n->args[0], "a power whose exponent is not a small fraction");
        return none_argument(n->args[1], "an exponent");
      }
      case Op::Der: return combine(visit(n->args[0]), Form::known(dim::time()), -1);
      case Op::Call: break;
    }
    const ir::Operands& a = n->args;
    switch (n->fn) {
      case Fn::Sin: return none_argument(a[0], "sin");
      case Fn::Cos: return none_argument(a[0], "cos");
      case Fn::Tan: return none_argument(a[0], "tan");
      case Fn::Asin: return none_argument(a[0], "asin");
      case Fn::Acos: return none_argument(a[0], "acos");
      case Fn::Atan: return none_argument(a[0], "atan");
      case Fn::Sinh: return none_argument(a[0], "sinh");
      case Fn::Cosh: return none_argument(a[0], "cosh");
      case Fn::Tanh: return none_argument(a[0], "tanh");
      case Fn::Exp: return none_argument(a[0], "exp");
      case Fn::Log: return none_argument(a[0], "log");
      case Fn::Atan2:
        both(a[0], a[1]);
        return function_result();
      case Fn::Sqrt: {
        Form f = visit(a[0]);
        return f.wild ? f : power(f, Rational(1, 2));
      }
      case Fn::Abs:
      case Fn::Frozen: return visit(a[0]);
      case Fn::Sign:
      case Fn::Step:
      case Fn::Select: visit(a[0]); return function_result();
      case Fn::Min:
      case Fn::Max: return both(a[0], a[1]);
    }
    return Form::number();
  }

  const ir::EquationSystem& sys_;
  const ir::BondGraph& g_;
  ir::Diagnostics& diags_;
  Solver solver_;
  ir::Namer names_;
  Site site_;
  std::unordered_map<const ir::Node*, Form> memo_;
  /// The quantities the multibody layer states, with their angles (the
  /// solver counts a radian as 1, as SI does: `hinge.rate` is 1/s to it).
  std::unordered_map<const ir::Node*, Dimension> with_angle_;

  /// A parameter's dimension as the model gives it: declared, else stated by the multibody layer.
  static std::optional<Dimension> given_dimension(const ir::Parameter& p) {
    return p.unit ? std::optional<Dimension>(p.unit->unit.dimension) : p.stated;
  }

  /// `d`, the inferred dimension of `value`, as a user reads it: with the
  /// angle of the quantity or parameter it is (`output w = hinge.rate` is
  /// rad/s); else as inferred (an angular rate of a plain bond graph reads 1/s).
  Dimension shown_with_angle(const Expr& value, const Dimension& d) const {
    std::optional<Dimension> stated;
    if (auto it = with_angle_.find(value.get()); it != with_angle_.end()) stated = it->second;
    if (value->op == Op::Param) stated = given_dimension(g_.params[static_cast<std::size_t>(value->id)]);
    return stated && stated->without_angle() == d ? *stated : d;
  }
  std::unordered_set<long long> reported_;
  /// Of the nodes whose equations are not read: those the multibody layer
  /// made, and elements whose modulus is a number (`I m = 1`: the equation
  /// `p = f` has lost the 1, and the kg with it).
  std::unordered_set<long long> unread_locs_;
  std::unordered_set<long long> junction_locs_;
};

}  // namespace

UnitReport check_units(const ir::EquationSystem& sys, ir::Diagnostics& diags, bool strict) {
  return Checker(sys, diags).run(strict);
}

namespace {

std::string described(const std::optional<ir::DeclaredUnit>& declared, const std::optional<Dimension>& stated,
                      const std::optional<Dimension>& d) {
  if (declared) return fmt::format("{:<14} declared", declared->unit.text);
  if (stated) return fmt::format("{:<14} stated by the multibody layer", format(*stated));
  if (d) return fmt::format("{:<14} inferred", format(*d));
  return "?              not fixed by the model";
}

}  // namespace

void record_dimensions(ir::BondGraph& g, const UnitReport& report) {
  for (std::size_t i = 0; i < g.params.size() && i < report.params.size(); ++i) g.params[i].dimension = report.params[i];
  for (std::size_t i = 0; i < g.outputs.size() && i < report.outputs.size(); ++i) g.outputs[i].dimension = report.outputs[i];
}

std::string print_report(const ir::BondGraph& g, const UnitReport& report) {
  std::string out = "parameters:\n";
  for (std::size_t i = 0; i < g.params.size(); ++i)
    out += fmt::format("  {:<24} {}\n", g.params[i].name, described(g.params[i].unit, g.params[i].stated, report.params[i]));
  out += "outputs:\n";
  for (std::size_t i = 0; i < g.outputs.size(); ++i)
    out += fmt::format("  {:<24} {}\n", g.outputs[i].name, described(g.outputs[i].unit, std::nullopt, report.outputs[i]));
  return out;
}

}  // namespace mbgc::units
