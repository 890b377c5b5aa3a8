#pragma once
// A run's plan: the designs a set of scene and comparison files name, every one read,
// validated (the scene checks, the numerical limits, the smoothing radius, a name that is
// safe for file names) and fingerprinted before anything runs or is written.
//
// A comparison file:
//   [comparison]
//   name = "sag-2x30-vs-1x30"                        # optional, for the record
//   description = "..."                              # optional
//   designs = ["sag-2x30.toml", "sag-1x30.toml"]     # scene files, relative to this file
//   reference = "sag-1x30"                           # design whose new stage normalises
//                                                    # (default: the first design)
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace millwear::study {

struct DesignInput {
  std::string name;                // names its output files: the design's, or DESIGN.rK
  std::string design;              // the design it is a history of (its scene's name)
  int replicate = 1;               // 1..Plan::replicates: seed = the scene's seed + replicate - 1
  Scene scene;
  std::vector<std::string> files;  // scene file, profile file(s) it reads
  std::string fingerprint;         // of the file contents and fidelity (resume check)
  // `run --continue RUN [--stage N]`: the design goes on from stage N of RUN (its exact
  // state), under this scene's conditions; the scene's clock is set so stage N falls at the
  // hours RUN recorded for it. Empty continue_run: a history from stage 0.
  std::string continue_run;
  int continue_stage = -1;
  double continue_hours = 0.0;
  std::vector<std::string> changes;  // settings that differ from RUN's ("mill.speed...: a -> b")
  // The scene's charge holds other disks than the one stage N started with (another filling,
  // size cut-off or species): stage N goes on with a charge filled anew on its liner, settled
  // and spun up, not the run's.
  bool refill = false;
};

// With replicates, every design runs N histories: replicate 1 under the design's own name and
// seed (the same files and bits as a run without replicates), replicate K under DESIGN.rK with
// seed + K - 1. The designs list holds them design by design.
struct Plan {
  std::vector<DesignInput> designs;
  int replicates = 1;
  std::string reference;
  std::vector<std::string> comparison_files;
  std::string fidelity;  // the override, or the shared fidelity of the scenes, or "mixed"
};

// The most histories per design `--replicates` accepts.
constexpr int kMaxReplicates = 1000;

struct PlanArgs {
  std::vector<std::string> scenes;  // scene or comparison files
  std::string fidelity;             // preset applied to every design ("": each scene's own)
  std::string reference;            // design that normalises ("": the comparison's, else the first)
  std::string out;                  // output folder ("": not checked)
  std::string continue_from;        // a finished run folder whose stage continue_stage each
  int continue_stage = -1;          // design continues from (-1: its last finished stage)
  std::vector<std::string> overrides;  // --set KEY=VALUE, applied to every design's scene
  int replicates = 1;                  // histories per design (seeds s .. s + N - 1)
};

// The scene a command runs: the file with its --set overrides, the fidelity preset when one is
// given ("": the scene's own), then `adjust` (the command's own settings: threads, a window),
// then every check (wear/reshape.hpp's check_scene), before anything is filled or written.
// Throws InputError naming the file and key.
Scene load_checked_scene(const std::string& file, const std::vector<std::string>& overrides,
                         const std::string& fidelity, const std::function<void(Scene&)>& adjust = {});

// Every file a scene reads: the scene file, then each profile file and those its profiles
// read (match_area_of), each once.
std::vector<std::string> scene_input_files(const Scene& scene);

// The design names of a plan, in its order, each once (replicates folded).
std::vector<std::string> design_names(const Plan& plan);

// Throws InputError naming the file and key for anything wrong; nothing is written.
Plan make_plan(const PlanArgs& args);

// Every design that starts a history from stage 0 filled as its run fills it (its starting
// mill, its seed), before any design runs: a filling the fill cannot place is refused as a
// wrong input (InputError naming the scene file and charge.filling), where it would have
// failed that design with the others run. (A design continuing another run with a new charge
// is filled by make_plan.)
void check_fills(const Plan& plan);

// The designs a scene or comparison file names, loaded and checked as make_plan does. Their
// own fidelity is kept.
std::vector<Scene> load_designs(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace millwear::study
