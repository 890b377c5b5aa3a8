#pragma once
// The tables of a run folder, written from a plain report of the run: summary.csv (one row
// per design and stage), spectrum.csv (the new stage's collision spectrum of each design) and
// manifest.json (what ran, with which settings, how it ended). Units at the file edge: hours,
// mm, mm^2, kW per mill.
#include <map>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "wear/history.hpp"

namespace millwear::io {

struct DesignReport {
  std::string name;
  const Scene* scene = nullptr;
  std::vector<std::string> input_files, input_copies;  // as given; copies under OUT/inputs/
  std::string status;                                  // waiting, running, finished, failed, interrupted
  std::string error;
  int resumed_stages = 0;                              // stages read back from disk
  double life_h = 0.0;                                 // NaN: not known yet
  bool life_extrapolated = true;
  double wear_rate_m3_per_J = 0.0;
  std::map<int, StageRecord> stages;                   // light records (no charge state)
  std::vector<std::string> events;
};

struct RunReport {
  std::string out;
  std::string program_version, program_commit;
  std::string started;       // local time, ISO 8601
  bool finished = false;
  double wall_s = 0.0;
  std::string fidelity, reference;
  bool resumed = false;
  int jobs = 1;
  std::vector<std::string> comparison_files;
  std::vector<DesignReport> designs;
  std::vector<std::string> files;  // every file the run wrote, relative to out
};

void write_summary(const RunReport& report);
void write_spectrum(const RunReport& report);
void write_manifest(const RunReport& report);

// The `files` list of OUT/manifest.json (paths relative to OUT): what a run wrote. Empty if
// there is no manifest, it does not parse or it has no list (an older millwear's).
std::vector<std::string> manifest_files(const std::string& out);

}  // namespace millwear::io
