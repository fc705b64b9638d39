// multibody/spanning_tree.cpp — the spanning tree from ground, and the
// constraint strategy of the joints left to `auto`.
#include "multibody/spanning_tree.hpp"

#include "multibody/constraint_strategy.hpp"

#include <deque>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {

namespace {

class TreePlanner {
 public:
  TreePlanner(Model& m, ir::Diagnostics& diags, std::string* strategy_report)
      : m_(m), diags_(diags), strategy_report_(strategy_report) {}

  void run() {
    find_tree();
    choose_strategy();
    check_coordinates();
  }

 private:
  void find_tree();
  void mark_coordinate_bodies();
  void choose_strategy();
  struct Problem {
    ir::SourceLoc loc;
    std::string message, hint;
  };
  std::vector<Problem> coordinate_problems() const;
  void check_coordinates();

  Model& m_;
  ir::Diagnostics& diags_;
  std::string* strategy_report_;  // ExpandOptions::strategy_report
};

/// Whether joint coordinates hold `j` (not yet while its strategy is still `auto`).
bool in_coordinates(const Joint& j) {
  return j.strategy != Strategy::Auto && constraint_strategy(j.strategy).tree_coordinates();
}

/// A spanning tree from ground, breadth first: each body is placed by the
/// first joint that reaches it; the other joints close loops.
void TreePlanner::find_tree() {
  std::deque<std::string> queue{"ground"};
  while (!queue.empty()) {
    std::string from = queue.front();
    queue.pop_front();
    for (Joint& j : m_.joints) {
      if (j.tree) continue;
      bool forward = j.a.body == from, backward = j.b.body == from;
      if (!forward && !backward) continue;
      const std::string& child = forward ? j.b.body : j.a.body;
      if (m_.bodies.at(child).placed) continue;  // closes a loop: the runtime assembles it
      j.tree = true;
      j.a_is_parent = forward;
      Body& c = m_.bodies.at(child);
      c.placed = true;
      c.placed_by = j.decl->name;
      m_.tree_order.push_back(&j);
      queue.push_back(child);
    }
  }
  mark_coordinate_bodies();
}

/// Which bodies the tree joints move by joint coordinates (their joint's strategy).
void TreePlanner::mark_coordinate_bodies() {
  for (const Joint* j : m_.tree_order) {
    Body& c = m_.bodies.at(j->a_is_parent ? j->b.body : j->a.body);
    const std::string& parent = j->a_is_parent ? j->a.body : j->b.body;
    c.by_coordinates = in_coordinates(*j);
    c.tree_parent = c.by_coordinates && parent != "ground" ? parent : "";
  }
}

/// constraints = auto: joint coordinates when they can move every joint left
/// to auto (a tree, no particle a joint turns, ...), else multipliers.
void TreePlanner::choose_strategy() {
  std::vector<Joint*> open;
  for (Joint& j : m_.joints)
    if (j.strategy == Strategy::Auto) open.push_back(&j);
  if (open.empty()) return;
  for (Joint* j : open) j->strategy = Strategy::Coordinates;
  mark_coordinate_bodies();
  const std::vector<Problem> problems = coordinate_problems();
  std::string report;
  if (problems.empty()) {
    std::vector<std::string> cut;
    for (const Joint* j : open)
      if (!j->tree) cut.push_back("`" + j->decl->name + "`");
    report = cut.empty() ? std::string("constraints = auto: coordinates (the joints form a tree: joint coordinates as states, "
                                       "an ODE without constraint rows)")
                         : fmt::format("constraints = auto: coordinates on a spanning tree, with cut joint{} {} (their rows "
                                       "held at acceleration level by multipliers, Baumgarte-stabilised: an ODE)",
                                       cut.size() == 1 ? "" : "s", fmt::join(cut, ", "));
  } else {
    for (Joint* j : open) j->strategy = Strategy::Lagrange;
    mark_coordinate_bodies();
    report = fmt::format("constraints = auto: lagrange (multipliers, a DAE), because {}", problems.front().message);
  }
  if (strategy_report_) *strategy_report_ = report;
}

/// What keeps joint coordinates from moving a joint: a particle a joint would
/// turn, a flexible body held at an origin that moves, and rows-strategy
/// constraint rows (a CN) on a body that has no position states. (A joint
/// that closes a loop is a cut joint: its rows act through multipliers on the
/// tree, emit_joint.)
std::vector<TreePlanner::Problem> TreePlanner::coordinate_problems() const {
  std::vector<Problem> out;
  for (const Joint& j : m_.joints) {
    const ir::AstJoint& d = *j.decl;
    if (in_coordinates(j)) {
      for (const Side* s : {&j.a, &j.b})
        if (m_.bodies.at(s->body).kind.field() && s->point.empty() && !m_.bodies.at(s->body).kind.field()->origin_fixed()) {
          out.push_back({d.loc, fmt::format("joint `{}` holds the flexible body `{}` at its frame's origin, which moves with "
                                            "its modes: not implemented in joint coordinates",
                                            d.name, s->body),
                         fmt::format("declare a point of `{}` where the joint sits and name it (`{}.p`): its deflection "
                                     "and turn come from the modes there; or put the frame at a clamped root",
                                     s->body, s->body)});
          break;
        }
    }
    if (in_coordinates(j) && j.tree && !j.kind->moves_particles())
      for (const Side* s : {&j.a, &j.b})
        if (m_.bodies.at(s->body).kind.particle()) {
          const bool parent = (s == &j.a) == j.a_is_parent;
          if (parent)
            out.push_back({d.loc, fmt::format("joint `{}` hangs `{}` from the particle `{}`, which joint coordinates "
                                              "cannot do", d.name, (j.a_is_parent ? j.b : j.a).body, s->body),
                           fmt::format("a particle has no orientation for the joint's frame to turn with: give `{}` "
                                       "an inertia, or write constraints = lagrange or penalty for this model",
                                       s->body)});
          else
            out.push_back({d.loc, fmt::format("joint `{}` cannot move the particle `{}` by joint coordinates", d.name, s->body),
                           fmt::format("a particle has no angular-velocity junction for the joint's rotation rates to "
                                       "drive, so they would carry no inertia: give `{}` an inertia, or write "
                                       "constraints = lagrange or penalty for this model",
                                       s->body)});
          break;
        }
    if (!in_coordinates(j))
      for (const Side* s : {&j.a, &j.b})
        if (m_.bodies.at(s->body).by_coordinates) {
          out.push_back({d.loc, fmt::format("joint `{}` uses constraint rows, but `{}` moves by joint coordinates", d.name, s->body),
                         fmt::format("a constraintor CN acts through the rates of a body's position states, and `{}` has "
                                     "none (its pose is a function of joint `{}`'s coordinates): use one strategy for the "
                                     "whole model (constraints = lagrange, penalty or coordinates)",
                                     s->body, m_.bodies.at(s->body).placed_by)});
          break;
        }
  }
  return out;
}

void TreePlanner::check_coordinates() {
  for (const Problem& p : coordinate_problems()) diags_.error(p.loc, p.message, p.hint);
}

}  // namespace

void plan_tree(Model& m, ir::Diagnostics& diags, std::string* strategy_report) { TreePlanner(m, diags, strategy_report).run(); }

}  // namespace mbgc::multibody::detail
