// cluster_backend.hpp — the interface between the core's sweep cluster
// (sweep_cluster.cpp) and the MPI module (sweep_cluster_mpi.cpp, built as
// libmbgrt_mpi.so where MPI is found). The core loads the module with dlopen
// only when an MPI launcher started the process, so a simulator carries no
// MPI library otherwise. The module uses nothing of the core's: it moves
// text and numbers between ranks; the core puts them in order.
#pragma once

#include <string>

namespace mbgrt::detail {

class ClusterBackend {
 public:
  virtual ~ClusterBackend() = default;  ///< MPI_Finalize, if the module called MPI_Init
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Every rank's `text`, concatenated in rank order on rank 0; empty elsewhere.
  virtual std::string gather(const std::string& text) const = 0;
  /// The sum over the ranks, on every rank.
  virtual long sum(long value) const = 0;
};

/// The module's one entry point, found with dlsym: MPI initialised and
/// MPI_COMM_WORLD's rank and size read. Throws std::runtime_error if MPI fails.
using ClusterBackendEntry = ClusterBackend* (*)();
inline constexpr const char* kClusterBackendEntry = "mbgrt_mpi_cluster_backend";

}  // namespace mbgrt::detail
