#include "codegen/drawings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

namespace mbgc::codegen {
namespace {

using ir::Drawing;

/// `HEAD{a, b, ...});` over several lines, `per_line` items each (a mesh's
/// vertices: one section of a beam's tube per line).
template <class T>
void braced(std::vector<CppStmt>& out, const std::string& head, const std::vector<T>& items, std::size_t per_line) {
  std::vector<std::string> texts;
  for (const T& x : items) texts.push_back(fmt::format("{}", x));
  initialiser_lines(out, head, texts, per_line, "});");
}

const char* shape_name(Drawing::Shape s) {
  switch (s) {
    case Drawing::Shape::Box: return "box";
    case Drawing::Shape::Cylinder: return "cylinder";
    case Drawing::Shape::Sphere: return "sphere";
    case Drawing::Shape::Mesh: return "mesh";
    case Drawing::Shape::Plane: return "plane";
    case Drawing::Shape::Prism: return "prism";
    case Drawing::Shape::Road: return "road";
  }
  return "box";
}

/// The statements that fill `v` with drawing d (one of `drawn`).
std::vector<CppStmt> fill(const Drawing& d, const std::vector<ir::DrawnBody>& drawn) {
  std::vector<CppStmt> out;
  out.push_back(CppStmt::line(fmt::format("v.name = \"{}\";", d.body)));
  out.push_back(CppStmt::line(fmt::format("v.shape = mbgrt::BodyVisual::Shape::{};", shape_name(d.shape))));
  for (const auto& [member, x] : {std::pair{"size", &d.size}, std::pair{"centre", &d.centre}, std::pair{"colour", &d.colour}})
    for (std::size_t k = 0; k < 3; ++k) out.push_back(CppStmt::line(fmt::format("v.{}[{}] = {};", member, k, (*x)[k])));
  if (d.surface) out.push_back(CppStmt::line("v.surface = true;"));
  std::vector<std::size_t> covers;  // the touching bodies a scene kept, by their index
  for (const std::string& body : d.covers)
    for (std::size_t i = 0; i < drawn.size(); ++i)
      if (!drawn[i].drawing->surface && drawn[i].drawing->body == body &&
          std::find(covers.begin(), covers.end(), i) == covers.end())
        covers.push_back(i);
  if (!covers.empty()) out.push_back(CppStmt::line(fmt::format("v.covers = {{{}}};  // the bodies touching it", fmt::join(covers, ", "))));
  if (!d.profile.empty()) braced(out, "v.profile.assign(", d.profile, 8);
  if (d.shape != Drawing::Shape::Mesh) return out;
  braced(out, "v.vertices.assign(", d.vertices, 12);
  braced(out, "v.triangles.assign(", d.triangles, 24);
  for (std::size_t k = 0; k < d.mode_shapes.size(); ++k) {
    out.push_back(CppStmt::line(fmt::format("// modal coordinate {}: each vertex's displacement per unit", k + 1)));
    braced(out, "v.mode_shapes.push_back(std::vector<double>", d.mode_shapes[k], 12);
  }
  return out;
}

}  // namespace

void add_drawing_methods(CppClass& c, const ir::ReducedSystem& s, CppFunction poses) {
  const std::vector<ir::DrawnBody>& drawn = s.graph.drawings;
  if (drawn.empty()) return;
  c.public_methods.push_back({"DRAWN BODIES (--animate): how many.", "std::size_t body_count() const override",
                              {CppStmt::line(fmt::format("return {};", drawn.size()))}});
  CppFunction visual{"How body i is drawn: its shape in body axes from the point body_poses gives.",
                     "mbgrt::BodyVisual body_visual(std::size_t i) const override",
                     {CppStmt::line("mbgrt::BodyVisual v;")}};
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    visual.body.push_back(CppStmt::line(fmt::format("if (i == {}) {{  // {}", i, drawn[i].drawing->body)));
    for (CppStmt& st : fill(*drawn[i].drawing, drawn)) {
      st.text = "  " + st.text;
      visual.body.push_back(std::move(st));
    }
    visual.body.push_back(CppStmt::line("}"));
  }
  visual.body.push_back(CppStmt::line("return v;"));
  c.public_methods.push_back(std::move(visual));
  c.public_methods.push_back(std::move(poses));
}

}  // namespace mbgc::codegen
