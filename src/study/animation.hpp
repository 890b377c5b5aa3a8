#pragma once
// A few seconds of the charge tumbling as an animated GIF, for a lecture
// (`millwear animate`).
//
// Without a history the liner is coloured by the shear work rate it takes during the
// animated seconds (W/m^2). With a history (a `millwear run` folder holding the scene's
// design) the animation walks through the finished stages: each stage's worn liner in turn
// (set_liner, the charge keeps moving), coloured by that stage's wear rate (mm per 1000 h,
// the rates behind OUT/liner_DESIGN.csv). The frames go to plots/animate.gp as one data file
// (disks, then the liner path, per frame) and a gnuplot file of titles and the colour scale.
#include <atomic>
#include <cstddef>
#include <string>
#include <vector>

namespace millwear::study {

struct AnimationRequest {
  std::string scene_file;
  std::string out;             // FILE.gif
  std::string history;         // a `millwear run` folder, or "" for the new liner
  std::string fidelity;        // "": the scene's own
  std::vector<std::string> overrides;  // --set KEY=VALUE (scene/scene.hpp)
  double seconds = 3.0;        // simulated seconds shown
  int frames = 60;
  int size = 640;              // pixels, square
  bool keep_data = false;      // keep the frame files in FILE_frames/ (else a temporary folder)
  // Non-zero: stop (a signal number). Heard between pieces of the settling and of every
  // frame's steps, and once gnuplot has ended.
  const std::atomic<int>* stop_signal = nullptr;
};

struct AnimationOutcome {
  std::string scene_name;
  std::size_t frames = 0;
  std::size_t disks = 0;
  bool from_history = false;
  int last_stage = 0;          // with a history: the last stage shown
  double seconds = 0.0;        // simulated seconds shown: frames x whole time steps per frame
  std::string data_dir;        // the frame files, when kept
  double wall_s = 0.0;
  // The signal that stopped it (0: none). A stopped animation writes no GIF (an earlier one
  // at FILE stays) and leaves no temporary folder; with keep_data, frame files it finished
  // stay in FILE_frames/ (data_dir).
  int stopped_by = 0;
};

// Throws InputError for a bad scene (or one outside the run limits), an output name not ending in .gif, frames
// shorter than the scene's time step (--frames), or a history folder without finished stages of the scene's
// design; RunError when gnuplot fails. A stop (stop_signal) is an outcome, not an error.
AnimationOutcome make_animation(const AnimationRequest& request);

}  // namespace millwear::study
