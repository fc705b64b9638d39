// multibody/shapes.cpp — shapes and constants known from the text.
#include "multibody/shapes.hpp"

#include "multibody/collect.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <ranges>
#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

using ir::AstExpr;

std::optional<Shape> Constants::shape_of(const AstExpr& e, int depth) const {
  if (depth > 50) return std::nullopt;
  auto sub = [&](std::size_t k) { return k < e.args.size() ? shape_of(*e.args[k], depth + 1) : std::nullopt; };
  switch (e.kind) {
    case AstExpr::Kind::Number: return Shape{};
    case AstExpr::Kind::Name: {
      if (e.name == "t" || e.name == "pi") return Shape{};
      auto p = params_.find(e.name);
      if (p == params_.end() || !p->second) return std::nullopt;
      return shape_of(*p->second, depth + 1);
    }
    case AstExpr::Kind::Unary: return sub(0);
    case AstExpr::Kind::String: return std::nullopt;
    case AstExpr::Kind::Index: return Shape{};
    case AstExpr::Kind::Binary: {
      auto a = sub(0), b = sub(1);
      if (!a || !b) return std::nullopt;
      switch (e.op) {
        case '+':
        case '-':
          if (a->scalar()) return b;
          if (b->scalar() || *a == *b) return a;
          return std::nullopt;
        case '*':
          if (a->scalar()) return b;
          if (b->scalar()) return a;
          if (a->cols == b->rows) return Shape{a->rows, b->cols};
          return std::nullopt;
        case '/': return a;
        case '^': return Shape{};
      }
      return std::nullopt;
    }
    case AstExpr::Kind::List: {
      if (e.args.empty()) return std::nullopt;
      auto first = sub(0);
      if (!first) return std::nullopt;
      for (std::size_t k = 1; k < e.args.size(); ++k)
        if (auto s = sub(k); !s || !(*s == *first)) return std::nullopt;
      if (first->scalar()) return Shape{static_cast<int>(e.args.size()), 1};
      if (first->cols == 1) return Shape{static_cast<int>(e.args.size()), first->rows};
      if (first->rows == 1) return Shape{static_cast<int>(e.args.size()), first->cols};
      return std::nullopt;
    }
    case AstExpr::Kind::Call: {
      static const std::set<std::string> scalar_fns = {
          "sin", "cos",  "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",      "exp", "log",
          "sqrt", "abs", "sign", "min", "max",  "step", "ramp",  "sine", "dot",  "heaviside", "select", "norm"};
      const std::string& f = e.name;
      if (scalar_fns.count(f)) return Shape{};
      auto count = [&](std::size_t k) -> std::optional<int> {
        if (k >= e.args.size() || e.args[k]->kind != AstExpr::Kind::Number) return std::nullopt;
        double n = e.args[k]->number;
        if (n < 1 || n > 1000 || n != static_cast<int>(n)) return std::nullopt;
        return static_cast<int>(n);
      };
      if (f == "diag") return Shape{static_cast<int>(e.args.size()), static_cast<int>(e.args.size())};
      if (f == "eye") {
        if (auto n = count(0)) return Shape{*n, *n};
        return std::nullopt;
      }
      if (f == "zeros") {
        auto r = count(0);
        auto c = e.args.size() > 1 ? count(1) : std::optional<int>(1);
        if (r && c) return Shape{*r, *c};
        return std::nullopt;
      }
      if (f == "frozen") return sub(0);
      if (f == "transpose") {
        auto a = sub(0);
        if (a) return Shape{a->cols, a->rows};
        return std::nullopt;
      }
      if (f == "cross" || f == "bryant") return Shape{3, 1};
      if (f == "skew" || f == "rotq" || f == "rot_axis_angle") return Shape{3, 3};
      if (f == "quat_rate") return Shape{4, 3};
      if (f == "quat_mul" || f == "quat_conj" || f == "quat_axis_angle" || f == "quat_arc") return Shape{4, 1};
      return std::nullopt;
    }
  }
  return std::nullopt;
}

/// (ir::constant_value, with a parameter's definition evaluated in turn)
std::optional<double> Constants::constant_of(const AstExpr& e, int depth) const {
  return ir::constant_value(e, rules(false), depth);
}

std::optional<double> Constants::drawn_number(const AstExpr& e, int depth) const {
  return ir::constant_value(e, rules(true), depth);
}

std::optional<std::array<double, 3>> Constants::constant_point(const AstExpr& e, int depth) const {
  if (depth > 50) return std::nullopt;
  if (e.kind == AstExpr::Kind::Name) {
    auto p = params_.find(e.name);
    if (p == params_.end() || !p->second) return std::nullopt;
    return constant_point(*p->second, depth + 1);
  }
  if (e.kind != AstExpr::Kind::List || e.args.size() != 3) return std::nullopt;
  std::array<double, 3> out{};
  for (std::size_t k = 0; k < 3; ++k) {
    auto v = constant_of(*e.args[k]);
    if (!v) return std::nullopt;
    out[k] = *v;
  }
  return out;
}

ir::ConstantRules Constants::rules(bool functions) const {
  ir::ConstantRules r;
  r.functions = functions;
  r.max_depth = kMaxDepth;
  r.name = [this, functions](const AstExpr& name, int depth) -> std::optional<double> {
    auto p = params_.find(name.name);
    if (p == params_.end() || !p->second) return std::nullopt;
    return ir::constant_value(*p->second, rules(functions), depth + 1);
  };
  return r;
}

bool Constants::mentions_time(const AstExpr& e) {
  if (e.kind == AstExpr::Kind::Name && e.name == "t") return true;
  for (const auto& a : e.args)
    if (a && mentions_time(*a)) return true;
  return false;
}

/// Reports a setting whose shape is known and wrong, or that depends on time.
void Collector::check_shape(const AstExpr& value, const std::string& what, const Expected& want, bool constant) {
  if (constant && Constants::mentions_time(value)) {
    diags_.error(value.loc, fmt::format("{} depends on time", what),
                 "body, joint and gravity settings are constants (parameters of the bond graph's elements); a "
                 "time-varying load is a joint's torque or force, or a force element");
    return;
  }
  auto got = constants_.shape_of(value);
  if (!got || *got == want.shape) return;
  diags_.error(value.loc, fmt::format("{} is {}, but it must be {}", what, got->text(), want.shape.text()), want.how);
}

}  // namespace mbgc::multibody::detail
