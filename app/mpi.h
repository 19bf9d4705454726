#pragma once
/// \file mpi.h
/// Optional MPI distribution of `gridshell sweep` (built when CMake finds MPI and
/// GRIDSHELL_MPI is on). `mpirun -n K gridshell sweep ...` runs rank r on the cases
/// r, r + K, r + 2K, ... of the (sharded) list and rank 0 gathers every row and writes the
/// outputs. Each case carries its own seed, so the rows equal those of a single-process run.
/// MPI is only initialised when the process was started by an MPI launcher: a plain
/// `gridshell sweep` never touches MPI, even in an MPI build.

#include <memory>
#include <vector>

#include "gridshell/pipeline/sweep.h"

namespace gridshell::app {

class MpiSession {
 public:
  /// Initialises MPI if this build has it and a launcher started the process.
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  bool active() const { return size_ > 1 || initialised_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Worker threads per rank that share the node's cores fairly (≥ 1).
  int threads_per_rank() const;

  /// Rank 0 receives every rank's rows (in case order); other ranks get an empty list.
  std::vector<SweepRow> gather(const std::vector<SweepRow>& mine) const;

  /// Ends every rank with `status` (used when one rank fails, so that none waits forever).
  [[noreturn]] void abort(int status) const;

 private:
  bool initialised_ = false;
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

/// True when this executable was built with MPI support.
bool mpi_built();

}  // namespace gridshell::app
