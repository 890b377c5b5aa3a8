// The calibrated copy of a scene (scene/scene_edit.hpp): its text is the scene's own with
// the wear-rate line replaced, so comments and every other key survive.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "common/errors.hpp"
#include "engine_fixtures.hpp"
#include "io/atomic_write.hpp"
#include "scene/scene.hpp"
#include "scene/scene_edit.hpp"
#include "temp_dir.hpp"

namespace millwear {
namespace {

namespace fs = std::filesystem;

const char* kScene =
    "# lab mill for the edit tests\n"
    "name = \"edit\"   # design name\n"
    "\n"
    "[wear]\n"
    "mode = \"staged\"\n"
    "area_loss_rate = 900.0   # mm^2 per 1000 h, from the last relining\n"
    "stage_hours = 50.0       # h\n";

TEST(SceneEdit, TheWearRateKeyIsReplacedAndEverythingElseKept) {
  const std::string dir = ::testing::TempDir();
  const std::string out = calibrated_scene_text(kScene, dir + "/edit.toml", {1.2345678e-10, "fitted", dir});
  EXPECT_EQ(out,
            "# Calibrated copy of " + dir + "/edit.toml written by millwear calibrate (fitted).\n"
            "# lab mill for the edit tests\n"
            "name = \"edit\"   # design name\n"
            "\n"
            "[wear]\n"
            "mode = \"staged\"\n"
            "wear_rate = 1.23457e-10   # m^3/J, fitted\n"
            "stage_hours = 50.0       # h\n");
}

// A [wear] given as an inline table has its other keys after the rate on the same line: the
// key and value alone are replaced, and the copy reads back with every key (the whole line
// replaced left the table unclosed: not TOML).
TEST(SceneEdit, AnInlineWearTableKeepsTheKeysAfterTheRate) {
  const std::string scene = testing::source_path("tests/data/lab-quick.toml");
  std::string text = io::read_file(scene);
  const std::size_t from = text.find("[wear]\n");
  ASSERT_NE(from, std::string::npos);
  const std::size_t to = text.find("\n[", from + 1);
  const Scene original = load_scene(scene);
  // The section's keys, comments dropped, as one inline table: a key of the root table,
  // before the first table's header.
  std::string inline_wear = "wear = { ";
  std::istringstream section(text.substr(from + 7, (to == std::string::npos ? text.size() : to) - from - 7));
  for (std::string line; std::getline(section, line);) {
    line = line.substr(0, line.find('#'));
    while (!line.empty() && line.back() == ' ') line.pop_back();
    if (!line.empty()) inline_wear += (inline_wear.size() > 9 ? ", " : "") + line;
  }
  inline_wear += " }";
  ASSERT_NE(inline_wear.find("wear_rate = 1e-10, factor"), std::string::npos) << inline_wear;
  text.erase(from, (to == std::string::npos ? text.size() : to) - from);
  text.insert(text.find("\n[") + 1, inline_wear + "\n");
  const testing::TempDir dir("millwear-scene-edit-inline");
  const std::string copy = (dir / "inline-calibrated.toml").string();
  const std::string out = calibrated_scene_text(text, scene, {2.5e-10, "fitted", dir.path().string()});
  std::string want = inline_wear;
  want.replace(want.find("1e-10"), 5, "2.5e-10");
  EXPECT_NE(out.find(want), std::string::npos) << out;
  io::write_file_atomic(copy, out);
  const Scene b = load_scene(copy);
  EXPECT_EQ(b.wear.wear_rate_m3_per_J, 2.5e-10);
  EXPECT_EQ(b.wear.stages, 2);
  EXPECT_EQ(b.wear.factor, 1e5);
  EXPECT_EQ(b.mill.lifter.points.size(), original.mill.lifter.points.size());
}

TEST(SceneEdit, AMissingWearRateKeyIsAnInputErrorNamingTheKey) {
  const std::string text = "name = \"edit\"\n[wear]\nmode = \"staged\"   # no rate\n";
  try {
    calibrated_scene_text(text, "edit.toml", {1e-10, "fitted", "."});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "edit.toml");
    EXPECT_EQ(e.where, "wear.wear_rate");
  }
  EXPECT_THROW(calibrated_scene_text("name = \"edit\"\n", "edit.toml", {1e-10, "fitted", "."}), InputError);
  EXPECT_THROW(calibrated_scene_text("name = = 1\n", "edit.toml", {1e-10, "fitted", "."}), InputError);
}

TEST(SceneEdit, TheProfilePathStillResolvesFromTheCopysFolder) {
  // The lab mill's copy in a folder beside scenarios/: the profile path is rewritten so that
  // the copy loads with the same lifter and exactly the new C (6 significant digits).
  const std::string scene = testing::source_path("scenarios/lab-mill.toml");
  const testing::TempDir dir("millwear-scene-edit-copy");
  const std::string copy = (dir / "lab-mill-calibrated.toml").string();
  io::write_file_atomic(copy, calibrated_scene_text(io::read_file(scene), scene, {2.5e-10, "test", dir.path().string()}));
  const Scene a = load_scene(scene), b = load_scene(copy);
  EXPECT_EQ(b.wear.rate_source, WearRateSource::Given);
  EXPECT_EQ(b.wear.wear_rate_m3_per_J, 2.5e-10);
  ASSERT_FALSE(a.mill.lifter.source_file.empty());
  EXPECT_EQ(fs::weakly_canonical(b.mill.lifter.source_file), fs::weakly_canonical(a.mill.lifter.source_file));
  EXPECT_EQ(b.mill.lifter.points.size(), a.mill.lifter.points.size());
  EXPECT_EQ(b.mill.rows, a.mill.rows);
  EXPECT_EQ(b.name, a.name);
}


// A pattern of profiles (hi-lo) is re-pointed as one profile is: each of its paths resolves
// from the copy's folder to the same file, with the line's comment kept.
TEST(SceneEdit, APatternsProfilePathsStillResolveFromTheCopysFolder) {
  const std::string scene = testing::source_path("scenarios/lab-hi-lo.toml");
  const testing::TempDir dir("millwear-scene-edit-pattern");
  fs::create_directories(dir / "sub");
  const std::string copy = (dir / "sub" / "hi-lo.toml").string();
  io::write_file_atomic(copy, edited_scene_text(io::read_file(scene), scene, {{"mill", "speed", "0.8", {}}},
                                                (dir / "sub").string(), "saved"));
  EXPECT_NE(io::read_file(copy).find("# row k: kind k % 2"), std::string::npos) << io::read_file(copy);
  const Scene a = load_scene(scene), b = load_scene(copy);
  ASSERT_EQ(b.mill.pattern.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_EQ(fs::weakly_canonical(b.mill.pattern[k].source_file), fs::weakly_canonical(a.mill.pattern[k].source_file));
  EXPECT_EQ(b.mill.speed_fraction_critical, 0.8);
}


// Key edits (the view's controls and its saved scene): a key's line rewritten from the key to
// the end of its value (to the end of the line, its comment too, where another key replaces it,
// it is removed, or its value is not a number: the comment named the old choice), a missing
// key added at the end of its table, a key removed, a new top-level key and a new table;
// nothing else of the text changes.
const char* kMillScene =
    "name = \"edit\"\n"
    "[mill]\n"
    "speed_rpm = 30.0   # the plant's figure\n"
    "direction = \"bidirectional\"   # as the plant runs it\n"
    "reverse_every = 100.0   # h\n"
    "[charge]\n"
    "filling = 0.3   # of the mill\n"
    "[[charge.species]]\n"
    "name = \"ball\"\n";

TEST(SceneEdit, KeyEditsRewriteAddAndRemoveKeysKeepingTheRest) {
  const std::string dir = ::testing::TempDir();
  const std::string out = edited_scene_text(
      kMillScene, dir + "/edit.toml",
      {{"mill", "speed", "0.8", {"speed_rpm"}},
       {"mill", "direction", "\"reverse\"", {}},
       {"mill", "reverse_every", "", {}},
       {"charge", "ball_filling", "0.1", {}},
       {"charge", "filling", "0.35", {}},
       {"", "fidelity", "\"draft\"", {}},
       {"run", "revolutions", "4", {}}},
      dir, "saved");
  EXPECT_EQ(out,
            "# saved\n"
            "name = \"edit\"\n"
            "fidelity = \"draft\"\n"
            "[mill]\n"
            "speed = 0.8\n"
            "direction = \"reverse\"\n"
            "\n"
            "[charge]\n"
            "filling = 0.35   # of the mill\n"
            "ball_filling = 0.1\n"
            "[[charge.species]]\n"
            "name = \"ball\"\n"
            "\n[run]\nrevolutions = 4\n");
}

// A number's comment that states numbers of the old value goes with it; one of its unit or
// meaning alone stays.
TEST(SceneEdit, ANumbersCommentStatingTheOldValuesFiguresGoesWithIt) {
  const std::string dir = ::testing::TempDir();
  const std::vector<KeyEdit> faster{{"mill", "speed", "2", {}}};
  EXPECT_EQ(edited_scene_text("[mill]\nspeed = 0.75   # fraction of critical (41 rpm)\n", dir + "/e.toml", faster, dir, ""),
            "[mill]\nspeed = 2\n");
  EXPECT_EQ(edited_scene_text("[mill]\nspeed = 0.75   # fraction of critical\n", dir + "/e.toml", faster, dir, ""),
            "[mill]\nspeed = 2   # fraction of critical\n");
}

TEST(SceneEdit, AKeyValueOverSeveralLinesIsNotEditedByGuess) {
  const std::string dir = ::testing::TempDir();
  EXPECT_THROW(edited_scene_text("[mill]\nspeed = [\n0.5]\n", dir + "/e.toml", {{"mill", "speed", "0.8", {}}}, dir, ""),
               RunError);
}

}  // namespace
}  // namespace millwear
