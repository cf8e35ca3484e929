// Wall-clock stage timing [ms] (steady clock). For CPU time of the calling thread see cpu_clock.h.
#pragma once

#include <chrono>

namespace iraf_vo {

using SteadyClock = std::chrono::steady_clock;

/// Wall milliseconds elapsed since `t0` (a SteadyClock::now() value).
inline double msSince(SteadyClock::time_point t0) {
  return std::chrono::duration<double, std::milli>(SteadyClock::now() - t0).count();
}

}  // namespace iraf_vo
