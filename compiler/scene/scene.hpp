// scene/scene.hpp — model only what a scene needs.
//
// A scene (`scene tip { outputs = [tip_deflection]; modes = 2 }`) names the
// outputs a run needs and may fix top-level parameters (as `mbgc --set`).
// Two steps, one on each side of elaboration:
//   take_scenes   takes the scene statements out of the parsed program, and
//                 select_scene turns the chosen one's parameters into overrides;
//   prune_graph   on the flattened multibond graph, keeps what the scene's
//                 outputs can depend on and removes the rest.
//
// What can influence an output, in bond-graph terms: the variables its
// expression reads; the element or junction that owns each of them (a state's
// storage, both ends of a bond); everything joined to a kept node by a power
// bond (power flows both ways, so the whole connected structure can act on
// it); and the variables a kept node's law reads (modulation, signals: one
// way only). A part reached only the other way round (a filter driven by a
// signal from the kept mechanism) cannot act on the outputs and goes.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/graph.hpp"

namespace mbgc::scene {

/// The scenes declared in a program, by name, in declaration order.
std::vector<ir::AstScene> take_scenes(ir::AstProgram& program, ir::Diagnostics& diags);

struct SelectedScene {
  std::string name;
  ir::SourceLoc loc;
  std::vector<std::pair<std::string, ir::SourceLoc>> outputs;  ///< as written in `outputs = [...]`
  std::map<std::string, double> overrides;                     ///< parameters the scene fixes
};

/// The scene called `name` (nullopt, with an error, if none is or it is malformed).
std::optional<SelectedScene> select_scene(const std::vector<ir::AstScene>& scenes, const std::string& name,
                                          const ir::AstProgram& program, ir::Diagnostics& diags);

/// "the model declares no scene `x` (its scenes: `a`, `b`)", for --scene x.
std::string no_such_scene(const std::vector<ir::AstScene>& scenes, const std::string& name);

/// What prune_graph kept and removed (for `mbgc --explain-scene`).
struct SceneReport {
  std::string scene;
  std::vector<std::string> kept_outputs, removed_outputs;
  std::vector<std::string> removed_nodes;  ///< "rod3.m (I)" in graph order
  std::vector<std::string> removed_signals;
  std::vector<std::string> idle_parameters;  ///< read by nothing that is kept: removed
  int nodes_before = 0, nodes_after = 0, bonds_before = 0, bonds_after = 0, states_before = 0, states_after = 0;
};

/// Removes from `graph` every node, bond, signal, output and parameter the
/// scene's outputs cannot depend on. Reports an unknown output name as an error.
SceneReport prune_graph(ir::BondGraph& graph, const SelectedScene& scene, ir::Diagnostics& diags);

/// The report as text: what was removed, grouped by the model's top-level
/// names (bodies, joints, components), and how much smaller the graph is.
std::string explain(const SceneReport& report);

}  // namespace mbgc::scene
