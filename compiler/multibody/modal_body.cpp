// multibody/modal_body.cpp — bodies from modal-data files.
#include "multibody/expander.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <ranges>
#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

bool Expander::all_zero(const flex::Matrix& m) {
  for (const auto& r : m)
    for (double x : r)
      if (x != 0) return false;
  return true;
}

ModalTerms Expander::modal_terms(const flex::ModalData& d) { return flex::modal_mass_terms(d); }

std::string Expander::axes(std::size_t i, std::size_t j) { return std::string(kAxes[i]) + kAxes[j]; }

void Expander::modal_params(const Build& B, const Body& body) {
  const std::string& n = body.decl->name;
  const flex::ModalData& d = *body.beam->modal;
  const ModalTerms t = modal_terms(d);
  param(B, n + ".mass", B.num(d.mass_kg));
  param(B, n + ".first_moment", B.vec(d.first_moment_kg_m[0], d.first_moment_kg_m[1], d.first_moment_kg_m[2]));
  param(B, n + ".J0", matrix_param(B, d.inertia_kg_m2));
  // what the joints' code reads of every body: the reference point is the frame origin
  param(B, n + ".com", B.vec(0, 0, 0));
  param(B, n + ".inertia", B.name(n + ".J0"));
  param(B, n + ".mean", matrix_param(B, d.mean_kg));
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = i; j < 3; ++j) {
      if (!all_zero(t.J1[i][j])) param(B, n + ".J1." + axes(i, j), vector_param(B, t.J1[i][j][0]));
      if (!all_zero(t.J2[i][j])) param(B, n + ".J2." + axes(i, j), matrix_param(B, t.J2[i][j]));
    }
  for (std::size_t i = 0; i < 3; ++i) {
    if (!all_zero(t.coupling[i])) param(B, n + ".coupling." + kAxes[i], vector_param(B, t.coupling[i][0]));
    if (!all_zero(t.coupling_eta[i])) param(B, n + ".coupling_eta." + kAxes[i], matrix_param(B, t.coupling_eta[i]));
  }
  param(B, n + ".modal_mass", matrix_param(B, t.modal_mass));
  param(B, n + ".stiffness", matrix_param(B, d.stiffness));
  modal_damping(B, n + ".damping", attr(*body.decl, "damping"), d.count, n + ".stiffness", n + ".modal_mass");
  for (const auto& [pt, node] : d.points) {
    param(B, n + "." + pt + ".shape", matrix_param(B, node.shape));
    param(B, n + "." + pt + ".slope", matrix_param(B, node.slope));
  }
}

/// s(eta) = int r0 dm + C eta.
E Expander::modal_first_moment(const Build& B, const std::string& n, const std::vector<E>& eta) const {
  std::vector<E> s;
  for (int i = 0; i < 3; ++i) s.push_back(B.op('+', B.at(B.name(n + ".first_moment"), i + 1), row_dot(B, n + ".mean", i, eta)));
  return B.list(s);
}

std::vector<std::vector<E>> Expander::modal_translation_coupling(const Build& B, const std::string& n, const flex::ModalData& d) const {
  std::vector<std::vector<E>> m(3);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < d.count; ++k) m[static_cast<std::size_t>(i)].push_back(idx2(B, B.name(n + ".mean"), i + 1, k + 1));
  return m;
}

std::vector<std::vector<E>> Expander::modal_mass_matrix(const Build& B, const std::string& n, const flex::ModalData& d,
                                              const std::vector<E>& eta) const {
  const std::size_t ne = eta.size(), N = 6 + ne;
  const ModalTerms t = modal_terms(d);
  std::vector<std::vector<E>> M(N, std::vector<E>(N, B.num(0)));
  for (std::size_t k = 0; k < 3; ++k) M[k][k] = B.name(n + ".mass");
  put_first_moment(B, M, modal_first_moment(B, n, eta));
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = i; j < 3; ++j) {
      E J = idx2(B, B.name(n + ".J0"), static_cast<int>(i) + 1, static_cast<int>(j) + 1);
      const std::string ij = axes(i, j);
      if (!all_zero(t.J1[i][j])) J = B.op('+', J, B.dot(B.name(n + ".J1." + ij), B.list(eta)));
      if (!all_zero(t.J2[i][j])) J = B.op('+', J, quadratic(B, n + ".J2." + ij, eta, eta));
      M[3 + i][3 + j] = M[3 + j][3 + i] = J;
    }
  auto tc = modal_translation_coupling(B, n, d);
  for (std::size_t l = 0; l < ne; ++l) {
    for (std::size_t i = 0; i < 3; ++i) {
      M[i][6 + l] = M[6 + l][i] = tc[i][l];
      const std::string axis = kAxes[i];
      E c = nullptr;
      if (!all_zero(t.coupling[i])) c = B.at(B.name(n + ".coupling." + axis), static_cast<int>(l) + 1);
      if (!all_zero(t.coupling_eta[i])) {
        E more = row_dot(B, n + ".coupling_eta." + axis, static_cast<int>(l), eta, /*transposed=*/true);
        c = c ? B.op('+', c, more) : more;
      }
      if (c) M[3 + i][6 + l] = M[6 + l][3 + i] = c;
    }
    for (std::size_t k = 0; k < ne; ++k)
      M[6 + k][6 + l] = idx2(B, B.name(n + ".modal_mass"), static_cast<int>(k) + 1, static_cast<int>(l) + 1);
  }
  return M;
}

/// A node's deflected position (what = "shape", at = its undeformed position) or small rotation ("slope").
E Expander::modal_point(const Build& B, const std::string& n, const std::string& pt, const char* what, std::array<double, 3> at,
              const std::vector<E>& eta) const {
  std::vector<E> v;
  for (int i = 0; i < 3; ++i) {
    E moved = row_dot(B, n + "." + pt + "." + what, i, eta);
    v.push_back(at[static_cast<std::size_t>(i)] == 0 ? moved : B.op('+', B.num(at[static_cast<std::size_t>(i)]), moved));
  }
  return B.list(v);
}

/// A mode's limit: where it alone turns one of the file's nodes by the slope limit.
std::vector<std::pair<double, std::string>> Expander::modal_file_limits(const std::string& n, const Beam& beam) {
  const flex::ModalData& d = *beam.modal;
  std::vector<std::pair<double, std::string>> limits;
  for (int k = 0; k < d.count; ++k) {
    double peak = 0;
    for (const auto& [pt, node] : d.points) {
      double r2 = 0;
      for (const auto& row : node.slope) r2 += row[static_cast<std::size_t>(k)] * row[static_cast<std::size_t>(k)];
      peak = std::max(peak, std::sqrt(r2));
    }
    limits.push_back(
        {peak > 0 ? beam.slope_limit_rad / peak : std::numeric_limits<double>::max(),
         fmt::format("mode {} of modal body `{}` (from {}) turns one of its nodes by more than {:g} rad, beyond the "
                     "small rotations of a linear modal model (`slope_limit`). Likely cause: an instability - a load "
                     "beyond what the linear model holds, or a spin faster than the body's first natural frequency "
                     "(a modal-data body has no geometric stiffness)",
                     k + 1, n, d.path, beam.slope_limit_rad)});
  }
  return limits;
}

}  // namespace mbgc::multibody::detail
