// The MPI module, libmbgrt_mpi.so (built where MPI is found, MBGC_MPI):
// MPI_COMM_WORLD as a ClusterBackend. The core loads it with dlopen when an
// MPI launcher started the process (sweep_cluster.cpp).
#include <mpi.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "cluster_backend.hpp"

namespace mbgrt::detail {

namespace {

void check(int status, const char* what) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

class MpiBackend final : public ClusterBackend {
 public:
  MpiBackend() {
    int already = 0;
    check(MPI_Initialized(&already), "MPI_Initialized");
    if (!already) {
      check(MPI_Init(nullptr, nullptr), "MPI_Init");
      initialised_ = true;
    }
    check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
  }
  ~MpiBackend() override {
    if (initialised_) MPI_Finalize();
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  std::string gather(const std::string& text) const override {
    const int length = static_cast<int>(text.size());
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
    check(MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
                      MPI_COMM_WORLD),
          "MPI_Gatherv");
    return all;
  }

  long sum(long value) const override {
    long total = 0;
    check(MPI_Allreduce(&value, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
    return total;
  }

 private:
  int rank_ = 0, size_ = 1;
  bool initialised_ = false;  ///< MPI_Init was called here
};

}  // namespace

}  // namespace mbgrt::detail

extern "C" __attribute__((visibility("default"))) mbgrt::detail::ClusterBackend* mbgrt_mpi_cluster_backend() {
  return new mbgrt::detail::MpiBackend();
}
