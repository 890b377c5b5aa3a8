#pragma once
// The output folder option of every command that writes one (-o OUT, screen-task's OUT):
// an existing file given there is bad input (exit 2), caught while the command line is
// parsed, before any work, with one message for every command.
#include <CLI/CLI.hpp>

#include <filesystem>
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

// An output file's option (animate -o FILE.gif, view --screenshot FILE.png): not a folder, and
// in a folder that exists or can be made and is writable, checked before any work (the file is
// written last, after the simulation).
inline CLI::Validator output_file() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        std::error_code ec;
        if (std::filesystem::is_directory(path, ec)) return path + ": an output file, but a folder of that name exists";
        try {
          io::check_output_path_text(path, "an output file");
        } catch (const InputError& e) {
          return path + ": " + e.expected;
        }
        const std::string folder = std::filesystem::path(path).parent_path().string();
        if (!folder.empty() && std::filesystem::exists(folder, ec) && !std::filesystem::is_directory(folder, ec))
          return path + ": an output file in a folder, but " + folder + " is a file";
        try {
          io::check_output_folder(folder.empty() ? "." : folder);
        } catch (const InputError& e) {
          return path + ": an output file in " + e.expected;
        }
        return "";
      },
      "FILE", "output file");
}

}  // namespace millwear::app
