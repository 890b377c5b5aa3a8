#pragma once
// OUT/manifest.json of the commands that write tables into a folder of their own (charge,
// rule1, tradeoff, validate): the program and its commit, the command and what it read (scene file,
// --set overrides in order, fidelity, seed, the command's own settings) and the files it
// wrote, so that a folder says what made it without its command line.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace millwear::study {

struct CommandRecord {
  std::string command;                 // "charge", "rule1", "tradeoff", "validate"
  std::string commit;                  // the program's (MILLWEAR_COMMIT)
  std::string scene_file;              // a scene, or a comparison file
  std::vector<std::string> overrides;  // --set KEY=VALUE, in order
  std::string fidelity;                // the scene's preset after --fidelity ("": none, not written)
  std::optional<std::uint64_t> seed;   // the scene's solver.seed (none: designs differ)
  std::vector<std::pair<std::string, std::string>> settings;  // the command's own options, as text
  std::vector<std::string> files;      // written into OUT: absolute, or relative to it
};

// Writes OUT/manifest.json atomically. The files are listed relative to OUT, the manifest
// itself with them; a file given that is not there (gnuplot's log of a run without
// figures) is left out.
// `failure`: why the figures written are not the scene's (a disk lost); the manifest then
// says "status": "failed" and gives it as "failure". Empty: neither field.
void write_command_manifest(const std::string& out, const CommandRecord& r, const std::string& failure = "");

}  // namespace millwear::study
