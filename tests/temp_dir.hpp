#pragma once
// A test's own folder: a fresh, uniquely named folder under the system's temp folder
// (mkdtemp: no two tests or test processes share one, however they run), removed with
// everything in it when the object goes, whether the test passed or failed.
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace millwear::testing {

class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "millwear-test") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  operator const std::filesystem::path&() const { return path_; }  // NOLINT: used as a path
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

  // TEXT written byte for byte to NAME inside the folder (its parent folders made); the path.
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = path_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace millwear::testing
