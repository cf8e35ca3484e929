// Per-process temporary files for tests: parallel runs (ctest -j, plain + sanitizer builds) never share
// files, and everything under tmpRoot() is removed when the test binary ends.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

inline std::string tmpRoot() {
  return (testing::TempDir().empty() ? std::string("/tmp/") : testing::TempDir()) + "iraf_vo_" +
         std::to_string(::getpid()) + "_";
}

struct TmpCleanup : testing::Environment {
  void TearDown() override { std::system(("rm -rf " + tmpRoot() + "*").c_str()); }
};

inline const testing::Environment* const kTmpCleanup = testing::AddGlobalTestEnvironment(new TmpCleanup);
