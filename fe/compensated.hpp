// fe/compensated.hpp — dot products as if computed in twice the precision of
// double: Ogita, Rump and Oishi's Dot2 ("Accurate sum and dot product", SIAM
// J. Sci. Comput. 26(6), 2005), built on the error-free transformations of a
// sum (TwoSum) and a product (TwoProduct, by a fused multiply-add).
//
// The projected stiffness of a thin solid needs it: for a low mode phi the
// strain energy phi^T K phi is a small difference of large terms, smaller than
// |phi|^T |K| |phi| by a factor c of 1e12 and more (c = 1.4e12 for the first
// mode of the 0.9 m x 5 mm x 2 mm strip of tests/fe/reduce_test.cpp). A sum of
// n terms in precision u can then be off by n u c relative; in long double
// the strip's first frequency came out 1e-9 off, by an amount that depends
// on the order of the terms. Dot2's error is at most about (n u)^2 c.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "matrix_market.hpp"

namespace mbgc::fe {

// An unevaluated sum hi + lo.
struct DoubleDouble {
  double hi = 0, lo = 0;
};

// a + b = hi + lo exactly, hi = fl(a + b) (Knuth's TwoSum: any magnitudes).
inline DoubleDouble two_sum(double a, double b) {
  const double s = a + b, z = s - a;
  return {s, (a - (s - z)) + (b - z)};
}

// a b = hi + lo exactly, hi = fl(a b), unless a b underflows.
inline DoubleDouble two_product(double a, double b) {
  const double p = a * b;
  return {p, std::fma(a, b, -p)};
}

// sum_i a_i b_i by Dot2: the running sum in `sum_`; every product's and every
// addition's rounding error, exact by TwoProduct and TwoSum, summed apart in
// `error_`. For n terms sum_ + error_ is within gamma_n gamma_{n+1}
// sum_i |a_i b_i| of the exact dot product (gamma_k = k u / (1 - k u), u =
// 2^-53): error_ is a plain sum of n terms (a product's and an addition's
// error each) whose magnitudes add up to at most gamma_{n+1} sum_i |a_i b_i|,
// so it is within gamma_n times that of their exact sum. value() adds the two
// exactly.
class CompensatedDot {
 public:
  void add(double a, double b) {
    const DoubleDouble p = two_product(a, b), s = two_sum(sum_, p.hi);
    sum_ = s.hi;
    error_ += p.lo + s.lo;
  }
  DoubleDouble value() const { return two_sum(sum_, error_); }

 private:
  double sum_ = 0, error_ = 0;
};

/// V^T A V for the symmetric part of A. The entry kl is within
/// u |v_k^T A v_l| + gamma_{m+1}^2 |v_k|^T |A| |v_l| + 2 gamma_{N+1}^2 |v_k|^T |A v_l|
/// of the exact value (m: the most nonzeros in a column of A; N: V's rows),
/// and off the diagonal within another u from the half sum of both
/// triangles. On the diagonal that is a relative error of u + gamma_{m+1}^2 c
/// + 2 gamma_{N+1}^2 c', c = |v_k|^T |A| |v_k| / v_k^T A v_k and
/// c' = |v_k|^T |A v_k| / v_k^T A v_k, which is small for a mode (A v = lambda
/// M v).
Eigen::MatrixXd congruence(const SparseMatrix& a, const Eigen::MatrixXd& v);

}  // namespace mbgc::fe
