#pragma once
// Runs a shell command for end-to-end tests of the executables: its exit code and its output
// (stdout and stderr together). Test-only.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace penumbra::test {

struct RunResult {
  int exitCode = -1;  // -1 when the command could not start or did not exit normally
  std::string output;
};

inline RunResult runCommand(const std::string& command) {
  RunResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace penumbra::test
