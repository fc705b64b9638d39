// multibody/modal_body.cpp — bodies from modal-data files.
#include "multibody/modal_body.hpp"
#include "multibody/drawing.hpp"
#include "multibody/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <ranges>
#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

std::map<std::string, std::array<double, 3>> ModalBody::points() const {
  std::map<std::string, std::array<double, 3>> out;
  for (const auto& [name, p] : data_->points) out[name] = p.position;
  return out;
}

Eta ModalBody::split(const std::function<E(int)>& eta) const {
  Eta out;
  for (int i = 0; i < count(); ++i) out.y.push_back(eta(i));
  return out;
}

void ModalBody::params(const FieldParams& fp) const {
  const Build& B = fp.B;
  const ModalSym n(fp.decl.name);
  const flex::ModalData& d = *data_;
  const flex::ModalMassTerms t = flex::modal_mass_terms(d);
  fp.param(n.mass(), B.num(d.mass_kg));
  fp.param(n.first_moment(), B.vec(d.first_moment_kg_m[0], d.first_moment_kg_m[1], d.first_moment_kg_m[2]));
  fp.param(n.J0(), matrix_param(B, d.inertia_kg_m2));
  // what the joints' code reads of every body: the reference point is the frame origin
  fp.param(n.com(), B.vec(0, 0, 0));
  fp.param(n.inertia(), B.ref(n.J0()));
  fp.param(n.mean(), matrix_param(B, d.mean_kg));
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = i; j < 3; ++j) {
      if (!all_zero(t.J1[i][j])) fp.param(n.J1(i, j), vector_param(B, t.J1[i][j][0]));
      if (!all_zero(t.J2[i][j])) fp.param(n.J2(i, j), matrix_param(B, t.J2[i][j]));
    }
  for (std::size_t i = 0; i < 3; ++i) {
    if (!all_zero(t.coupling[i])) fp.param(n.coupling(i), vector_param(B, t.coupling[i][0]));
    if (!all_zero(t.coupling_eta[i])) fp.param(n.coupling_eta(i), matrix_param(B, t.coupling_eta[i]));
  }
  fp.param(n.modal_mass(), matrix_param(B, t.modal_mass));
  // stiffness_scale = k: the same body with its Young's modulus times k (the modes and their mass stay)
  E stiffness = matrix_param(B, d.stiffness);
  if (E k = body_term(fp.decl, modal_setting::stiffness_scale)) stiffness = B.op('*', k, stiffness);
  fp.param(n.stiffness(), stiffness);
  fp.param(n.damping(), modal_damping(B, body_term(fp.decl, beam_setting::damping), d.count, n.stiffness(), n.modal_mass()));
  for (const auto& [pt, node] : d.points) {
    fp.param(n.shape(pt), matrix_param(B, node.shape));
    fp.param(n.slope(pt), matrix_param(B, node.slope));
  }
}

/// s(eta) = int r0 dm + C eta.
E ModalBody::first_moment(const Build& B, const FlexibleSym& body, const Eta& modes) const {
  const std::vector<E>& eta = modes.y;
  const ModalSym n(body);
  std::vector<E> s;
  for (int i = 0; i < 3; ++i) s.push_back(B.op('+', B.at(B.ref(n.first_moment()), i + 1), row_dot(B, n.mean(), i, eta)));
  return B.list(s);
}

Rows ModalBody::translation_coupling(const Build& B, const FlexibleSym& body, const Eta&) const {
  const flex::ModalData& d = *data_;
  const ModalSym n(body);
  std::vector<std::vector<E>> m(3);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < d.count; ++k) m[static_cast<std::size_t>(i)].push_back(idx2(B, B.ref(n.mean()), i + 1, k + 1));
  return m;
}

Rows ModalBody::mass_matrix(const Build& B, const FlexibleSym& body, const Eta& modes) const {
  const std::vector<E>& eta = modes.y;
  const ModalSym n(body);
  const std::size_t ne = eta.size(), N = 6 + ne;
  const flex::ModalMassTerms t = flex::modal_mass_terms(*data_);
  std::vector<std::vector<E>> M(N, std::vector<E>(N, B.num(0)));
  for (std::size_t k = 0; k < 3; ++k) M[k][k] = B.ref(n.mass());
  put_first_moment(B, M, first_moment(B, n, modes));
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = i; j < 3; ++j) {
      E J = idx2(B, B.ref(n.J0()), static_cast<int>(i) + 1, static_cast<int>(j) + 1);
      if (!all_zero(t.J1[i][j])) J = B.op('+', J, B.dot(B.ref(n.J1(i, j)), B.list(eta)));
      if (!all_zero(t.J2[i][j])) J = B.op('+', J, quadratic(B, n.J2(i, j), eta, eta));
      M[3 + i][3 + j] = M[3 + j][3 + i] = J;
    }
  auto tc = translation_coupling(B, n, modes);
  for (std::size_t l = 0; l < ne; ++l) {
    for (std::size_t i = 0; i < 3; ++i) {
      M[i][6 + l] = M[6 + l][i] = tc[i][l];
      E c = nullptr;
      if (!all_zero(t.coupling[i])) c = B.at(B.ref(n.coupling(i)), static_cast<int>(l) + 1);
      if (!all_zero(t.coupling_eta[i])) {
        E more = row_dot(B, n.coupling_eta(i), static_cast<int>(l), eta, /*transposed=*/true);
        c = c ? B.op('+', c, more) : more;
      }
      if (c) M[3 + i][6 + l] = M[6 + l][3 + i] = c;
    }
    for (std::size_t k = 0; k < ne; ++k)
      M[6 + k][6 + l] = idx2(B, B.ref(n.modal_mass()), static_cast<int>(k) + 1, static_cast<int>(l) + 1);
  }
  return M;
}

/// A node's deflected position (P = its shapes, at = its undeformed position) or small rotation (P = its slopes).
E ModalBody::node(const Build& B, const Sym& P, std::array<double, 3> at, const std::vector<E>& eta) {
  std::vector<E> v;
  for (int i = 0; i < 3; ++i) {
    E moved = row_dot(B, P, i, eta);
    v.push_back(at[static_cast<std::size_t>(i)] == 0 ? moved : B.op('+', B.num(at[static_cast<std::size_t>(i)]), moved));
  }
  return B.list(v);
}

/// A mode's limit: where it alone turns one of the file's nodes by the slope limit.
Limits ModalBody::limits(const std::string& body) const {
  const flex::ModalData& d = *data_;
  Limits limits;
  for (int k = 0; k < d.count; ++k) {
    double peak = 0;
    for (const auto& [pt, node] : d.points) {
      double r2 = 0;
      for (const auto& row : node.slope) r2 += row[static_cast<std::size_t>(k)] * row[static_cast<std::size_t>(k)];
      peak = std::max(peak, std::sqrt(r2));
    }
    limits.push_back(
        {peak > 0 ? slope_limit_rad / peak : std::numeric_limits<double>::max(),
         fmt::format("mode {} of modal body `{}` (from {}) turns one of its nodes by more than {:g} rad, beyond the "
                     "small rotations of a linear modal model (`slope_limit`). Likely cause: an instability - a load "
                     "beyond what the linear model holds, or a spin faster than the body's first natural frequency "
                     "(a modal-data body has no geometric stiffness)",
                     k + 1, body, d.path, slope_limit_rad)});
  }
  return limits;
}

E ModalBody::point(const Build& B, const FlexibleSym& body, const std::string& pt, const Eta& eta) const {
  return node(B, ModalSym(body).shape(pt), data_->points.at(pt).position, eta.y);
}

E ModalBody::slope(const Build& B, const FlexibleSym& body, const std::string& pt, const Eta& eta) const {
  return node(B, ModalSym(body).slope(pt), {0, 0, 0}, eta.y);
}

/// The file's full matrices.
void ModalBody::stiffness_and_damping(const Build& B, const FlexibleSym& body, Rows& K, Rows& D) const {
  const int ne = count();
  const ModalSym n(body);
  for (int i = 0; i < ne; ++i)
    for (int j = 0; j < ne; ++j) {
      K[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = idx2(B, B.ref(n.stiffness()), i + 1, j + 1);
      D[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = idx2(B, B.ref(n.damping()), i + 1, j + 1);
    }
}

}  // namespace mbgc::multibody::detail

namespace mbgc::multibody::detail {

/// The file gives the field at its nodes only: each node is drawn as a
/// small octahedron its modes move, and the nodes are joined by bars along
/// the shortest tree through them (Prim), each end moving with its node.
ir::Drawing ModalBody::drawing(double scale) const {
  ir::Drawing d;
  d.shape = ir::Drawing::Shape::Mesh;
  std::vector<const flex::ModalPoint*> nodes;
  double extent = 0;
  for (const auto& [name, p] : data_->points) {
    nodes.push_back(&p);
    for (double c : p.position) extent = std::max(extent, std::abs(c));
  }
  const double r = 0.04 * (extent > 0 ? extent : scale);
  std::vector<const flex::ModalPoint*> owner;  // per vertex: the node whose motion it follows
  for (const flex::ModalPoint* p : nodes) {
    add_octahedron(d, p->position, r);
    owner.resize(d.vertices.size() / 3, p);
  }
  auto distance = [](const flex::ModalPoint* p, const flex::ModalPoint* q) {
    double s = 0;
    for (std::size_t k = 0; k < 3; ++k) s += (p->position[k] - q->position[k]) * (p->position[k] - q->position[k]);
    return s;
  };
  std::vector<bool> joined(nodes.size(), false);
  if (!nodes.empty()) joined[0] = true;
  for (std::size_t added = 1; added < nodes.size(); ++added) {
    std::size_t from = 0, to = 0;
    double best = -1;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      for (std::size_t j = 0; j < nodes.size() && joined[i]; ++j)
        if (!joined[j] && (best < 0 || distance(nodes[i], nodes[j]) < best)) best = distance(nodes[i], nodes[j]), from = i, to = j;
    joined[to] = true;
    const std::size_t before = d.vertices.size() / 3;
    add_bar(d, nodes[from]->position, nodes[to]->position, r / 3);
    if (d.vertices.size() / 3 == before) continue;  // two nodes at one place: no bar
    owner.resize(before + 4, nodes[from]);
    owner.resize(before + 8, nodes[to]);
  }
  d.mode_shapes.assign(static_cast<std::size_t>(data_->count), std::vector<double>(d.vertices.size()));
  for (std::size_t v = 0; v < owner.size(); ++v)
    for (std::size_t k = 0; k < d.mode_shapes.size(); ++k)
      for (std::size_t c = 0; c < 3; ++c) d.mode_shapes[k][3 * v + c] = owner[v]->shape[c][k];
  return d;
}

}  // namespace mbgc::multibody::detail
