// The cluster of a runtime built without MPI: this process alone.
#include "sweep_cluster.hpp"

namespace mbgrt::detail {

Cluster::Cluster() = default;
Cluster::~Cluster() = default;

std::vector<std::string> Cluster::gather_lines(const std::string& lines, std::size_t total) const {
  return lines_in_case_order(lines, total);
}

long Cluster::sum(long value) const { return value; }

bool Cluster::with_mpi() { return false; }

}  // namespace mbgrt::detail
