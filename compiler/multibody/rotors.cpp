// multibody/rotors.cpp — which bodies are rotors on their parents (rotors.hpp).
//
// Every test here reads the model as written and holds for any value of its
// parameters (a `--set` at run time cannot make a rotor lopsided): the axis
// is a literal coordinate axis of the body, the coordinates off it of the
// centre of mass, the joint point and every point are literal zeros, and the
// inertia's two entries across the axis are the same expression.
#include "multibody/rotors.hpp"

#include <array>
#include <map>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

using ir::AstExpr;

/// A number as written (or its negation), else nullopt.
std::optional<double> literal(const AstExpr& e) {
  if (e.kind == AstExpr::Kind::Number) return e.number;
  if (e.kind == AstExpr::Kind::Unary && e.args.size() == 1) {
    std::optional<double> x = literal(*e.args[0]);
    if (x) return e.op == '-' ? -*x : *x;
  }
  return std::nullopt;
}

bool literal_zero(const AstExpr* e) {
  if (!e) return true;  // an entry a diag() leaves out
  std::optional<double> x = literal(*e);
  return x && *x == 0;
}

/// The same expression, node for node.
bool same(const AstExpr& a, const AstExpr& b) {
  if (a.kind != b.kind || a.number != b.number || a.name != b.name || a.op != b.op || a.args.size() != b.args.size())
    return false;
  for (std::size_t k = 0; k < a.args.size(); ++k)
    if (!same(*a.args[k], *b.args[k])) return false;
  return true;
}

/// Entry k (0-based) of a 3-vector written as a list, else null.
const AstExpr* entry(const AstExpr& v, std::size_t k) {
  if (v.kind != AstExpr::Kind::List || v.args.size() != 3) return nullptr;
  return v.args[k].get();
}

/// The coordinate axis (0, 1, 2) a direction is along: one literal entry
/// not zero, the others literal zeros.
std::optional<std::size_t> axis_along(const std::array<std::optional<double>, 3>& d) {
  std::optional<std::size_t> along;
  for (std::size_t k = 0; k < 3; ++k) {
    if (!d[k]) return std::nullopt;
    if (*d[k] == 0) continue;
    if (along) return std::nullopt;
    along = k;
  }
  return along;
}
std::optional<std::size_t> coordinate_axis(const AstExpr& v) {
  std::array<std::optional<double>, 3> d;
  for (std::size_t k = 0; k < 3; ++k)
    if (const AstExpr* x = entry(v, k)) d[k] = literal(*x);
    else return std::nullopt;
  return axis_along(d);
}
std::optional<std::size_t> coordinate_axis(const std::vector<double>& v) {
  if (v.size() != 3) return std::nullopt;
  return axis_along({v[0], v[1], v[2]});
}

/// Whether point `p` (null: the body's origin) is on coordinate axis k.
bool on_axis(const AstExpr* p, std::size_t k) {
  if (!p) return true;
  for (std::size_t i = 0; i < 3; ++i) {
    if (i == k) continue;
    const AstExpr* x = entry(*p, i);
    if (!x || !literal_zero(x)) return false;
  }
  return true;
}

/// Entry (r, c) of an inertia written as diag(a, b, c) or as a 3 x 3 list;
/// `written` false where it is neither.
struct InertiaEntry {
  bool written = false;
  const AstExpr* value = nullptr;  // null: a zero diag() leaves out
};
InertiaEntry inertia_entry(const AstExpr& I, std::size_t r, std::size_t c) {
  if (I.kind == AstExpr::Kind::Call && I.name == "diag" && I.args.size() == 3)
    return {true, r == c ? I.args[r].get() : nullptr};
  if (I.kind == AstExpr::Kind::List && I.args.size() == 3 && I.args[r]->kind == AstExpr::Kind::List && I.args[r]->args.size() == 3)
    return {true, I.args[r]->args[c].get()};
  return {};
}

/// The inertia is the same for every turn about coordinate axis k: the
/// products of inertia zero, the two moments across the axis one expression.
bool axisymmetric(const AstExpr& I, std::size_t k) {
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t c = 0; c < 3; ++c) {
      const InertiaEntry e = inertia_entry(I, r, c);
      if (!e.written) return false;
      if (r != c && !literal_zero(e.value)) return false;
    }
  const std::size_t i = (k + 1) % 3, j = (k + 2) % 3;
  const AstExpr* a = inertia_entry(I, i, i).value;
  const AstExpr* b = inertia_entry(I, j, j).value;
  return a && b && same(*a, *b);
}

}  // namespace

void find_rotors(Model& m, std::string* report) {
  // joints and contacts on each body: a rotor has its own joint and nothing else
  std::map<std::string, int> attached;
  for (const Joint& j : m.joints) ++attached[j.a.body], ++attached[j.b.body];
  for (const Contact& c : m.contacts) attached[c.a.body] += 2, attached[c.b.body] += 2;
  const char* axis_names[] = {"x", "y", "z"};
  for (const Joint& j : m.joints) {
    if (!j.tree || j.kind != &revolute_joint() || !j.a_is_parent || j.strategy != Strategy::Coordinates) continue;
    Body& rotor = m.bodies.at(j.b.body);
    const Body& parent = m.bodies.at(j.a.body);
    if (!rotor.by_coordinates || rotor.placed_by != j.decl->name || !rotor.kind.turns() || rotor.kind.field() ||
        parent.kind.field() || attached[j.b.body] != 1)
      continue;
    // the axis in the rotor's frame
    std::optional<std::size_t> k;
    if (const ir::AstAttr* ax = given_attr(j, joint_setting::axis_b) ? given_attr(j, joint_setting::axis_b) : given_attr(j, joint_setting::axis))
      k = coordinate_axis(*ax->value);
    else
      k = coordinate_axis(joint_setting::axis.by_default.numbers());
    if (!k) continue;
    const ir::AstBody& d = *rotor.decl;
    bool on = on_axis(attr(d, body_setting::com).get(), *k);
    if (!j.b.point.empty()) on = on && on_axis(rotor.points.at(j.b.point).get(), *k);
    for (const auto& [name, p] : rotor.points) on = on && on_axis(p.get(), *k);
    const ir::AstExprPtr inertia = attr(d, body_setting::inertia);
    if (!on || !inertia || !axisymmetric(*inertia, *k)) continue;
    bool rolls = true;  // a tyre on it turns about the same axis
    for (const Tyre& t : m.tyres) {
      if (t.wheel.body != j.b.body) continue;
      const ir::AstAttr* ax = given_in(t.attrs, tyre_setting::axis);
      rolls = rolls && (ax ? coordinate_axis(*ax->value) : coordinate_axis(tyre_setting::axis.by_default.numbers())) == k;
    }
    if (!rolls) continue;
    rotor.rotor_joint = j.decl->name;
    if (report)
      *report += fmt::format("{}rotor `{}` on `{}` (joint `{}`): symmetric about its {} axis, its equations in a frame "
                             "without its spin",
                             report->empty() ? "" : "\n", j.b.body, j.a.body, j.decl->name, axis_names[*k]);
  }
}

}  // namespace mbgc::multibody::detail
