// The processes a sweep is spread over (sweep_cluster.hpp): this process
// alone, or, when an MPI launcher started it and the runtime was built with
// MPI, MPI_COMM_WORLD through the MPI module (cluster_backend.hpp) loaded
// here with dlopen. The module is found through the simulator's run path,
// which linking against mbgrt sets (runtime/CMakeLists.txt, mbgrt.pc).
#include "sweep_cluster.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>

#include "cluster_backend.hpp"

namespace mbgrt::detail {

namespace {

/// Set by Open MPI's mpirun, by MPICH/Hydra and by Slurm's PMI(x).
bool launched_by_mpi() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(variable)) return true;
  return false;
}

#ifdef MBGRT_MPI_MODULE
constexpr const char* kMpiModule = MBGRT_MPI_MODULE;
#else
constexpr const char* kMpiModule = nullptr;  // built without MPI (MBGC_MPI=OFF, or none found)
#endif

/// The MPI module's backend. The module stays loaded until the process
/// ends: MPI is not made to be unloaded.
std::unique_ptr<ClusterBackend> load_mpi_backend() {
  // RTLD_GLOBAL: Open MPI's own components, which it loads in MPI_Init,
  // resolve symbols of libmpi.
  void* module = dlopen(kMpiModule, RTLD_NOW | RTLD_GLOBAL);
  if (!module)
    throw std::runtime_error(std::string("started by an MPI launcher, but the runtime's MPI module could not be "
                                         "loaded: ") + dlerror());
  auto entry = reinterpret_cast<ClusterBackendEntry>(dlsym(module, kClusterBackendEntry));
  if (!entry) throw std::runtime_error(std::string("the MPI module has no entry point: ") + dlerror());
  return std::unique_ptr<ClusterBackend>(entry());
}

}  // namespace

Cluster::Cluster() {
  if (!kMpiModule || !launched_by_mpi()) return;
  backend_ = load_mpi_backend();
  rank_ = backend_->rank();
  size_ = backend_->size();
}

Cluster::~Cluster() = default;

std::vector<std::string> Cluster::gather_lines(const std::string& lines, std::size_t total) const {
  if (size_ == 1) return lines_in_case_order(lines, total);
  std::string all = backend_->gather(lines);
  if (rank_ != 0) return {};
  return lines_in_case_order(all, total);
}

long Cluster::sum(long value) const { return size_ == 1 ? value : backend_->sum(value); }

bool Cluster::with_mpi() { return kMpiModule != nullptr; }

}  // namespace mbgrt::detail
