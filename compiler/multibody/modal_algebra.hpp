// multibody/modal_algebra.hpp — AST builders for the floating-frame equations
// of flexible bodies: sums over modal coordinates with parameter matrices
// (1-based, as the generated code indexes them), constant tables, and M(eta)
// assembled from rows of scalars.
#pragma once

#include <vector>

#include "flex/beam_modes.hpp"
#include "multibody/build.hpp"

namespace mbgc::multibody::detail {

using Rows = std::vector<std::vector<E>>;

/// eta_k of body n as an AST expression (1-based component of the modal C's state).
E eta_of(const Build& B, const FlexibleSym& n, int k);
/// sum_ij P[i][j] x_i y_j for a parameter matrix P (0 for no terms).
E quadratic(const Build& B, const Sym& P, const std::vector<E>& x, const std::vector<E>& y);
/// (P x)_i, or (P^T x)_i, for a parameter matrix P.
E row_dot(const Build& B, const Sym& P, int i, const std::vector<E>& x, bool transposed = false);
/// sum_k P[k] x_k for a parameter vector P (0 for no x).
E vec_dot(const Build& B, const Sym& P, const std::vector<E>& x);
/// The sum of the non-null terms (0 for none).
E sum_of(const Build& B, const std::vector<E>& terms);
/// A constant matrix or vector as a list literal.
E matrix_param(const Build& B, const flex::Matrix& m);
E vector_param(const Build& B, const std::vector<double>& v);
/// Rows of scalars as a matrix literal.
E rows_to_matrix(const Build& B, const Rows& m);
/// The V-omega blocks of M: -skew(s) at (V, omega), skew(s) at (omega, V).
void put_first_moment(const Build& B, Rows& M, E s);
/// Every entry is 0.
bool all_zero(const flex::Matrix& m);
/// The turn of a flexible body's section whose small rotation (body axes) is
/// `theta`: rotq([1, theta / 2]), orthonormal (the Cayley form; to first
/// order I + skew(theta)). Joint frames at a flexible body's points turn by it
/// under every constraint strategy, so rows and coordinates model the same body.
E section_quaternion(const Build& B, E theta);  // [1, theta / 2], not normalised
E section_turn(const Build& B, E theta);
/// Modal damping 2 zeta omega_i m_i = 2 zeta sqrt(K_ii M_ii) per mode (zeta: the body's `damping`, or none).
E modal_damping(const Build& B, E zeta, int count, const Sym& K, const Sym& M);

}  // namespace mbgc::multibody::detail
