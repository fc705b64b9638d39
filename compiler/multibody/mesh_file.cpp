#include "multibody/mesh_file.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "ir/find_file.hpp"

namespace mbgc::multibody {
namespace {

/// A mesh this big is not a drawing any more: the simulator would carry it in its source.
constexpr std::size_t kMaxVertices = 200000;

}  // namespace

bool read_mesh_file(const std::string& name, const ir::SourceLoc& named_at, const std::vector<std::string>& search_dirs,
                    ir::SourceManager& sources, ir::Diagnostics& diags, ir::Drawing& d) {
  auto id = ir::read_named_file(name, named_at, search_dirs, sources, diags, "mesh file");
  if (!id) return false;
  const std::string& text = sources.file(*id).text;
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  auto fail = [&](int col, int length, const std::string& message, const std::string& hint) {
    diags.error({*id, number, col, std::max(length, 1)}, message, hint);
    return false;
  };
  while (std::getline(lines, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    if (!(words >> key) || key[0] == '#') continue;
    if (key == "v") {
      double x[3];
      for (double& c : x) {
        std::string w;
        words >> w;
        const char* end = w.data() + w.size();
        auto [ptr, ec] = std::from_chars(w.data(), end, c);
        if (w.empty() || ec != std::errc() || ptr != end || !std::isfinite(c)) {
          const auto col = static_cast<int>(line.find(w, 1)) + 1;
          return fail(w.empty() ? static_cast<int>(line.size()) + 1 : col, static_cast<int>(w.size()),
                      "a vertex is `v x y z`, three finite numbers (m)", "for example: v 0.1 0 -0.05");
        }
      }
      if (d.vertices.size() / 3 >= kMaxVertices)
        return fail(1, 1, fmt::format("the mesh has more than {} vertices", kMaxVertices),
                    "a drawing needs far fewer: simplify the mesh (for example with a decimation filter)");
      d.vertices.insert(d.vertices.end(), x, x + 3);
    } else if (key == "f") {
      std::vector<unsigned> face;
      std::string w;
      while (words >> w) {
        long index = 0;
        const std::string first = w.substr(0, w.find('/'));  // v, v/vt, v//vn, v/vt/vn
        auto [ptr, ec] = std::from_chars(first.data(), first.data() + first.size(), index);
        const long count = static_cast<long>(d.vertices.size() / 3);
        if (index < 0) index += count + 1;  // relative to the last vertex so far
        if (first.empty() || ec != std::errc() || ptr != first.data() + first.size() || index < 1 || index > count)
          return fail(static_cast<int>(line.find(w, 1)) + 1, static_cast<int>(w.size()),
                      fmt::format("face corner `{}` is not one of the {} vertices given so far", w, count),
                      "a face lists vertex numbers from 1 (or negative, counted back from the last vertex)");
        face.push_back(static_cast<unsigned>(index - 1));
      }
      if (face.size() < 3) return fail(1, 1, "a face has at least three corners", "write f 1 2 3");
      for (std::size_t k = 1; k + 1 < face.size(); ++k) d.triangles.insert(d.triangles.end(), {face[0], face[k], face[k + 1]});
    }  // other records (vn, vt, o, g, usemtl, s, ...) are not needed to draw the shape
  }
  if (d.triangles.empty()) {
    number = 1;
    return fail(1, 1, fmt::format("mesh file \"{}\" has no faces", name), "a Wavefront OBJ mesh lists `v x y z` vertices and `f a b c` faces");
  }
  return true;
}

}  // namespace mbgc::multibody
