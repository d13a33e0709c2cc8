// The CPU time this process has used, all its threads together (user and system). A share of a
// time budget measured in it is not cut short when other processes take the cores.
#pragma once

#include <ctime>

namespace shaderfit {

inline double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace shaderfit
