// flex/modal_file.hpp — reads a modal-data file (`.mbm`): a flexible body
// reduced by an FE program to a few modes, given by its inertia invariants,
// modal stiffness and the modes at its attachment nodes.
//
// The format is documented in docs/modal_format.md. The reader checks every
// record (name, count of numbers, once only, all present) and reports what is
// wrong at the file's line and column, like an error in a model. The data is
// what the body's equations need; flexible-body expansion builds M(eta) from it.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "flex/beam_modes.hpp"
#include "ir/diagnostics.hpp"

namespace mbgc::flex {

/// A node of the reduced body: where joints and loads attach.
struct ModalPoint {
  std::array<double, 3> position{};  // undeformed, body axes, m
  Matrix shape;                      // 3 x n: translation per unit eta_k (column k)
  Matrix slope;                      // 3 x n: small rotation per unit eta_k
};

struct ModalData {
  std::string path;                   // as found (the model's directory or an -I directory)
  int count = 0;                      // n, the number of modal coordinates
  double mass_kg = 0;
  std::array<double, 3> first_moment_kg_m{};  // int r0 dm
  Matrix inertia_kg_m2;               // 3 x 3, about the frame origin, undeformed
  Matrix mean_kg;                     // 3 x n: C = int Phi dm
  std::vector<Matrix> moment_kg_m;    // n of 3 x 3: A_k = int r0 Phi_k^T dm
  std::vector<std::vector<Matrix>> product_kg;  // n x n of 3 x 3: B_kl = int Phi_k Phi_l^T dm (both triangles)
  Matrix stiffness;                   // n x n, N/m per unit eta
  std::map<std::string, ModalPoint> points;
};

/// The coefficients of a modal body's mass matrix M(eta), from the invariants
/// (docs/modal_format.md), for nu = [V; omega; eta'] in body axes:
///   J(eta)_ij      = J0_ij + J1[i][j] . eta + eta^T J2[i][j] eta
///   M_omega_i,eta_l = coupling[i]_l + sum_k coupling_eta[i]_kl eta_k
///   M_eta,eta       = modal_mass
/// (with M_V,V = m I, M_V,omega = -skew(s(eta)), M_V,eta = C).
struct ModalMassTerms {
  Matrix J1[3][3];          // 1 x n each
  Matrix J2[3][3];          // n x n each, symmetric
  Matrix coupling[3];       // 1 x n: int (r0 x Phi_l)_i dm
  Matrix coupling_eta[3];   // n x n: [k][l] = int (Phi_k x Phi_l)_i dm
  Matrix modal_mass;        // n x n: tr B_kl = int Phi_k . Phi_l dm
};
ModalMassTerms modal_mass_terms(const ModalData& d);

/// Finds `name` relative to the directory of the model file that names it,
/// then in each of `search_dirs`; reads and checks it. Errors go to `diags`
/// (at `named_at` when the file cannot be found; at the file's own line
/// otherwise) and the result is then nullopt. The file joins `sources`, so
/// its diagnostics show its lines and a depfile lists it.
std::optional<ModalData> read_modal_file(const std::string& name, const ir::SourceLoc& named_at,
                                         const std::vector<std::string>& search_dirs, ir::SourceManager& sources,
                                         ir::Diagnostics& diags);

/// Reads and checks the modal data already in `sources` as `file_id` (what
/// read_modal_file does once the file is found; the fuzz target's entry).
std::optional<ModalData> read_modal_source(const ir::SourceManager& sources, int file_id, ir::Diagnostics& diags);

}  // namespace mbgc::flex
