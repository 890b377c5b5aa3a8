#pragma once
// The output folder option of every command that writes one (-o OUT, screen-task's OUT):
// an existing file given there is bad input (exit 2), caught while the command line is
// parsed, before any work, with one message for every command.
#include <CLI/CLI.hpp>

#include <string>

#include "common/errors.hpp"
#include "io/folder_lock.hpp"

namespace millwear::app {

inline CLI::Validator output_folder() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        try {
          io::check_output_folder(path);
        } catch (const InputError& e) {
          return e.file + ": " + e.expected;  // CLI11 puts the option's name in front
        }
        return "";
      },
      "FOLDER", "output folder");
}

}  // namespace millwear::app
