#include "study/command_manifest.hpp"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"

#ifndef MILLWEAR_VERSION
#define MILLWEAR_VERSION "unknown"
#endif

namespace millwear::study {

void write_command_manifest(const std::string& out, const CommandRecord& r, const std::string& failure) {
  nlohmann::ordered_json m;
  m["program"] = "millwear";
  m["version"] = MILLWEAR_VERSION;
  m["commit"] = r.commit;
  m["command"] = r.command;
  m["scene_file"] = r.scene_file;
  m["set"] = r.overrides;
  if (!r.fidelity.empty()) m["fidelity"] = r.fidelity;
  if (r.seed) m["seed"] = static_cast<unsigned long long>(*r.seed);
  nlohmann::ordered_json settings = nlohmann::ordered_json::object();
  for (const auto& [key, value] : r.settings) settings[key] = value;
  m["settings"] = settings;
  if (!failure.empty()) {
    m["status"] = "failed";
    m["failure"] = failure;
  }
  std::vector<std::string> files{"manifest.json"};
  for (const std::string& f : r.files) {
    const std::string rel = io::relative_to(out, f);
    const std::string listed = rel.empty() ? f : rel;
    const bool outside = rel.empty() && std::filesystem::path(f).is_absolute();
    if (io::file_exists(outside ? f : io::join_path(out, listed))) files.push_back(listed);
  }
  m["files"] = files;
  io::write_file_atomic(io::join_path(out, "manifest.json"),
                        m.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
}

}  // namespace millwear::study
