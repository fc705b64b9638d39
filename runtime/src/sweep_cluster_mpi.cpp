// The cluster of a runtime built with MPI (-DMBGC_MPI=ON): MPI_COMM_WORLD
// when an MPI launcher started this process, else this process alone.
#include <mpi.h>

#include <cstdlib>
#include <stdexcept>

#include "sweep_cluster.hpp"

namespace mbgrt::detail {

namespace {

/// Set by Open MPI's mpirun, by MPICH/Hydra and by Slurm's PMI(x).
bool launched_by_mpi() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(variable)) return true;
  return false;
}

void check(int status, const char* what) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

}  // namespace

Cluster::Cluster() {
  if (!launched_by_mpi()) return;
  int already = 0;
  check(MPI_Initialized(&already), "MPI_Initialized");
  if (!already) {
    check(MPI_Init(nullptr, nullptr), "MPI_Init");
    initialised_ = true;
  }
  check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
}

Cluster::~Cluster() {
  if (initialised_) MPI_Finalize();
}

std::vector<std::string> Cluster::gather_lines(const std::string& lines, std::size_t total) const {
  if (size_ == 1) return lines_in_case_order(lines, total);
  const int length = static_cast<int>(lines.size());
  std::vector<int> lengths(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
  check(MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  std::vector<int> offsets(lengths.size());
  std::string all;
  if (rank_ == 0) {
    long at = 0;
    for (std::size_t r = 0; r < lengths.size(); ++r) {
      offsets[r] = static_cast<int>(at);
      at += lengths[r];
    }
    all.resize(static_cast<std::size_t>(at));
  }
  check(MPI_Gatherv(lines.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
                    MPI_COMM_WORLD),
        "MPI_Gatherv");
  if (rank_ != 0) return {};
  return lines_in_case_order(all, total);
}

long Cluster::sum(long value) const {
  if (size_ == 1) return value;
  long total = 0;
  check(MPI_Allreduce(&value, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
  return total;
}

bool Cluster::with_mpi() { return true; }

}  // namespace mbgrt::detail
