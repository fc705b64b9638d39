// mbgrt/features.hpp — the optional parts of the runtime, each linked into a
// program only when the program names it here. The core (integrators, the
// command line, CSV, sweeps on threads) needs SUNDIALS and fmt alone; a
// simulator that calls none of these starts without loading tinygltf or
// SuiteSparse. mbgc's generated main() calls the ones its model needs; a
// program that embeds a model (mbgc --library) calls them itself.
//
// Sweeps across MPI ranks need no call: a runtime built with MPI loads its
// MPI module (libmbgrt_mpi.so) only when an MPI launcher started the process.
#pragma once

namespace mbgrt {

/// `--animate FILE.glb`: the glTF 2.0 writer (library mbgrt_gltf, over
/// tinygltf). Without it, --animate stops with a message.
void use_gltf_animation();

/// IDA's sparse direct solver, KLU (library mbgrt_klu, over SuiteSparse), on
/// the sparsity pattern a model gives (Model::residual_sparsity). Without it,
/// `--linear-solver auto` keeps dense LU and `--linear-solver sparse` stops
/// with a message.
void use_sparse_lu();

}  // namespace mbgrt
