// fe/compensated.cpp
#include "compensated.hpp"

namespace mbgc::fe {

Eigen::MatrixXd congruence(const SparseMatrix& a, const Eigen::MatrixXd& v) {
  const long rows = v.rows(), n = v.cols();
  // y_l = A^T v_l, an entry per column of A, each a Dot2 kept as hi + lo:
  // within gamma_{m+1}^2 (|A|^T |v_l|)_i of the exact value.
  Eigen::MatrixXd y_hi(rows, n), y_lo(rows, n);
  for (long l = 0; l < n; ++l)
    for (long i = 0; i < a.outerSize(); ++i) {
      CompensatedDot dot;
      for (SparseMatrix::InnerIterator it(a, i); it; ++it) dot.add(it.value(), v(it.row(), l));
      const DoubleDouble y = dot.value();
      y_hi(i, l) = y.hi;
      y_lo(i, l) = y.lo;
    }
  // v_k^T y_l: v_k^T hi_l by Dot2, within gamma_{N+1}^2 |v_k|^T |hi_l|, and
  // v_k^T lo_l by a plain sum, within gamma_N |v_k|^T |lo_l| <= gamma_N u
  // |v_k|^T |hi_l|; together within 2 gamma_{N+1}^2 |v_k|^T |y_l| of
  // v_k^T (hi + lo), which is within gamma_{m+1}^2 |v_k|^T |A|^T |v_l| of
  // v_k^T A^T v_l. Then rounded once.
  Eigen::MatrixXd s(n, n);
  for (long k = 0; k < n; ++k)
    for (long l = 0; l < n; ++l) {
      CompensatedDot dot;
      double low = 0;
      for (long i = 0; i < rows; ++i) {
        dot.add(v(i, k), y_hi(i, l));
        low += v(i, k) * y_lo(i, l);
      }
      const DoubleDouble x = dot.value();
      s(k, l) = x.hi + (x.lo + low);
    }
  // S = V^T A^T V; its symmetric part is that of V^T A V (and the diagonal is
  // left as it is).
  return 0.5 * (s + s.transpose());
}

}  // namespace mbgc::fe
