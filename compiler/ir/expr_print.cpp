// ir/expr_print.cpp — expressions as text: model syntax for dumps and
// diagnostics, C++ for generated code (see expr.hpp: to_string, to_cpp, the
// operation counts of CppOps and the named nodes of NamedNodes).
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "ir/expr.hpp"
#include "units/unit.hpp"

namespace mbgc::ir {
namespace {

// ---- printing ----------------------------------------------------------------------

enum Prec : int { kAdd = 1, kMul = 2, kUnary = 3, kPow = 4, kAtom = 5 };

struct Printed {
  std::string s;
  int prec = kAtom;
  bool neg_lead = false;  // text starts with a unary minus
};

class Printer {
 public:
  Printer(const Namer& names, bool cpp, CppOps* ops = nullptr, const NamedNodes* named = nullptr)
      : names_(names), cpp_(cpp), ops_(ops ? ops : &unused_), named_(named && *named ? named : nullptr) {}

  Printed print(const Expr& e) {
    if (!e) return {"<null>", kAtom, false};
    if (const std::string* name = named(e)) return {*name, kAtom, false};  // like a variable
    switch (e->op) {
      case Op::Const: {
        Printed p = constant_text(e->value);
        if (!cpp_ && e->id >= 0) p.s += " {" + units::format(units::literal_dimension(e->id)) + "}";  // `0.002 {m}`, in SI
        return p;
      }
      case Op::Param:
        return {names_.param ? names_.param(e->id) : fmt::format("p{}", e->id), kAtom, false};
      case Op::Var:
        return {names_.var ? names_.var(e->id) : fmt::format("v{}", e->id), kAtom, false};
      case Op::Time: return {names_.time, kAtom, false};
      case Op::Neg: {
        const Expr& x = e->args[0];
        Printed px = print(x);
        // -(a*b) == (-a)*b exactly, so print it as "-a*b" (a Mul-level text).
        // Not when the product starts with a NaN: "-nan" would read as nan.
        if ((x->op == Op::Mul || x->op == Op::Div) && px.prec == kMul && !px.neg_lead &&
            !starts_with_nan(x)) {
          // "-2.0 * x" is the literal -2.0 times x: no negation at run time
          if (!starts_with_literal(x)) ++ops_->neg;
          return {"-" + px.s, kMul, true};
        }
        if (x->op != Op::Const) ++ops_->neg;
        if (px.prec >= kUnary && !px.neg_lead) return {"-" + px.s, kUnary, true};
        return {"-(" + px.s + ")", kUnary, true};
      }
      case Op::Add: ++ops_->add; return binary(e, kAdd, " + ");
      case Op::Sub: ++ops_->add; return binary(e, kAdd, " - ");
      case Op::Mul: ++ops_->mul; return binary(e, kMul, cpp_ ? " * " : "*");
      case Op::Div: ++ops_->div; return binary(e, kMul, cpp_ ? " / " : "/");
      case Op::Pow: return cpp_ ? cpp_pow(e) : model_pow(e);
      case Op::Call: return cpp_ ? cpp_call(e) : model_call(e);
      case Op::Der:
        if (cpp_) return {"/*der*/ MBGC_DER_NOT_REMOVED(" + print(e->args[0]).s + ")", kAtom, false};
        return {"der(" + print(e->args[0]).s + ")", kAtom, false};
    }
    return {"<bad>", kAtom, false};
  }

 private:
  bool starts_with_nan(const Expr& product) const {
    const Expr* n = &product;
    while (((*n)->op == Op::Mul || (*n)->op == Op::Div) && !named(*n)) n = &(*n)->args[0];
    return (*n)->op == Op::Const && std::isnan((*n)->value) && !named(*n);
  }

  /// The product's text starts with a numeric literal (its leftmost factor is
  /// a constant, not printed by name; the printer never parenthesises the
  /// left operand of * or / when it is itself a product).
  bool starts_with_literal(const Expr& product) const {
    const Expr* n = &product;
    while (((*n)->op == Op::Mul || (*n)->op == Op::Div) && !named(*n)) n = &(*n)->args[0];
    return (*n)->op == Op::Const && !named(*n);
  }

  const std::string* named(const Expr& e) const { return named_ ? (*named_)(e) : nullptr; }

  Printed constant_text(double v) const {
    if (std::isnan(v))
      return {cpp_ ? "std::numeric_limits<double>::quiet_NaN()" : "nan", kAtom, false};
    if (std::isinf(v)) {
      std::string inf = cpp_ ? "std::numeric_limits<double>::infinity()" : "inf";
      if (v > 0) return {inf, kAtom, false};
      return {"-" + inf, kUnary, true};
    }
    std::string s = fmt::format("{}", v);
    if (cpp_ && s.find_first_of(".eE") == std::string::npos) s += ".0";
    if (v < 0) return {s, kUnary, true};
    return {s, kAtom, false};
  }

  // Left-associative binary operators: the right operand is parenthesised at
  // equal precedence (a - (b - c), a/(b*c), also a + (b + c) to keep the tree).
  Printed binary(const Expr& e, int p, const char* sep) {
    Printed l = print(e->args[0]);
    Printed r = print(e->args[1]);
    bool lp = l.prec < p;
    bool rp = r.prec <= p || r.neg_lead;
    std::string s = lp ? "(" + l.s + ")" : std::move(l.s);
    s += sep;
    s += rp ? "(" + r.s + ")" : r.s;
    return {std::move(s), p, !lp && l.neg_lead};
  }

  // ^ is right-associative and binds tighter than unary minus.
  Printed model_pow(const Expr& e) {
    Printed l = print(e->args[0]);
    Printed r = print(e->args[1]);
    bool lp = l.prec <= kPow || l.neg_lead;
    bool rp = r.prec < kPow || r.neg_lead;
    std::string s = lp ? "(" + l.s + ")" : std::move(l.s);
    s += "^";
    s += rp ? "(" + r.s + ")" : r.s;
    return {std::move(s), kPow, false};
  }

  Printed cpp_pow(const Expr& e) {
    const Expr &a = e->args[0], &b = e->args[1];
    double c = 0.0;
    bool leaf = a->op == Op::Var || a->op == Op::Param || a->op == Op::Time || named(a);
    if (leaf && is_const(b, &c) && (c == 2.0 || c == 3.0)) {
      ops_->mul += c == 2.0 ? 1 : 2;
      std::string x = print(a).s;
      return {c == 2.0 ? "(" + x + "*" + x + ")" : "(" + x + "*" + x + "*" + x + ")", kAtom, false};
    }
    ++ops_->call;
    return {"std::pow(" + print(a).s + ", " + print(b).s + ")", kAtom, false};
  }

  std::string arg_list(const Expr& e) {
    std::string s;
    for (std::size_t i = 0; i < e->args.size(); ++i) {
      if (i) s += ", ";
      s += print(e->args[i]).s;
    }
    return s;
  }

  Printed model_call(const Expr& e) {
    return {std::string(fn_name(e->fn)) + "(" + arg_list(e) + ")", kAtom, false};
  }

  Printed cpp_call(const Expr& e) {
    const char* f = nullptr;
    switch (e->fn) {
      case Fn::Sign: {
        // the argument is written twice: its operations count twice
        const CppOps before = *ops_;
        std::string x = print(e->args[0]).s;
        add_difference(*ops_, before);
        ops_->compare += 2;
        return {"((" + x + ") > 0.0 ? 1.0 : ((" + x + ") < 0.0 ? -1.0 : 0.0))", kAtom, false};
      }
      case Fn::Frozen:
        return print(e->args[0]);  // (its derivative was 0 where it mattered; its value is x)
      case Fn::Step:
      case Fn::Select:
        ++ops_->compare;
        return {"((" + print(e->args[0]).s + ") >= 0.0 ? 1.0 : 0.0)", kAtom, false};
      case Fn::Abs: f = "std::fabs"; break;
      case Fn::Min: f = "std::fmin"; break;
      case Fn::Max: f = "std::fmax"; break;
      default: break;
    }
    ++ops_->call;
    std::string name = f ? std::string(f) : "std::" + std::string(fn_name(e->fn));
    return {name + "(" + arg_list(e) + ")", kAtom, false};
  }

  /// ops += (ops - before), field by field: a text printed twice.
  static void add_difference(CppOps& ops, const CppOps& before) {
    ops.add += ops.add - before.add;
    ops.mul += ops.mul - before.mul;
    ops.div += ops.div - before.div;
    ops.neg += ops.neg - before.neg;
    ops.call += ops.call - before.call;
    ops.compare += ops.compare - before.compare;
  }

  const Namer& names_;
  bool cpp_;
  CppOps unused_;  // where the counts go when nobody asked for them
  CppOps* ops_;
  const NamedNodes* named_;
};

}  // namespace

std::string to_string(const Expr& e, const Namer& names) {
  return Printer(names, false).print(e).s;
}

std::string to_cpp(const Expr& e, const Namer& names, CppOps* ops) {
  return Printer(names, true, ops).print(e).s;
}

std::string to_cpp(const Expr& e, const Namer& names, const NamedNodes& named, CppOps* ops) {
  return Printer(names, true, ops, &named).print(e).s;
}

}  // namespace mbgc::ir
