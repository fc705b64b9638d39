// sparse_lu.hpp — IDA's sparse direct linear solver, an optional part of the
// runtime (mbgrt/features.hpp): KLU lives in solvers/klu.cpp (library
// mbgrt_klu), installed by mbgrt::use_sparse_lu(), so a simulator whose model
// gives no sparsity pattern never links SuiteSparse.
#pragma once

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

namespace mbgrt::detail {

/// Makes the linear solver for the CSC matrix A (y: a vector of the unknowns).
using SparseLuFactory = SUNLinearSolver (*)(N_Vector y, SUNMatrix A, SUNContext ctx);

/// The installed factory; null until use_sparse_lu() (see animation_sink.hpp
/// for why a function-local static).
inline SparseLuFactory& sparse_lu_factory() {
  static SparseLuFactory factory = nullptr;
  return factory;
}

}  // namespace mbgrt::detail
