// `millwear view [SCENE]`: the live mill in a window (src/view/). This file parses, calls and
// prints; a millwear built without the view (MILLWEAR_VIEW=OFF, or Dear ImGui, GLFW or
// OpenGL missing) says so.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

#include "app/commands.hpp"
#include "app/default_text.hpp"
#include "app/fidelity_option.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "common/errors.hpp"
#include "plots/plots.hpp"
#ifdef MILLWEAR_HAVE_VIEW
#include "view/view.hpp"
#endif

namespace millwear::app {

namespace {

struct ViewArgs {
  std::string scene, fidelity, screenshot, script;
  int frames = 0;
  std::vector<int> size{view::ViewRequest{}.width, view::ViewRequest{}.height};
};

// Without a scene: the shipped lab mill (beside the figure scripts, installed or built).
std::string default_scene() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path share = fs::canonical(fs::path(plots::plots_dir()), ec).parent_path();
  const fs::path lab = share / "scenarios" / "lab-mill.toml";
  if (ec || !fs::is_regular_file(lab, ec))
    throw InputError("", "scene", "a scene file (the shipped scenarios/lab-mill.toml was not found)");
  return lab.string();
}

int run_view_command(const ViewArgs& a) {
#ifdef MILLWEAR_HAVE_VIEW
  view::ViewRequest req;
  req.scene_file = a.scene.empty() ? default_scene() : a.scene;
  req.fidelity = a.fidelity;
  req.frames = a.frames;
  req.screenshot = a.screenshot;
  req.script = a.script;
  req.width = a.size[0];
  req.height = a.size[1];
  view::ViewHooks hooks;
  hooks.report = [](const std::string& line) { std::cout << line << std::endl; };
  hooks.notice = [](const std::string& line) { std::cerr << "millwear view: " << line << std::endl; };
  const view::ViewOutcome o = view::run_view(req, hooks);
  if (o.frames > 0 && o.wall_s > 0)
    std::printf("%s: %ld frames in %.2f s wall: %.1f frames/s; %.2f s simulated, simulated/real %.2f; %zu disks\n",
                o.scene_name.c_str(), o.frames, o.wall_s, o.frames / o.wall_s, o.simulated_s, o.simulated_s / o.wall_s,
                o.disks);
  if (o.physics_wall_s > 0)
    std::printf("  the charge's steps alone: %.2f s wall, simulated/real %.2f\n", o.physics_wall_s,
                o.simulated_s / o.physics_wall_s);
  if (!a.screenshot.empty()) std::printf("screenshot: %s\n", a.screenshot.c_str());
  if (o.lost_disks > 0) {
    std::cerr << "millwear: run failed: " << o.lost_disks << " disks were lost (escaped or non-finite)\n";
    return 1;
  }
  return o.refused > 0 ? 2 : 0;
#else
  (void)a;
  throw RunError("this millwear was built without the view (it needs Dear ImGui, GLFW and OpenGL at build time: "
                 "libimgui-dev, libglfw3-dev, libgl-dev, and MILLWEAR_VIEW=ON)");
#endif
}

}  // namespace

void register_view(CLI::App& app, Action* action) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* cmd = app.add_subcommand("view", "The live mill in a window: turn, fill, change lifters and wear it (teaching)");
  cmd->footer(
      "Controls take effect at once; a value the scene checker refuses is refused in the panel\n"
      "with its message. --frames N runs N frames (1/60 s simulated each) without a person and\n"
      "prints the frame rate and the simulated-to-real time ratio; --script FILE plays timed\n"
      "control changes (docs/view.md). Needs a display (xvfb-run works).\n"
      "Exit codes: 0 done, 1 a disk was lost or a window could not open, 2 bad input (a script\n"
      "control the checker refused included).");
  cmd->add_option("scene", args->scene, "scene file (TOML; default: the shipped lab mill)");
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference (default: the scene's)")->check(fidelity_name());
  cmd->add_option("--frames", args->frames, "run this many frames, then stop")->check(whole_in(1, 10000000));
  cmd->add_option("--screenshot", args->screenshot, "write the last frame as a PNG")->check(output_file());
  cmd->add_option("--size", args->size, "window width and height in pixels (" + default_text(args->size) + ")")
      ->expected(2)->check(whole_in(320, 4096));
  cmd->add_option("--script", args->script, "timed control changes (docs/view.md)")->check(CLI::ExistingFile);
  cmd->callback([args, action] { *action = [args] { return run_view_command(*args); }; });
}

}  // namespace millwear::app
