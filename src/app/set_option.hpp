#pragma once
// `--set KEY=VALUE` of every command that reads a scene: one override a time, repeatable,
// read by load_scene exactly as the file's keys are (scene/scene.hpp).
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace millwear::app {

inline void add_set_option(CLI::App* cmd, std::vector<std::string>* overrides) {
  cmd->add_option("--set", *overrides,
                  "override a scene key, KEY=VALUE, typed and checked as in the file (repeatable): "
                  "--set mill.speed=0.8 --set charge.filling=0.3")
      ->allow_extra_args(false)
      ->type_name("KEY=VALUE");
}

}  // namespace millwear::app
