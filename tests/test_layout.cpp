// The source layout: every module under src/ includes only itself and the modules the README
// lists before it, so the dependencies form one chain with no cycle.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;

namespace {

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The README's module list: the backquoted names of the paragraph that starts "Source, a
// module a folder", in order ("src/common" read as "common").
std::vector<std::string> readme_module_order() {
  const std::string text = read_text(fs::path(MILLWEAR_SOURCE_DIR) / "README.md");
  const std::size_t start = text.find("Source, a module a folder");
  if (start == std::string::npos) return {};
  const std::size_t end = text.find("\n\n", start);
  const std::string para = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
  std::vector<std::string> order;
  const std::regex quoted("`(src/)?([a-z_]+)`");
  for (auto it = std::sregex_iterator(para.begin(), para.end(), quoted); it != std::sregex_iterator(); ++it)
    order.push_back((*it)[2].str());
  return order;
}

struct Include {
  std::string file;
  int line = 0;
  std::string module;  // the included path's first folder
};

// The quoted includes of a file whose path starts with a folder (not "probe_scene.hpp").
std::vector<Include> module_includes(const fs::path& file) {
  std::vector<Include> found;
  std::ifstream in(file);
  const std::regex include_line("^\\s*#\\s*include\\s*\"([a-z_]+)/[^\"]+\"");
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::smatch m;
    if (std::regex_search(line, m, include_line)) found.push_back({file.string(), n, m[1].str()});
  }
  return found;
}

TEST(Layout, TheReadmeListsEveryModuleOnce) {
  const std::vector<std::string> order = readme_module_order();
  std::vector<std::string> folders;
  for (const auto& entry : fs::directory_iterator(fs::path(MILLWEAR_SOURCE_DIR) / "src"))
    if (entry.is_directory()) folders.push_back(entry.path().filename().string());
  std::vector<std::string> listed = order;
  std::sort(listed.begin(), listed.end());
  std::sort(folders.begin(), folders.end());
  EXPECT_EQ(std::adjacent_find(listed.begin(), listed.end()), listed.end()) << "a module listed twice";
  EXPECT_EQ(listed, folders);
}

TEST(Layout, EveryModuleIncludesOnlyItselfAndTheModulesBeforeIt) {
  const std::vector<std::string> order = readme_module_order();
  ASSERT_FALSE(order.empty());
  const auto rank = [&](const std::string& module) {
    return static_cast<int>(std::find(order.begin(), order.end(), module) - order.begin());
  };
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(MILLWEAR_SOURCE_DIR) / "src")) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
    ++files;
    const std::string module =
        fs::relative(entry.path(), fs::path(MILLWEAR_SOURCE_DIR) / "src").begin()->string();
    ASSERT_LT(rank(module), static_cast<int>(order.size())) << module << " is not in the README's list";
    for (const Include& inc : module_includes(entry.path())) {
      if (rank(inc.module) == static_cast<int>(order.size())) continue;  // not ours (a library's folder)
      EXPECT_LE(rank(inc.module), rank(module))
          << inc.file << ":" << inc.line << ": " << module << " includes " << inc.module << ", listed after it";
    }
  }
  EXPECT_GT(files, 100);
}

// The check itself: an include that points the wrong way is caught.
TEST(Layout, AnIncludeOfALaterModuleIsFound) {
  const TempDir dir("millwear-layout-probe");
  const fs::path file = dir / "probe.cpp";
  std::ofstream(file) << "// a comment\n#include <vector>\n#include \"study/run_designs.hpp\"\n";
  const std::vector<Include> found = module_includes(file);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].module, "study");
  EXPECT_EQ(found[0].line, 3);
  const std::vector<std::string> order = readme_module_order();
  const auto at = [&](const char* m) { return std::find(order.begin(), order.end(), m) - order.begin(); };
  EXPECT_LT(at("geometry"), at("study"));
}

}  // namespace
