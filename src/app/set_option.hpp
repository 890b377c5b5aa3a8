#pragma once
// `--set KEY=VALUE` of every command that reads a scene: one override a time, repeatable,
// read by load_scene exactly as the file's keys are (scene/scene.hpp).
#include <CLI/CLI.hpp>

#include <initializer_list>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "scene/scene.hpp"

namespace millwear::app {

// A scene key one of the command's own options sets as well (--stages: wear.stages), and
// whether that option is in effect.
struct OptionKey {
  const char* key;
  const char* option;
  bool given;
};

// A --set of such a key (or of a key it replaces, or of its table) would be overridden by the
// option without a word, while the manifest still lists it: refused, exit 2, before any work.
inline void refuse_sets_options_give(const std::vector<std::string>& overrides, std::initializer_list<OptionKey> keys) {
  for (const OptionKey& k : keys) {
    if (!k.given) continue;
    const std::string probe = std::string(k.key) + "=0";
    for (const std::string& o : overrides)
      if (override_replaces(o, probe) || override_replaces(probe, o))
        throw InputError("", "--set " + printable(o, 80),
                         std::string("a key other than ") + k.key + ", which " + k.option +
                             " sets in this command and would replace: give one of the two");
  }
}

inline void add_set_option(CLI::App* cmd, std::vector<std::string>* overrides) {
  cmd->add_option("--set", *overrides,
                  "override a scene key, KEY=VALUE, typed and checked as in the file (repeatable): "
                  "--set mill.speed=0.8 --set charge.filling=0.3")
      ->allow_extra_args(false)
      ->type_name("KEY=VALUE");
}

}  // namespace millwear::app
