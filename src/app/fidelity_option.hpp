#pragma once
// The --fidelity option of every command that has one: a preset's name, checked while the
// command line is parsed (an empty value is a mistake, not "the scene's own").
#include <CLI/CLI.hpp>

#include <string>

#include "common/errors.hpp"
#include "scene/fidelity.hpp"

namespace millwear::app {

inline CLI::Validator fidelity_name() {
  return CLI::Validator(
      [](std::string& name) -> std::string {
        try {
          fidelity_preset(name);
        } catch (const InputError& e) {
          return e.expected;  // CLI11 puts the option's name in front
        }
        return "";
      },
      "{draft,standard,reference}", "fidelity name");
}

// A name option that must not be empty when given (run --reference DESIGN).
inline CLI::Validator non_empty(const std::string& what) {
  return CLI::Validator([what](std::string& s) -> std::string { return s.empty() ? what + ", not an empty text" : ""; },
                        "TEXT", "non-empty");
}

}  // namespace millwear::app
