// fe/main.cpp — mbgc-reduce: Craig–Bampton reduction of an FE model to the
// modal-data file (.mbm) that mbgc reads as `flexible = modal("...")`.
//
//   mbgc-reduce --stiffness K.mtx --mass M.mtx --nodes nodes.txt --dofs-per-node 6
//               --interface root=1 --interface tip=41 --modes 4 -o arm.mbm
//
// See README ("Reduced FE bodies") and docs/modal_format.md.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fmt/format.h>
#include <iostream>

#include "craig_bampton.hpp"
#include "invariants.hpp"
#include "matrix_market.hpp"
#include "mbm_writer.hpp"
#include "mesh.hpp"

namespace {

constexpr int kMaxModes = 64;  // the modal-data format's limit

struct Options {
  std::string stiffness, mass, nodes, output, frame;
  int dofs_per_node = 6, modes = 0, keep = -1;
  std::vector<std::string> interfaces, points;
};

int reduce(const Options& o, const std::string& command_line) {
  using namespace mbgc;
  ir::SourceManager sources;
  sources.set_tool_name("mbgc-reduce");
  ir::Diagnostics diags(sources);
  auto fail = [&] {
    diags.render(std::cerr);
    return 1;
  };

  const auto mesh = fe::read_nodes(o.nodes, o.dofs_per_node, sources, diags);
  if (!mesh) return fail();
  fe::ReductionRequest request;
  request.normal_modes = o.modes;
  request.keep = o.keep;
  std::vector<fe::Attachment> points;
  for (const std::string& spec : o.interfaces)
    if (auto a = fe::parse_attachment(spec, true, *mesh, diags)) request.interfaces.push_back(*a);
  for (const std::string& spec : o.points)
    if (auto a = fe::parse_attachment(spec, false, *mesh, diags)) points.push_back(*a);
  if (diags.has_errors()) return fail();
  // names unique; a node in one interface only
  std::map<std::string, int> names;
  std::vector<std::string> node_owner(mesh->ids.size());
  for (const auto* list : {&request.interfaces, &points})
    for (const fe::Attachment& a : *list) {
      if (names.count(a.name)) {
        diags.error({}, fmt::format("`{}` is named twice (--interface and --point names share one list)", a.name));
        return fail();
      }
      names[a.name] = 0;
      if (!a.interface) continue;
      for (int n : a.nodes) {
        std::string& owner = node_owner[static_cast<std::size_t>(n)];
        if (!owner.empty()) {
          diags.error({}, fmt::format("node {} is in interfaces `{}` and `{}`", mesh->ids[static_cast<std::size_t>(n)], owner, a.name),
                      "an interface's nodes move rigidly with it, so a node can belong to one interface only");
          return fail();
        }
        owner = a.name;
      }
    }
  if (!o.frame.empty()) {
    request.frame = -1;
    for (std::size_t j = 0; j < request.interfaces.size(); ++j)
      if (request.interfaces[j].name == o.frame) request.frame = static_cast<int>(j);
    if (request.frame < 0) {
      diags.error({}, fmt::format("--frame {}: no interface has that name", o.frame), "the frame is attached to one of the --interface names");
      return fail();
    }
  }
  const long total = 6L * static_cast<long>(request.interfaces.size() - 1) + o.modes;
  const long kept = o.keep < 0 ? total : std::min<long>(o.keep, total);
  if (kept < 1) {
    diags.error({}, "the reduced body would have no modes", "add --modes N (fixed-interface modes) or a second --interface");
    return fail();
  }
  if (kept > kMaxModes) {
    diags.error({}, fmt::format("the reduced body would have {} modes; a modal-data file holds at most {}", kept, kMaxModes),
                "keep fewer with --keep N (the lowest after orthogonalisation)");
    return fail();
  }

  const auto stiffness = fe::read_matrix_market(o.stiffness, "stiffness matrix", mesh->dofs(), sources, diags);
  if (!stiffness) return fail();
  const auto mass = fe::read_matrix_market(o.mass, "mass matrix", mesh->dofs(), sources, diags);
  if (!mass) return fail();

  const auto reduction = fe::craig_bampton(*mesh, *stiffness, *mass, request, diags);
  if (!reduction) return fail();
  const fe::Attachment& frame = request.interfaces[static_cast<std::size_t>(request.frame)];
  const fe::Invariants inv = fe::inertia_invariants(*mesh, *mass, *stiffness, reduction->modes, frame.at);
  const Eigen::Vector3d& by_axis = inv.mass_by_axis;
  if (!(inv.mass > 0) || by_axis.maxCoeff() - by_axis.minCoeff() > 1e-9 * inv.mass) {
    diags.error({}, fmt::format("the mass matrix moves {:.9g} kg along x, {:.9g} kg along y and {:.9g} kg along z",
                                by_axis.x(), by_axis.y(), by_axis.z()),
                "a structural mass matrix moves the same mass whichever way it is translated; check --dofs-per-node and the DOF order");
    return fail();
  }

  std::vector<fe::NamedPoint> named;
  for (const auto* list : {&request.interfaces, &points})
    for (const fe::Attachment& a : *list) named.push_back({a.name, a.at - frame.at, fe::point_motion(*mesh, a, reduction->modes)});

  std::vector<std::string> comments = {
      "Written by mbgc-reduce (Craig-Bampton reduction, docs/modal_format.md):",
      "  " + command_line,
      fmt::format("{} nodes, {} DOFs per node; frame at interface `{}`, held (its origin: {:.9g} {:.9g} {:.9g} in the FE axes)",
                  mesh->ids.size(), mesh->dofs_per_node, frame.name, frame.at.x(), frame.at.y(), frame.at.z()),
      fmt::format("{} constraint modes + {} fixed-interface modes, orthogonalised; the lowest {} kept, "
                  "each scaled to a largest nodal translation of 1",
                  reduction->constraint_modes, o.modes, kept),
      inv.exact_directions ? "inertia invariants: exact from the mass matrix (M = M_s (x) I_3)"
                           : "inertia invariants: rigid-body and first-order terms exact from the mass matrix; "
                             "the deformation-dependent rest from lumped nodal masses"};
  for (long q = 0; q < kept; ++q)
    comments.push_back(fmt::format("mode {}: omega = {:.12g} rad/s ({:.9g} Hz)", q + 1, reduction->omega(q),
                                   reduction->omega(q) / (2 * M_PI)));
  if (!fe::write_mbm(o.output, comments, inv, named)) {
    diags.error({}, fmt::format("cannot write `{}`", o.output));
    return fail();
  }
  for (long q = 0; q < kept; ++q)
    std::cout << fmt::format("mode {:2}: omega = {:.12g} rad/s, f = {:.9g} Hz\n", q + 1, reduction->omega(q),
                             reduction->omega(q) / (2 * M_PI));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mbgc-reduce: Craig-Bampton reduction of an FE model to a modal-data file (.mbm) for mbgc"};
  Options o;
  app.add_option("--stiffness", o.stiffness, "stiffness matrix, Matrix Market (coordinate, symmetric or general)")->required();
  app.add_option("--mass", o.mass, "mass matrix, Matrix Market")->required();
  app.add_option("--nodes", o.nodes, "node file: `ID x y z` per line, in the matrices' DOF order")->required();
  app.add_option("--dofs-per-node", o.dofs_per_node, "3 (translations: solids) or 6 (and rotations: beams, shells)")
      ->check(CLI::IsMember({3, 6}));
  app.add_option("--interface", o.interfaces, "NAME=NODE[,NODE...] or NAME=@FILE (a node set): a joint's place; several nodes are tied rigidly to their centroid")
      ->required();
  app.add_option("--frame", o.frame, "the interface that carries the body frame (default: the first)");
  app.add_option("--modes", o.modes, "fixed-interface normal modes (eq. 2.222)")->check(CLI::Range(0, 100000));
  app.add_option("--keep", o.keep, "keep the lowest K modes after orthogonalisation (default: all)")->check(CLI::Range(1, 100000));
  app.add_option("--point", o.points, "NAME=NODE[,NODE...]: a place to measure or load, without constraint modes");
  app.add_option("-o,--output", o.output, "the modal-data file to write")->required();
  CLI11_PARSE(app, argc, argv);
  std::string command_line = "mbgc-reduce";
  for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
  return reduce(o, command_line);
}
