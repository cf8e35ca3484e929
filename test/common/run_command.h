// Tests of the command-line tools: run a shell command and capture what it prints.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace iraf_vo {
namespace test {

/// Runs `cmd` through the shell with stderr joined to stdout, stores everything it printed in `output` and returns
/// its exit status (-1 when it could not be started or did not exit normally).
inline int runCommand(const std::string& cmd, std::string* output) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[512];
  output->clear();
  while (fgets(buf, sizeof(buf), p)) *output += buf;
  const int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

}  // namespace test
}  // namespace iraf_vo
