#pragma once
// Running the designs of a plan into one output folder: the library's side of `millwear
// run` and `millwear screen-task`. Designs run in parallel threads (one per design, up to
// jobs); every finished stage is written atomically (the exact stage state for --resume, the
// profile, snapshot and liner files, the tables and the manifest) as it finishes; a resumed
// run continues from the last finished stages and gives the same bits as an uninterrupted
// one. Nothing here prints: the caller watches the run through on_tick.
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "metrics/estimates.hpp"
#include "study/plan.hpp"
#include "wear/history.hpp"

namespace millwear::study {

enum class DesignStatus { Waiting, Running, Done, Failed, Interrupted };
const char* status_name(DesignStatus s);

using Clock = std::chrono::steady_clock;

// One design's run as the caller sees it (read under RunState::mutex).
struct DesignState {
  DesignStatus status = DesignStatus::Waiting;
  std::string error;
  std::map<int, StageRecord> stages;  // light copies: no charge state, no edge rates
  int resumed_up_to = -1;             // stages 0..K were read back from disk
  int copied_up_to = -1;              // of which 0..K came from the run --continue names
  int latest_written = -1;            // stage of the snapshot/liner files
  bool have_history = false;
  double life_h = std::nan("");
  bool life_extrapolated = false;
  double wear_rate_m3_per_J = std::nan("");
  std::vector<std::string> events;
  WearProgress progress;
  Clock::time_point progress_at;      // when progress last came
  Clock::time_point started;
  double wall_s = 0.0;
  std::atomic<bool> stop{false};
};

struct RunOptions {
  std::string out;
  bool resume = false;
  // OUT holds the results of other designs or inputs (its stages/run.key differs): without
  // force the run is refused (InputError); with it, the files that run's manifest lists are
  // deleted first, and nothing else.
  bool force = false;
  // Hold OUT's lock (io/folder_lock.hpp) for the whole run; false when the caller holds it.
  bool lock_folder = true;
  int jobs = 0;                         // designs at once (0: the hardware's cores)
  // Threads of each design's engine step (0: one per kDisksPerStepThread disks of its
  // charge, up to the cores the designs at once leave: cores / jobs, at least 1). The
  // results do not depend on it.
  int threads = 0;
  int stop_after_stage = -1;            // >= 0: stop cleanly after that stage, as if interrupted
  const std::atomic<int>* stop_signal = nullptr;  // non-zero: stop at the next window (a signal number)
  bool figures = true;                  // render the figures at the end
  std::string commit;                   // the program's git commit, for the manifest
  // Called about four times a second from the calling thread, with RunState::mutex held.
  std::function<void()> on_tick;
};

// Everything the run shares between its threads and the caller.
struct RunState {
  explicit RunState(const Plan& p) : plan(p) {}
  const Plan& plan;
  std::vector<std::unique_ptr<DesignState>> designs;
  std::mutex mutex;
  std::string started_text;
  Clock::time_point t0 = Clock::now();
  int jobs = 1;
  int engine_threads = 1;  // threads of each design's engine step
  bool engine_threads_fit_size = false;  // ... at most (no --threads given: SolverDef)
  bool resumed = false;
  std::map<std::string, std::vector<std::string>> copied;  // design -> inputs/ names
  std::set<std::string> written;  // files of the run, relative to OUT (the manifest's list)
};

struct RunOutcome {
  bool failed = false;            // a design failed (the others finished)
  bool interrupted = false;       // stopped by a signal or stop_after_stage: --resume continues
  int signal = 0;                 // the signal that stopped it (0: stop_after_stage)
  bool figures_failed = false;
  std::string figure_error;
  std::size_t figures_written = 0;  // files under OUT/plots (none with figures off or no gnuplot)
  double wall_s = 0.0;
};

// What run_designs checks of OUT before it writes, without writing (`run --check`): throws
// InputError(OUT, "-o", ...) where the run would refuse the folder. Returns what the run would
// do with what OUT holds ("" for a new folder or one of the user's own files alone).
std::string check_run_folder(const Plan& plan, const std::string& out, bool force, bool resume);

// The files an earlier run in OUT wrote, removed: those its manifest lists, and by the names
// millwear gives them the stage files, snapshot and liner of each design its run.key names.
// Nothing else (a user's own files stay), and none of `keep` (the inputs a run reads, which
// may be the copies in OUT/inputs/). run_designs calls it for another run's folder with
// --force and for this same run's without --resume (it starts over); a screen for each
// design's folder when it starts over.
void remove_run_outputs(const std::string& out, const std::vector<std::string>& keep = {});

// Runs every design of the plan into options.out. Throws InputError before anything is
// written when another process is writing into the folder, when the folder holds the
// results of other inputs (unless force) or when --resume meets a damaged stage file.
RunOutcome run_designs(RunState& state, const RunOptions& options);

// Each design's figures with their errors from the stages finished so far (replicates folded;
// one history: its batch means), and every design set against the plan's reference. Caller
// holds state.mutex (or the run has ended).
struct RunEstimates {
  std::vector<DesignEstimate> designs;
  std::vector<DesignEstimate> histories;  // one per plan design, batch-means errors
  std::vector<Verdict> verdicts;
};
RunEstimates run_estimates(const RunState& state);

// Life of a design from its stages so far (a finished history carries its own).
void life_of(const DesignInput& design, const DesignState& state, double& life_h, bool& extrapolated);
// A pattern's life of each kind of lifter from its stages so far (empty for a plain liner).
void kind_lives_of(const DesignInput& design, const DesignState& state, std::vector<double>& life_h,
                   std::vector<bool>& extrapolated);

}  // namespace millwear::study
