// multibody/modal_algebra.cpp — AST builders for the floating-frame equations.
#include "multibody/modal_algebra.hpp"

namespace mbgc::multibody::detail {

/// eta_k of beam n as an AST expression (1-based component of the modal C's state).
E eta_of(const Build& B, const FlexibleSym& n, int k) { return B.at(B.ref(n.eta().displacement()), k + 1); }

/// sum_ij P[i][j] x_i y_j for a parameter matrix P (1-based indexing).
E quadratic(const Build& B, const Sym& P, const std::vector<E>& x, const std::vector<E>& y) {
  E sum = nullptr;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < y.size(); ++j) {
      E term = B.op('*', B.op('*', idx2(B, B.ref(P), static_cast<int>(i) + 1, static_cast<int>(j) + 1), x[i]), y[j]);
      sum = sum ? B.op('+', sum, term) : term;
    }
  return sum ? sum : B.num(0);
}

/// (P x)_i, or (P^T x)_i, for a parameter matrix P.
E row_dot(const Build& B, const Sym& P, int i, const std::vector<E>& x, bool transposed) {
  E sum = nullptr;
  for (std::size_t j = 0; j < x.size(); ++j) {
    int r = transposed ? static_cast<int>(j) + 1 : i + 1, c = transposed ? i + 1 : static_cast<int>(j) + 1;
    E term = B.op('*', idx2(B, B.ref(P), r, c), x[j]);
    sum = sum ? B.op('+', sum, term) : term;
  }
  return sum ? sum : B.num(0);
}

E sum_of(const Build& B, const std::vector<E>& terms) {
  E sum = nullptr;
  for (const auto& t : terms)
    if (t) sum = sum ? B.op('+', sum, t) : t;
  return sum ? sum : B.num(0);
}

E matrix_param(const Build& B, const flex::Matrix& m) {
  std::vector<E> rows_;
  for (const auto& r : m) {
    std::vector<E> row;
    for (double x : r) row.push_back(B.num(x));
    rows_.push_back(B.list(row));
  }
  return B.list(rows_);
}

E vector_param(const Build& B, const std::vector<double>& v) {
  std::vector<E> items;
  for (double x : v) items.push_back(B.num(x));
  return B.list(items);
}

/// sum_k P[k] x_k for a parameter vector P (0 for no x).
E vec_dot(const Build& B, const Sym& P, const std::vector<E>& x) {
  std::vector<E> terms;
  for (std::size_t k = 0; k < x.size(); ++k) terms.push_back(B.op('*', B.at(B.ref(P), static_cast<int>(k) + 1), x[k]));
  return sum_of(B, terms);
}

/// The V-omega blocks of M: -skew(s) at (V, omega), skew(s) at (omega, V).
void put_first_moment(const Build& B, Rows& M, E s) {
  std::vector<E> sc = {B.at(s, 1), B.at(s, 2), B.at(s, 3)};
  auto put_skew = [&](int r0, int c0, double sign) {  // sign * skew(s) at (r0, c0)
    auto v = [&](int k) { return sign > 0 ? sc[static_cast<std::size_t>(k)] : B.neg(sc[static_cast<std::size_t>(k)]); };
    M[r0 + 0][c0 + 1] = B.neg(v(2)), M[r0 + 0][c0 + 2] = v(1);
    M[r0 + 1][c0 + 0] = v(2), M[r0 + 1][c0 + 2] = B.neg(v(0));
    M[r0 + 2][c0 + 0] = B.neg(v(1)), M[r0 + 2][c0 + 1] = v(0);
  };
  put_skew(0, 3, -1);
  put_skew(3, 0, +1);
}

E rows_to_matrix(const Build& B, const Rows& m) {
  std::vector<E> rows_;
  for (const auto& r : m) rows_.push_back(B.list(r));
  return B.list(rows_);
}

bool all_zero(const flex::Matrix& m) {
  for (const auto& r : m)
    for (double x : r)
      if (x != 0) return false;
  return true;
}

E modal_damping(const Build& B, E zeta, int count, const Sym& K, const Sym& M) {
  std::vector<E> c;
  for (int i = 1; i <= count; ++i)
    c.push_back(B.op('*', B.op('*', B.num(2), zeta ? zeta : B.num(0)),
                     B.call("sqrt", {B.op('*', idx2(B, B.ref(K), i, i), idx2(B, B.ref(M), i, i))})));
  return c.size() == 1 ? B.list({B.list({c[0]})}) : B.call("diag", c);
}

E section_quaternion(const Build& B, E theta) {
  return B.call("vcat", {B.list({B.num(1)}), B.op('*', B.num(0.5), std::move(theta))});
}

E section_turn(const Build& B, E theta) { return B.call("rotq", {section_quaternion(B, std::move(theta))}); }

}  // namespace mbgc::multibody::detail
