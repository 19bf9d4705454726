// GOMP_parallel for one-thread regions (core/cholmod_support.h). libgomp (GCC's OpenMP runtime,
// CHOLMOD's) ends every parallel region with a futex wake system call, also a region that runs
// on one thread because its `if` clause is false or because max-active-levels is 0
// (SerialOpenMpScope). CHOLMOD's supernodal factorisation opens several regions per supernode
// for its scatter loops, nearly all of them one-thread: 88 000 system calls for one factorisation
// of the Aquadom frame, millions on a non-linear path. This definition, linked into an
// executable (CMake target gridshell_openmp, exported to the dynamic symbol table), runs such a
// region's body directly on the calling thread — what libgomp does for it, minus the team
// bookkeeping: outside a team omp_get_num_threads() is 1 and omp_get_thread_num() 0, so the
// body's work-sharing gives the whole range to this thread. Only outside any region (level 0):
// inside a team those calls would answer for the enclosing team. Every other region is passed
// on to libgomp. Opt-in like the other interposed routines: the library never replaces a routine
// of the process it is linked into.

#include <dlfcn.h>

#include <bit>

namespace {
using ParallelFn = void (*)(void (*)(void*), void*, unsigned, unsigned);
using LevelsFn = int (*)();
}  // namespace

extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads,
                              unsigned flags) {
  static const auto next = std::bit_cast<ParallelFn>(dlsym(RTLD_NEXT, "GOMP_parallel"));
  static const auto max_active_levels =
      std::bit_cast<LevelsFn>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  static const auto level = std::bit_cast<LevelsFn>(dlsym(RTLD_DEFAULT, "omp_get_level"));
  // num_threads is 1 when the region's `if` clause is false (0 means "the default").
  const bool one_thread =
      num_threads == 1 || (max_active_levels != nullptr && max_active_levels() == 0);
  if (next == nullptr || (one_thread && level != nullptr && level() == 0)) {
    fn(data);
    return;
  }
  next(fn, data, num_threads, flags);
}
