#include "ir/constant.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <string>

namespace mbgc::ir {

namespace {

std::optional<double> scalar_function(const std::string& name, double x) {
  static const std::map<std::string, double (*)(double)> kFunctions = {
      {"sin", [](double v) { return std::sin(v); }},   {"cos", [](double v) { return std::cos(v); }},
      {"tan", [](double v) { return std::tan(v); }},   {"sqrt", [](double v) { return std::sqrt(v); }},
      {"atan", [](double v) { return std::atan(v); }}, {"abs", [](double v) { return std::abs(v); }},
      {"exp", [](double v) { return std::exp(v); }},   {"log", [](double v) { return std::log(v); }}};
  auto f = kFunctions.find(name);
  if (f == kFunctions.end()) return std::nullopt;
  return f->second(x);
}

std::optional<double> fail(const AstExpr& e, const ConstantRules& rules, NotConstant why) {
  if (rules.failed) rules.failed(e, why);
  return std::nullopt;
}

}  // namespace

std::optional<double> constant_value(const AstExpr& e, const ConstantRules& rules, int depth) {
  if (depth > rules.max_depth) return std::nullopt;
  switch (e.kind) {
    case AstExpr::Kind::Number: return e.number;
    case AstExpr::Kind::Name:
      if (rules.functions && e.name == "pi") return std::numbers::pi;
      return rules.name ? rules.name(e, depth) : std::nullopt;
    case AstExpr::Kind::Unary: {
      auto a = constant_value(*e.args[0], rules, depth + 1);
      if (a && e.op == '-') return -*a;
      return a;
    }
    case AstExpr::Kind::Binary: {
      auto a = constant_value(*e.args[0], rules, depth + 1);
      auto b = constant_value(*e.args[1], rules, depth + 1);
      if (!a || !b) return std::nullopt;
      switch (e.op) {
        case '+': return *a + *b;
        case '-': return *a - *b;
        case '*': return *a * *b;
        case '/':
          if (*b == 0) return fail(e, rules, NotConstant::division_by_zero);
          return *a / *b;
        case '^': return std::pow(*a, *b);
      }
      return std::nullopt;
    }
    case AstExpr::Kind::Call:
      if (rules.functions && e.args.size() == 1) {
        if (auto a = constant_value(*e.args[0], rules, depth + 1)) return scalar_function(e.name, *a);
        return std::nullopt;
      }
      return fail(e, rules, NotConstant::form);
    default: return fail(e, rules, NotConstant::form);
  }
}

}  // namespace mbgc::ir
