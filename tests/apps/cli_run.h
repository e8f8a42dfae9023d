// Running the `relief` binary from a test: exit code and everything it printed.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "tests/sanitized.h"
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

// Why the CLI cannot render with `--backend gl` here, or "" when it can: a GL context must be
// available (`relief info`), and the build not a sanitizer build. There the instrumented CLI
// would report Mesa's own allocations (not instrumented, still held at exit, from a driver
// already unloaded) as its leaks and exit non-zero; the GL backend is tested in the Release
// suite, as test_gl and test_gl_frames are (scripts/ci-sanitizers.sh).
inline std::string cli_gl_missing() {
  if (relief::test::kSanitizedBuild)
    return "the GL backend's CLI runs are tested in the Release suite, not under a sanitizer";
  if (run("info").out.find("gl: available") == std::string::npos) return "no GL context here";
  return "";
}

inline int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}
