// Stage timing in CPU time of the calling thread [ms]. On a shared machine the wall time of a few-ms stage is
// dominated by preemptions; without preemption the two agree. Used by the feature stage's FeatureStats and by
// the front-end benchmark, so both report the same clock.
#pragma once

#include <ctime>

namespace iraf_vo {

/// CPU time of the calling thread in milliseconds.
inline double threadCpuMs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/// Thread CPU milliseconds elapsed since `t0` (a threadCpuMs() value).
inline double threadCpuMsSince(double t0) { return threadCpuMs() - t0; }

}  // namespace iraf_vo
