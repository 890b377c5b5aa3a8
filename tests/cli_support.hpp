#pragma once
// Running the built `millwear` binary from a test: its exit code and everything it printed.
// One copy for every command-line test (app, profile, validation, calibrate, screen).
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
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

// Every file under a folder, hidden ones included (relative path -> content).
inline std::map<std::string, std::string> files_under(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[std::filesystem::relative(e.path(), dir).string()] = read_text(e.path());
  return files;
}

// The files of two such listings that differ ("-NAME" gone, "+NAME" new, "~NAME" changed),
// one a line; "" when they are the same.
inline std::string changed_files(const std::map<std::string, std::string>& before,
                                 const std::map<std::string, std::string>& after) {
  std::string changes;
  for (const auto& [name, text] : before) {
    const auto it = after.find(name);
    if (it == after.end()) changes += "-" + name + "\n";
    else if (it->second != text) changes += "~" + name + "\n";
  }
  for (const auto& [name, text] : after)
    if (!before.count(name)) changes += "+" + name + "\n";
  return changes;
}

}  // namespace millwear::testing
