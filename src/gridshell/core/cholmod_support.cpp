#include "gridshell/core/cholmod_support.h"

#include <dlfcn.h>

#include <bit>

namespace gridshell {

std::unique_lock<std::mutex> lock_symbolic_analysis() {
  // One lock for the whole process: METIS's state is one global, whoever calls it.
  static std::mutex metis;
  return std::unique_lock<std::mutex>(metis);
}

// libgomp's max-active-levels is per thread: setting it to 0 makes every parallel region this
// thread opens run on the thread alone.
SerialOpenMpScope::SerialOpenMpScope()
    : get_(std::bit_cast<Get>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"))),
      set_(std::bit_cast<Set>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) {
  if (get_ && set_) {
    previous_ = get_();
    set_(0);
  }
}

SerialOpenMpScope::~SerialOpenMpScope() {
  if (get_ && set_) set_(previous_);
}

}  // namespace gridshell
