// sweep_cluster.hpp — the processes a sweep is spread over. Alone (the
// usual case) a cluster is this process, rank 0 of 1. Built with MPI
// (MBGC_MPI: the module libmbgrt_mpi.so, sweep_cluster_mpi.cpp) and started
// by an MPI launcher (mpirun -n 8 ./sim --sweep ...: the launcher's
// environment says so), it is MPI_COMM_WORLD: the module is loaded and MPI
// initialised here, and MPI is finalised when the cluster goes, so a
// simulator that is not sweeping under MPI never loads MPI.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace mbgrt::detail {

class ClusterBackend;  // cluster_backend.hpp

class Cluster {
 public:
  Cluster();
  ~Cluster();
  Cluster(const Cluster&) = delete;
  Cluster& operator=(const Cluster&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Every rank's `lines` (text, one case per line, each starting with its
  /// case number from 1); on rank 0 the `total` lines in case order, empty elsewhere.
  std::vector<std::string> gather_lines(const std::string& lines, std::size_t total) const;
  /// The sum over the ranks, on every rank.
  long sum(long value) const;
  /// Whether this runtime was built with MPI.
  static bool with_mpi();

 private:
  int rank_ = 0, size_ = 1;
  std::unique_ptr<ClusterBackend> backend_;  ///< MPI's, under an MPI launcher
};

/// Splits `text` into lines and orders them by their leading case number
/// (what rank 0 does with the gathered rows). Throws if a case is missing or doubled.
std::vector<std::string> lines_in_case_order(const std::string& text, std::size_t total);

}  // namespace mbgrt::detail
