#pragma once
// `millwear screen SCREEN -o OUT` as one call: the family sampled and its candidates
// written and checked (screen.hpp), then either every unfinished design run by the local
// pool (pool.hpp) and the screen collected (collect.hpp), or a job list for GNU parallel or
// a Slurm array script written for them (jobs.hpp).
//
// OUT holds screen.key (the fingerprint of the screen file, the base scene, the profiles, the
// --set overrides, the replicates and the program version; --resume and --emit keep OUT's
// finished designs only when it is the same; a `set` line per override records them, and
// `replicates` the histories each task runs) and inputs/ (a copy of the screen file). Without --resume or --emit, or with other
// inputs, OUT's designs, logs, job lists, ranking and figures are removed first. Every
// input is validated before anything is written, and OUT is locked (io/folder_lock.hpp) from
// then to the ranking.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "screen/collect.hpp"
#include "screen/pool.hpp"

namespace millwear::screen {

struct ScreenRequest {
  std::string screen_file;
  std::string out;
  bool resume = false;     // keep OUT's finished designs (and stages), run the rest
  std::string emit;        // "parallel" or "slurm": write the jobs instead of running them
  int chunk = 1;           // designs per job or array task (emit)
  int jobs = 0;            // pool: tasks at once (0: the cores); slurm: array tasks at once (0: no limit)
  std::string exe;         // the millwear executable the tasks run ("": self_executable())
  std::vector<std::string> overrides;  // --set KEY=VALUE over the base scene (screen.hpp)
  int replicates = 1;      // histories per design (seeds s .. s + N - 1): life's error from their spread
  bool force = false;      // OUT holds a screen of other inputs: delete its files and start over
};

// The screen file read and checked, its family sampled: nothing written yet.
struct ScreenInputs {
  ScreenDef def;
  std::vector<Candidate> candidates;
  std::vector<std::string> varying;
  std::string fingerprint;       // of the screen file, the base scene, the profiles, the build
};

// OUT once the candidates are written: what is there to run.
struct ScreenSetup {
  std::string name;
  std::size_t candidates = 0, rejected = 0;
  std::vector<Candidate> designs;   // the valid ones, in task order (designs.csv)
  std::vector<int> todo;            // tasks not finished yet
  int already_done = 0;             // kept finished designs (--resume, --emit)
};

struct EmitOutcome {
  std::string path;                 // jobs.txt or screen.sbatch ("" when nothing to emit)
  std::size_t jobs = 0;             // job lines or array tasks
  std::string binary;               // the millwear the jobs run
};

struct ScreenCallbacks {
  std::function<void(const ScreenSetup&)> on_setup;    // OUT prepared, before any job runs
  std::function<void(int jobs)> on_pool_start;          // the pool's callbacks (pool.hpp)
  std::function<void(const PoolProgress&)> on_pool_tick;
  std::function<void()> on_pool_end;
};

struct ScreenOutcome {
  ScreenSetup setup;
  bool emitted = false;
  EmitOutcome emit;
  int signal = 0;                   // the pool was stopped by this signal (OUT kept for --resume)
  CollectOutcome collected;         // when the pool ran to the end (or nothing was left to run)
};

// Throws InputError for bad input (the request, the screen file, its base scene, a family
// with no valid candidate, --resume or --emit on an OUT of other inputs, an OUT another
// process holds).
ScreenOutcome run_screen(const ScreenRequest& request, const std::atomic<int>* stop_signal = nullptr,
                         const ScreenCallbacks& callbacks = {});

// The parts of run_screen: the inputs read (InputError before anything is written); OUT
// prepared (the caller holds OUT's lock); the job list or script written.
ScreenInputs read_screen_inputs(const ScreenRequest& request);
ScreenSetup prepare_screen(const ScreenRequest& request, const ScreenInputs& inputs);
EmitOutcome emit_jobs(const ScreenRequest& request, const ScreenSetup& setup);

}  // namespace millwear::screen
