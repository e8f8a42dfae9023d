// Running the `relief` binary from a test: exit code and everything it printed.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "tests/test_dir.h"  // tmp()

struct CliRun {
  int code;
  std::string out;  // stdout and stderr
};

// Runs a shell command line with stderr joined to stdout.
inline CliRun run_shell(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  CliRun r{-1, ""};
  FILE* p = popen(cmd.c_str(), "r");
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), p)) r.out += buf.data();
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Runs `relief ARGS`.
inline CliRun run(const std::string& args) {
  return run_shell(std::string(RELIEF_CLI) + " " + args);
}

inline int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}
