// libFuzzer target: bytes -> TUM / EuRoC trajectory readers. The first byte picks the reader
// (readTumTrajectory, readEurocGroundTruth, readTrajectory auto-detection); the rest is written to a temp
// file. Readers must return true with finite, unit-quaternion, time-sorted poses, or false with an error
// naming the file; never throw or crash. Built and run by scripts/fuzz.sh.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "iraf_vo/io/trajectory.h"

#include "fuzz_check.h"

namespace {
const std::string& tempPath() {
  static const std::string p = [] {
    const char* tmp = std::getenv("TMPDIR");
    return std::string(tmp && *tmp ? tmp : "/tmp") + "/iraf_vo_fuzz_traj_" + std::to_string(getpid()) + ".txt";
  }();
  return p;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const int mode = data[0] % 3;
  {
    std::ofstream f(tempPath(), std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  iraf_vo::Trajectory traj;
  std::string err;
  std::vector<std::string> warnings;
  bool ok = false;
  if (mode == 0) ok = iraf_vo::readTumTrajectory(tempPath(), &traj, &err, &warnings);
  if (mode == 1) ok = iraf_vo::readEurocGroundTruth(tempPath(), &traj, &err, Eigen::Matrix4d::Identity(), &warnings);
  if (mode == 2) ok = iraf_vo::readTrajectory(tempPath(), &traj, &err, Eigen::Matrix4d::Identity(), &warnings);
  if (!ok) {
    FUZZ_CHECK(err.find(tempPath()) != std::string::npos);  // the error names the file
    return 0;
  }
  FUZZ_CHECK(!traj.empty() && traj.stamps.size() == traj.poses.size());
  for (size_t i = 0; i < traj.size(); ++i) {
    FUZZ_CHECK(std::isfinite(traj.stamps[i]));
    FUZZ_CHECK(traj.poses[i].matrix().allFinite());
    if (i > 0) FUZZ_CHECK(traj.stamps[i] >= traj.stamps[i - 1]);
  }
  for (const std::string& w : warnings) FUZZ_CHECK(!w.empty());
  return 0;
}
