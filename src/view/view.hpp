#pragma once
// `millwear view`: the live mill in a window (Dear ImGui on GLFW and OpenGL 3). Everything
// the window shows comes from view::LiveMill (live_mill.hpp), which drives the same library
// calls as `charge` and `run`; nothing of GLFW, OpenGL or ImGui leaves src/view/.
#include <cstddef>
#include <functional>
#include <string>

namespace millwear::view {

struct ViewRequest {
  std::string scene_file;
  std::string fidelity;       // "": the scene's own
  int frames = 0;             // > 0: stop after this many frames (each 1/60 s simulated)
  std::string screenshot;     // PNG of the last frame
  std::string script;         // timed control changes (script.hpp)
  int width = 1280, height = 800;
};

struct ViewHooks {
  std::function<void(const std::string&)> report;   // a `report` line of a script
  std::function<void(const std::string&)> notice;   // a refused control, a lost disk, a file written
};

struct ViewOutcome {
  std::string scene_name;
  long frames = 0;
  double wall_s = 0.0;          // of the frame loop
  double simulated_s = 0.0;     // simulated time the frames advanced
  double physics_wall_s = 0.0;  // of which the charge's steps (the rest draws the frames)
  std::size_t disks = 0;        // active at the end
  std::size_t lost_disks = 0;
  int refused = 0;              // 1 when a script control was refused: the run ended at its line
};

// Throws InputError for a bad scene or script (before a window opens); RunError when no
// window can be opened (no display) or a file cannot be written.
ViewOutcome run_view(const ViewRequest& request, const ViewHooks& hooks);

}  // namespace millwear::view
