#pragma once
// Runs the pllvo command-line program (PLLVO_CLI_PATH, set by tests/CMakeLists.txt) the way a
// user would, for the tests of each subcommand's output and exit status.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace pllvo::test {

struct CliResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// `pllvo ARGS`, with `env` (e.g. "PLLVO_MODELS=/tmp/x") in front when given.
inline CliResult run_cli(const std::string& args, const std::string& env = "") {
  const std::string command = env + (env.empty() ? "" : " ") + PLLVO_CLI_PATH + " " + args + " 2>&1";
  CliResult r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace pllvo::test
