// MPI session for `gridshell sweep` (see mpi.h). Without GRIDSHELL_WITH_MPI every function is
// the single-process behaviour.

#include "mpi.h"

#include <algorithm>
#include <cstdlib>
#include <thread>
#include <type_traits>

#ifdef GRIDSHELL_WITH_MPI
#include <mpi.h>
#endif

namespace gridshell::app {

namespace {

/// Launchers (Open MPI's mpirun, PMI/PMIx-based ones such as srun) announce themselves here.
bool started_by_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  if (!v) return fallback;
  const int n = std::atoi(v);
  return n > 0 ? n : fallback;
}

}  // namespace

bool mpi_built() {
#ifdef GRIDSHELL_WITH_MPI
  return true;
#else
  return false;
#endif
}

MpiSession::MpiSession() {
#ifdef GRIDSHELL_WITH_MPI
  if (!started_by_launcher()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  initialised_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  local_size_ = env_int("OMPI_COMM_WORLD_LOCAL_SIZE", env_int("MPI_LOCALNRANKS", 1));
#else
  (void)started_by_launcher;
  (void)env_int;
#endif
}

MpiSession::~MpiSession() {
#ifdef GRIDSHELL_WITH_MPI
  if (initialised_) MPI_Finalize();
#endif
}

int MpiSession::threads_per_rank() const {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, cores / std::max(1, local_size_));
}

std::vector<SweepRow> MpiSession::gather(const std::vector<SweepRow>& mine) const {
  static_assert(std::is_trivially_copyable_v<SweepRow>, "rows travel as bytes");
  if (!initialised_ || size_ == 1) return mine;
  std::vector<SweepRow> all;
#ifdef GRIDSHELL_WITH_MPI
  // Every rank runs the same executable, so rows can travel as raw bytes.
  const int bytes = static_cast<int>(mine.size() * sizeof(SweepRow));
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(counts.size());
  MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  int total = 0;
  if (rank_ == 0)
    for (std::size_t r = 0; r < counts.size(); ++r) offsets[r] = total, total += counts[r];
  std::vector<SweepRow> received(static_cast<std::size_t>(total) / sizeof(SweepRow));
  MPI_Gatherv(mine.data(), bytes, MPI_BYTE, received.data(), counts.data(), offsets.data(),
              MPI_BYTE, 0, MPI_COMM_WORLD);
  if (rank_ == 0) {
    all = std::move(received);
    std::sort(all.begin(), all.end(),
              [](const SweepRow& a, const SweepRow& b) { return a.c.index < b.c.index; });
  }
#endif
  return all;
}

void MpiSession::abort(int status) const {
#ifdef GRIDSHELL_WITH_MPI
  if (initialised_) MPI_Abort(MPI_COMM_WORLD, status);
#endif
  std::exit(status);
}

}  // namespace gridshell::app
