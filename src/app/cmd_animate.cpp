// `millwear animate SCENE -o FILE.gif`: a few seconds of the charge tumbling, for a lecture,
// the liner coloured by its shear work rate or, with --history OUT, stage by stage by its
// wear rate (study/animation.hpp).
// Exit codes: 0 done; 1 gnuplot failed; 2 bad input; 130/143 interrupted (Ctrl-C, SIGTERM: no
// GIF written, the temporary frame folder removed).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

#include "app/commands.hpp"
#include "app/default_text.hpp"
#include "app/fidelity_option.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "app/set_option.hpp"
#include "app/signals.hpp"
#include "study/animation.hpp"

namespace millwear::app {

namespace {

int run_animate(study::AnimationRequest a) {
  refuse_sets_options_give(a.overrides, {{"fidelity", "--fidelity", !a.fidelity.empty()}});
  // Ctrl-C or SIGTERM is heard between pieces of the simulation and once gnuplot has ended;
  // the animation then removes what it made and ends here.
  const SignalScope signals;
  a.stop_signal = &g_signal;
  const study::AnimationOutcome o = study::make_animation(a);
  if (o.stopped_by != 0) {
    std::fprintf(stderr, "millwear animate: interrupted by %s; no GIF written (%s is as it was)%s\n",
                 o.stopped_by == SIGTERM ? "SIGTERM" : "SIGINT", a.out.c_str(),
                 o.data_dir.empty() ? "" : ("; the frame data is kept in " + o.data_dir).c_str());
    return 128 + o.stopped_by;
  }
  const std::string liner =
      o.from_history ? "stages 0-" + std::to_string(o.last_stage) + " by wear rate" : "liner by shear work rate";
  std::printf("%s: %zu frames, %.2f s of the charge (%zu disks), %s; wrote %s in %.1f s\n", o.scene_name.c_str(),
              o.frames, o.seconds, o.disks, liner.c_str(), a.out.c_str(), o.wall_s);
  if (a.keep_data) std::printf("  frame data kept in %s (rerun plots/animate.gp by hand)\n", o.data_dir.c_str());
  return 0;
}

}  // namespace

void register_animate(CLI::App& app, Action* action) {
  auto args = std::make_shared<study::AnimationRequest>();
  CLI::App* cmd = app.add_subcommand(
      "animate", "Animated GIF of the charge tumbling, the liner coloured by shear work rate (teaching demo)");
  cmd->footer(
      "Without --history the liner is coloured by its shear work rate (W/m^2) in the animated\n"
      "seconds. With --history OUT (a `millwear run` folder holding this scene's design) the\n"
      "animation steps through the finished stages' worn liners, coloured by wear rate\n"
      "(mm per 1000 h). Needs gnuplot with the gif terminal.");
  cmd->add_option("scene", args->scene_file, "scene file (TOML)")->required();
  cmd->add_option("-o,--out", args->out, "output file, FILE.gif")->required()->check(output_file());
  cmd->add_option("--seconds", args->seconds, "simulated seconds shown (" + default_text(args->seconds) + ")")
      ->check(finite_in(0.1, 60.0));
  cmd->add_option("--frames", args->frames, "frames in the GIF (" + default_text(args->frames) + ")")->check(whole_in(10, 200));
  cmd->add_option("--size", args->size, "image size in pixels, square (" + default_text(args->size) + ")")->check(whole_in(200, 2000));
  cmd->add_option("--history", args->history, "a finished `millwear run` output folder of this design");
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference (default: the scene's)")->check(fidelity_name());
  add_set_option(cmd, &args->overrides);
  cmd->add_flag("--keep-data", args->keep_data, "keep the frame data next to the GIF (FILE_frames/)");
  cmd->callback([args, action] { *action = [args] { return run_animate(*args); }; });
}

}  // namespace millwear::app
