// klu.cpp — IDA's sparse direct solver: KLU (SuiteSparse) through SUNDIALS'
// SUNLinSol_KLU. The library mbgrt_klu; a program installs it with
// mbgrt::use_sparse_lu() (mbgrt/features.hpp).
#include <sunlinsol/sunlinsol_klu.h>

#include "mbgrt/features.hpp"
#include "solvers/sparse_lu.hpp"

namespace mbgrt {

namespace {

SUNLinearSolver make_klu(N_Vector y, SUNMatrix A, SUNContext ctx) {
  SUNLinearSolver ls = SUNLinSol_KLU(y, A, ctx);
  // Partial pivoting as dense LU does (KLU's default keeps a diagonal
  // pivot down to 1e-3 of its column's largest entry, which loses digits
  // when masses differ by orders of magnitude: a 1e-9 kg rod on a 1e3 kg one)
  if (ls) SUNLinSol_KLUGetCommon(ls)->tol = 1.0;
  return ls;
}

}  // namespace

void use_sparse_lu() { detail::sparse_lu_factory() = make_klu; }

}  // namespace mbgrt
