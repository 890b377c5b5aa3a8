#pragma once
// Running the built `millwear` binary from a test: its exit code and everything it printed.
// One copy for every command-line test (app, profile, validation, calibrate, screen).
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace millwear::testing {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// A shell command line, stderr folded into stdout.
inline CliResult run_shell(const std::string& command) {
  CliResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  std::size_t got;
  while ((got = fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, got);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// `millwear ARGS` (ARGS already quoted as the shell needs).
inline CliResult run_millwear(const std::string& args) {
  return run_shell(std::string("\"") + MILLWEAR_BINARY + "\" " + args);
}

// A path in double quotes for the shell.
inline std::string quoted(const std::filesystem::path& p) { return "\"" + p.string() + "\""; }

// A whole file as text ("" if it cannot be read).
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace millwear::testing
