#pragma once
// The tables of a run folder, written from a plain report of the run: summary.csv (one row
// per design and stage), spectrum.csv (the new stage's collision spectrum of each design) and
// manifest.json (what ran, with which settings, how it ended). Units at the file edge: hours,
// mm, mm^2, kW per mill.
#include <map>
#include <string>
#include <vector>

#include "metrics/estimates.hpp"
#include "scene/scene.hpp"
#include "wear/history.hpp"

namespace millwear::study {

struct DesignReport {
  std::string name;                                    // the history's (DESIGN, or DESIGN.rK)
  std::string design;                                  // the design it is a history of
  int replicate = 1;
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
  // Life counted from: the scene's start_hours, or the stage a continued run went on from.
  double life_from_hours = 0.0;
  std::vector<double> kind_life_h;                     // per kind of a pattern
  std::vector<bool> kind_life_extrapolated;
  std::string continue_run;                            // `run --continue`: RUN, its stage, hours
  int continue_stage = -1;
  double continue_hours = 0.0;
  std::vector<std::string> changes;                    // settings changed from RUN's
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
  std::vector<DesignReport> designs;  // every history
  std::vector<std::string> files;  // every file the run wrote, relative to out
  int replicates = 1;              // histories per design
  // Each design's figures with their errors (replicates folded), each history's (with
  // batch-means errors, in the order of `designs`), and every design against the reference.
  std::vector<DesignEstimate> estimates, history_estimates;
  std::vector<Verdict> verdicts;
};

// OUT/summary.csv: one row per design and stage, every figure FIG with its standard error in
// FIG_se beside it; error_source says where the errors come from (replicates, or one
// history's batch_means).
// A run with a design of a pattern of kinds adds, for every kind K, the
// columns kindK_profile, kindK_area_mm2, kindK_area_loss_pct, kindK_height_mm,
// kindK_area_loss_rate_mm2_per_1000h, kindK_life_h (each with its _se beside it, from the
// same source as the design's), kindK_life_extrapolated (empty cells for a design without
// kind K); a run without one has the plain columns only.
void write_summary(const RunReport& report);
// OUT/replicates.csv, with replicates: summary.csv's columns per history (history, replicate,
// seed added), errors from its own batch means.
void write_replicates(const RunReport& report);
std::string replicates_path(const std::string& out);
// OUT/summary.md: every design against the reference, figure by figure: which is ahead, by
// how much, and whether the difference is resolved.
void write_verdicts(const RunReport& report);
std::string verdicts_path(const std::string& out);
// OUT/kinds.csv, when a design has a pattern of kinds of lifter: one row per design, kind and
// stage (design,kind,profile,stage,hours,area_mm2,area_loss_pct,height_mm,
// area_loss_rate_mm2_per_1000h,life_h,life_extrapolated,replacement_height_mm). Not written
// otherwise. summary.csv carries the same figures per kind in kindK_ columns.
void write_kinds(const RunReport& report);
std::string kinds_path(const std::string& out);
// The settings of `design` in run folder RUN's manifest.json that differ from `scene`'s, as
// "section.key: old -> new". Throws InputError(RUN/manifest.json) if it has no such design.
std::vector<std::string> settings_changes(const std::string& run, const std::string& design, const Scene& scene);
// For a command that draws on a finished run (validate --from, animate --history): throws
// InputError(RUN, option, ...) listing settings_changes unless the run was of `scene` as given
// now (its --set and --fidelity included).
void check_run_of_scene(const std::string& run, const Scene& scene, const std::string& option);
void write_spectrum(const RunReport& report);
void write_manifest(const RunReport& report);

}  // namespace millwear::study
