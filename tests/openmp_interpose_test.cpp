// The executable's GOMP_parallel (src/interpose/openmp.cpp): a one-thread region outside any
// team runs its body on the calling thread without libgomp (no per-region system call), with
// the same results as libgomp's own one-thread team; regions with more threads, and any region
// inside a team, are still libgomp's. This program is compiled with OpenMP, so its `#pragma omp`
// regions go through the interposed entry point as CHOLMOD's do.
#include <gtest/gtest.h>

#include <dlfcn.h>
#include <omp.h>
#include <sys/syscall.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <thread>
#include <vector>

#include "gridshell/core/cholmod_support.h"

namespace gridshell {
namespace {

extern "C" void GOMP_parallel(void (*)(void*), void*, unsigned, unsigned);

TEST(OpenMpInterpose, IsTheGompParallelTheProcessCalls) {
  void* self = dlopen(nullptr, RTLD_NOW);
  ASSERT_NE(self, nullptr);
  EXPECT_EQ(dlsym(self, "GOMP_parallel"), reinterpret_cast<void*>(&GOMP_parallel));
  void* libgomp = dlsym(RTLD_NEXT, "GOMP_parallel");
  EXPECT_NE(libgomp, nullptr) << "libgomp is what one-thread regions are kept away from";
  EXPECT_NE(libgomp, reinterpret_cast<void*>(&GOMP_parallel));
  dlclose(self);
}

// What a parallel for saw: the iterations' sum, the threads that ran them, the team size and
// the nesting level (libgomp's one-thread team is a level; a body run directly is not).
struct Seen {
  long sum = 0;
  std::vector<std::thread::id> threads;
  int team = 0;
  int level = -1;
};

Seen run_loop(int n, int requested, bool condition) {
  std::vector<long> value(n, 0);
  std::vector<std::thread::id> who(n);
  int team = 0, level = -1;
#pragma omp parallel for num_threads(requested) if (condition) schedule(static)
  for (int i = 0; i < n; ++i) {
    value[i] = i;
    who[i] = std::this_thread::get_id();
    if (i == 0) team = omp_get_num_threads(), level = omp_get_level();
  }
  Seen s;
  s.sum = std::accumulate(value.begin(), value.end(), 0L);
  for (const auto& id : who)
    if (std::find(s.threads.begin(), s.threads.end(), id) == s.threads.end())
      s.threads.push_back(id);
  s.team = team;
  s.level = level;
  return s;
}

TEST(OpenMpInterpose, OneThreadRegionsRunWholeOnTheCallingThread) {
  const int n = 10000;
  const long expected = static_cast<long>(n) * (n - 1) / 2;
  // `if` false: one thread, as libgomp would.
  const Seen off = run_loop(n, 4, false);
  EXPECT_EQ(off.sum, expected);
  ASSERT_EQ(off.threads.size(), 1u);
  EXPECT_EQ(off.threads.front(), std::this_thread::get_id());
  EXPECT_EQ(off.team, 1);
  EXPECT_EQ(off.level, 0) << "run by libgomp, not directly";
  // Inside SerialOpenMpScope (max-active-levels 0) even a region asking for 4 threads.
  {
    const SerialOpenMpScope serial;
    const Seen scoped = run_loop(n, 4, true);
    EXPECT_EQ(scoped.sum, expected);
    ASSERT_EQ(scoped.threads.size(), 1u);
    EXPECT_EQ(scoped.team, 1);
    EXPECT_EQ(scoped.level, 0);
  }
}

TEST(OpenMpInterpose, OtherRegionsAreStillLibgomps) {
  const int n = 10000;
  const long expected = static_cast<long>(n) * (n - 1) / 2;
  omp_set_max_active_levels(1);
  const Seen two = run_loop(n, 2, true);
  EXPECT_EQ(two.sum, expected);
  EXPECT_EQ(two.team, 2);
  EXPECT_EQ(two.threads.size(), 2u);
  EXPECT_EQ(two.level, 1);
  // A one-thread region inside a team must get its own one-thread team (libgomp's): run inline
  // it would see the enclosing team's size and do only its share of the loop.
  std::atomic<long> total{0};
  std::atomic<int> inner_team{0};
#pragma omp parallel num_threads(2)
  {
    long part = 0;
#pragma omp parallel for num_threads(2) if (n < 0) schedule(static)
    for (int i = 0; i < n; ++i) {
      part += i;
      if (i == 0) inner_team = omp_get_num_threads();
    }
    total += part;
  }
  EXPECT_EQ(total.load(), 2 * expected);  // each of the 2 outer threads ran the whole loop
  EXPECT_EQ(inner_team.load(), 1);
}

}  // namespace
}  // namespace gridshell
