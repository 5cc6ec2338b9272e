// MPI ranks (OpenMPI). MPI is initialised only under a launcher, so plain runs (and their tests under the
// sanitizers) never load the MPI runtime's state.
#include <mpi.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "parallel/ranks.h"

namespace rfidray::parallel {
namespace {

// Set by mpirun/mpiexec (OpenMPI, MPICH/Hydra) and by srun with PMI-2 or PMIx.
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

}  // namespace

Ranks::Ranks() {
  if (!launched_by_mpi()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  mpi_ = true;
}

Ranks::~Ranks() {
  int finalized = 0;
  if (mpi_ && MPI_Finalized(&finalized) == MPI_SUCCESS && !finalized) MPI_Finalize();
}

Ranks& Ranks::world() {
  static Ranks r;
  return r;
}

std::vector<double> Ranks::gather(std::span<const double> local, size_t n, size_t per_item) const {
  if (!mpi_ || size_ == 1) return {local.begin(), local.end()};
  // Counts and displacements follow from share(): nothing to exchange but the values. MPI counts are int:
  // beyond 2^31 − 1 values per rank, the gather goes in pieces of whole ranks is not needed here — refuse.
  std::vector<int> counts(size_), displs(size_);
  size_t offset = 0;
  for (int r = 0; r < size_; ++r) {
    const size_t c = share(n, r).second * per_item;
    if (c > static_cast<size_t>(INT32_MAX) || offset > static_cast<size_t>(INT32_MAX))
      throw std::runtime_error("MPI gather: more than 2^31 values; use more ranks or fewer cells");
    counts[r] = static_cast<int>(c);
    displs[r] = static_cast<int>(offset);
    offset += c;
  }
  if (local.size() != static_cast<size_t>(counts[rank_]))
    throw std::logic_error("internal error: rank " + std::to_string(rank_) + " gathers " +
                           std::to_string(local.size()) + " values, expected " + std::to_string(counts[rank_]));
  std::vector<double> all(root() ? offset : 0);
  MPI_Gatherv(local.data(), counts[rank_], MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0,
              MPI_COMM_WORLD);
  return all;
}

bool Ranks::all_ok(bool ok) const {
  if (!mpi_ || size_ == 1) return ok;
  int mine = ok ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return all == 1;
}

}  // namespace rfidray::parallel
