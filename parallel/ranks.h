#pragma once
// Module parallel — the one place that knows about MPI: a run's processes ("ranks"), how n work items are
// shared among them, and the gather of their results on rank 0. Coverage maps and placement (cli/) shard
// cells and candidates with it; the library below knows nothing of it.
//
// Built with MPI (CMake option RFIDRAY_WITH_MPI, on when OpenMPI is found: ranks_mpi.cpp) MPI is initialised
// only when the process was started by an MPI launcher (mpirun / mpiexec / srun: their environment variables
// say so), so a plain `rfidray …` never touches MPI. Without MPI (ranks_serial.cpp) there is one rank.
// Shares are contiguous and fixed by (n, size) alone, and every item is computed the same way wherever it
// runs, so the gathered result — and every file rank 0 writes from it — is identical for any number of ranks.
// Call only from the main thread (MPI_THREAD_FUNNELED); OpenMP threads inside a rank are fine.
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace rfidray::parallel {

class Ranks {
 public:
  // The run's ranks; initialises MPI on first use when launched by an MPI launcher. MPI is finalised at exit.
  static Ranks& world();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  bool mpi() const { return mpi_; }

  // The share [first, first + count) of n items of rank r (default: this rank): ⌊n·r/size⌋ … ⌊n·(r+1)/size⌋.
  std::pair<size_t, size_t> share(size_t n) const { return share(n, rank_); }
  std::pair<size_t, size_t> share(size_t n, int r) const;

  // Every rank passes the values of its share of n items (`per_item` doubles per item, item-major); rank 0
  // gets all n·per_item values in item order, the others an empty vector. Collective.
  std::vector<double> gather(std::span<const double> local, size_t n, size_t per_item) const;

  // True on every rank iff `ok` is true on every rank (so that no rank waits in a collective for one that
  // failed). Collective.
  bool all_ok(bool ok) const;

  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;
  ~Ranks();

 private:
  Ranks();
  int rank_ = 0, size_ = 1;
  bool mpi_ = false;
};

}  // namespace rfidray::parallel
