// fe/mesh.cpp
#include "mesh.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <iterator>
#include <fstream>
#include <set>
#include <sstream>

#include "text_reader.hpp"

namespace mbgc::fe {

std::optional<Mesh> read_nodes(const std::string& path, int dofs_per_node, ir::SourceManager& sources,
                               ir::Diagnostics& diags) {
  TextReader in(sources, diags);
  if (!in.open(path, '#')) return std::nullopt;
  Mesh mesh;
  mesh.dofs_per_node = dofs_per_node;
  std::vector<Word> w;
  while (in.next_line(w)) {
    if (w.size() != 4) {
      diags.error(in.line_loc(), fmt::format("a node is `ID x y z`; this line has {} words", w.size()),
                  "one node per line: its whole-number ID and its coordinates in metres");
      return std::nullopt;
    }
    const auto id = in.integer(w[0], "the node ID", 0, 999'999'999'999LL);
    if (!id) return std::nullopt;
    Eigen::Vector3d x;
    for (int i = 0; i < 3; ++i) {
      const auto v = in.number(w[1 + i], "a coordinate");
      if (!v) return std::nullopt;
      x(i) = *v;
    }
    if (!mesh.index_of.emplace(*id, static_cast<int>(mesh.ids.size())).second) {
      diags.error(w[0].loc, fmt::format("node {} is defined twice", *id), "node IDs must be unique");
      return std::nullopt;
    }
    mesh.ids.push_back(*id);
    mesh.position.push_back(x);
    if (mesh.ids.size() > 50'000'000) {
      diags.error(w[0].loc, "more than 50 million nodes", "mbgc-reduce holds the model in memory; reduce it in parts");
      return std::nullopt;
    }
  }
  if (mesh.ids.empty()) {
    diags.error(in.end_loc(), fmt::format("`{}` has no nodes", path), "one node per line: `ID x y z`");
    return std::nullopt;
  }
  return mesh;
}

std::optional<Attachment> parse_attachment(const std::string& spec, bool interface, const Mesh& mesh,
                                           ir::Diagnostics& diags) {
  const char* option = interface ? "--interface" : "--point";
  const std::size_t eq = spec.find('=');
  Attachment a;
  a.interface = interface;
  a.name = spec.substr(0, eq);
  const bool name_ok = !a.name.empty() && (std::isalpha(static_cast<unsigned char>(a.name[0])) || a.name[0] == '_') &&
                       a.name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") == std::string::npos;
  if (eq == std::string::npos || !name_ok) {
    diags.error({}, fmt::format("{} `{}`: expected NAME=NODE or NAME=NODE,NODE,... with NAME an identifier", option, spec),
                fmt::format("e.g. {} root=1 (a node ID of the node file)", option));
    return std::nullopt;
  }
  // The IDs as written: NAME=ID,ID,... (an empty one is an error), or
  // NAME=@FILE, a node set: IDs separated by commas or white space.
  const std::string list = spec.substr(eq + 1);
  std::vector<std::string> words;
  if (!list.empty() && list[0] == '@') {
    std::ifstream in(list.substr(1));
    if (!in) {
      diags.error({}, fmt::format("{} {}: cannot read the node set `{}`", option, a.name, list.substr(1)),
                  "NAME=@FILE reads the node IDs from FILE, relative to the working directory");
      return std::nullopt;
    }
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::replace(text.begin(), text.end(), ',', ' ');
    std::istringstream ids(text);
    for (std::string w; ids >> w;) words.push_back(w);
    if (words.empty()) {
      diags.error({}, fmt::format("{} {}: the node set `{}` holds no node IDs", option, a.name, list.substr(1)),
                  "a node set lists node IDs of the node file, separated by commas or white space");
      return std::nullopt;
    }
  } else {
    for (std::size_t start = 0; start <= list.size();) {
      const std::size_t comma = std::min(list.find(',', start), list.size());
      words.push_back(list.substr(start, comma - start));
      start = comma + 1;
    }
  }
  std::set<int> seen;
  for (const std::string& text : words) {
    char* end = nullptr;
    const long long id = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || end != text.c_str() + text.size()) {
      diags.error({}, fmt::format("{} {}: `{}` is not a node ID", option, a.name, text), "node IDs are whole numbers from the node file");
      return std::nullopt;
    }
    const auto found = mesh.index_of.find(id);
    if (found == mesh.index_of.end()) {
      diags.error({}, fmt::format("{} {}: node {} is not in the node file", option, a.name, id),
                  fmt::format("the node file has {} nodes, IDs {} to {} in its order", mesh.ids.size(), mesh.ids.front(), mesh.ids.back()));
      return std::nullopt;
    }
    if (!seen.insert(found->second).second) {
      diags.error({}, fmt::format("{} {}: node {} is named twice", option, a.name, id));
      return std::nullopt;
    }
    a.nodes.push_back(found->second);
  }
  for (int n : a.nodes) a.at += mesh.position[static_cast<std::size_t>(n)];
  a.at /= static_cast<double>(a.nodes.size());

  // A single node of a beam or shell mesh carries its own rotation. Otherwise
  // the rotation comes from the nodes' translations, and they must not lie on
  // one line (a rotation about that line would move none of them).
  if (a.nodes.size() == 1 && mesh.has_rotations()) return a;
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  double size = 0;
  for (int n : a.nodes) {
    const Eigen::Vector3d r = mesh.position[static_cast<std::size_t>(n)] - a.at;
    spread += r * r.transpose();
    size = std::max(size, r.norm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(spread);
  if (a.nodes.size() < 3 || eig.eigenvalues()(1) <= 1e-12 * size * size * static_cast<double>(a.nodes.size())) {
    diags.error({}, fmt::format("{} {}: its {} node(s) lie on one line, so they cannot carry a rotation", option, a.name, a.nodes.size()),
                mesh.has_rotations() ? "give one node (it has rotations) or at least three nodes not on one line"
                                     : "a mesh without rotational DOFs ties at least three nodes not on one line (a face) to the point");
    return std::nullopt;
  }
  return a;
}

}  // namespace mbgc::fe
