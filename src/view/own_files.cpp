// Whether the view may write a file (see own_files.hpp).
#include "view/own_files.hpp"

#include <filesystem>
#include <fstream>

#include "io/run_folder.hpp"

namespace millwear::view {

namespace fs = std::filesystem;

std::string overwrite_refusal(const std::string& file, const std::string& mark, std::size_t at,
                              const std::string& mark_text, const std::vector<RunInput>& inputs) {
  for (const RunInput& in : inputs)
    if (!in.file.empty() && io::is_one_of(file, {in.file})) return "it is " + in.what + ", which the view reads";
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return "";
  if (!fs::is_regular_file(file, ec)) return "something that is not a file is there";
  // Only the mark's bytes are read: a user's file may be large.
  std::ifstream f(file, std::ios::binary);
  std::string head(at + mark.size(), '\0');
  f.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (f.gcount() == static_cast<std::streamsize>(head.size()) && head.compare(at, mark.size(), mark) == 0) return "";
  return "a file is there that millwear view did not write (" + mark_text + "), which is left as it is";
}

}  // namespace millwear::view
