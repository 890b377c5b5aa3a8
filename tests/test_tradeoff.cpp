// The speed-against-accuracy runner (study/tradeoff.hpp): the ladder it builds, the
// profile deviation it measures, the Pareto front it marks. The runs themselves are
// measured by `millwear tradeoff` (README "Speed against accuracy"), not here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "common/errors.hpp"
#include "engine_fixtures.hpp"
#include "scene/fidelity.hpp"
#include "study/tradeoff.hpp"
#include "temp_dir.hpp"

namespace millwear {
namespace {

using testing::source_path;

TEST(TradeoffDeviation, ParallelLinesAreTheirOffsetApart) {
  const Polyline a{{-0.1, 0.0}, {0.1, 0.0}};
  const Polyline b{{-0.1, 0.001}, {0.0, 0.001}, {0.1, 0.001}};
  double max_m = 0.0, mean_m = 0.0;
  profile_deviation(a, b, 0.001, max_m, mean_m);
  EXPECT_NEAR(max_m, 0.001, 1e-12);
  EXPECT_NEAR(mean_m, 0.001, 1e-12);
}

TEST(TradeoffDeviation, ABumpCountsInTheLargestButLittleInTheMean) {
  // A 2 mm bump 1 mm wide on a 200 mm line: largest 2 mm, mean about 2 mm x 1/200 x 1/2 x 2.
  const Polyline flat{{-0.1, 0.0}, {0.1, 0.0}};
  const Polyline bump{{-0.1, 0.0}, {-0.0005, 0.0}, {0.0, 0.002}, {0.0005, 0.0}, {0.1, 0.0}};
  double max_m = 0.0, mean_m = 0.0;
  profile_deviation(bump, flat, 0.0001, max_m, mean_m);
  EXPECT_NEAR(max_m, 0.002, 1e-12);
  EXPECT_LT(mean_m, 0.0001);
}

TradeoffRow row(const std::string& label, double cpu_s, double dev_pct) {
  TradeoffRow r;
  r.label = label;
  r.cpu_s = cpu_s;
  r.dev_max_pct = dev_pct;
  return r;
}

TEST(TradeoffPareto, DominatedRowsAreOffTheFront) {
  std::vector<TradeoffRow> rows{row("ref", 100, 0), row("fast", 10, 5), row("slow-bad", 50, 6),
                                row("mid", 30, 2), row("failed", 1, NAN), row("failed-fast", 0.5, 0)};
  rows[4].error = "solver.time_step";
  rows[5].error = "lost disks";  // its figures would dominate every row: they count for nothing
  mark_pareto(rows);
  EXPECT_TRUE(rows[0].pareto);
  EXPECT_TRUE(rows[1].pareto);
  EXPECT_FALSE(rows[2].pareto);  // slower and worse than "fast"
  EXPECT_TRUE(rows[3].pareto);
  EXPECT_FALSE(rows[4].pareto);  // a failed run is never on the front
  EXPECT_FALSE(rows[5].pareto);
}

TEST(TradeoffLadder, StartsWithTheReferenceAndMovesOneKnobFromStandard) {
  const Scene scene = load_scene(source_path("scenarios/sag-1x30.toml"));
  TradeoffOptions o;
  o.stages = 1;
  const TradeoffLadder ladder = tradeoff_ladder(scene, o);
  ASSERT_GE(ladder.settings.size(), 3u);
  EXPECT_EQ(ladder.settings[0].label, "reference");
  EXPECT_EQ(ladder.settings[0].scenes[0].fidelity, "reference");
  EXPECT_EQ(ladder.settings[0].scenes[0].wear.stages, 1);
  EXPECT_TRUE(ladder.held_knobs.empty());  // the SAG scene leaves every knob to the preset
  std::set<std::string> knobs;
  const FidelityDef& std_p = fidelity_preset("standard");
  for (const auto& s : ladder.settings) {
    knobs.insert(s.knob);
    if (s.knob == "time_step") {
      // Only the knob moved: the rest is the standard preset.
      EXPECT_EQ(s.scenes[0].solver.velocity_iterations, std_p.velocity_iterations) << s.label;
      EXPECT_DOUBLE_EQ(s.scenes[0].wear.window_revolutions, std_p.window_revolutions) << s.label;
      EXPECT_DOUBLE_EQ(s.scenes[0].mill.mesh.lifter_edge_m, std_p.lifter_edge_m) << s.label;
      EXPECT_EQ(s.scenes[0].solver.backend, std_p.backend) << s.label;
    }
    if (s.knob == "backend") {
      EXPECT_NE(s.scenes[0].solver.backend, std_p.backend) << s.label;
    }
  }
  for (const char* k : {"preset", "backend", "time_step", "window", "depth_step", "size_cutoff", "mesh", "smoothing"})
    EXPECT_EQ(knobs.count(k), 1u) << k;
  // The solver knob that means something for standard's backend, and not the other.
  const bool soft = std_p.backend == Backend::Soft;
  EXPECT_EQ(knobs.count("substeps"), soft ? 1u : 0u);
  EXPECT_EQ(knobs.count("iterations"), soft ? 0u : 1u);
}

TEST(TradeoffLadder, AComparisonLaddersEveryDesignTogether) {
  const Scene a = load_scene(source_path("scenarios/sag-2x30.toml"));
  const Scene b = load_scene(source_path("scenarios/sag-1x30.toml"));
  TradeoffOptions o;
  o.stages = 2;
  const TradeoffLadder ladder = tradeoff_ladder(std::vector<Scene>{a, b}, o);
  ASSERT_GE(ladder.settings.size(), 3u);
  for (const auto& s : ladder.settings) {
    ASSERT_EQ(s.scenes.size(), 2u) << s.label;
    EXPECT_EQ(s.scenes[0].name, a.name);
    EXPECT_EQ(s.scenes[1].name, b.name);
    // The same numerical settings on both designs; the designs keep their own lifters.
    EXPECT_DOUBLE_EQ(s.scenes[0].solver.time_step_s, s.scenes[1].solver.time_step_s) << s.label;
    EXPECT_EQ(s.scenes[0].solver.backend, s.scenes[1].solver.backend) << s.label;
    EXPECT_DOUBLE_EQ(s.scenes[0].wear.max_depth_step_m, s.scenes[1].wear.max_depth_step_m) << s.label;
    EXPECT_EQ(s.scenes[1].wear.stages, 2) << s.label;
    EXPECT_NE(s.scenes[0].mill.direction, s.scenes[1].mill.direction) << s.label;
  }
  // A knob one design's file sets is held for the whole comparison.
  Scene held = b;
  held.explicit_keys.insert("wear.window_revolutions");
  const TradeoffLadder l2 = tradeoff_ladder(std::vector<Scene>{a, held}, o);
  for (const auto& s : l2.settings) EXPECT_NE(s.knob, "window") << s.label;
  EXPECT_EQ(l2.held_knobs.size(), 1u);
}

TEST(TradeoffLadder, QuickIsThePresetsOnly) {
  TradeoffOptions o;
  o.quick = true;
  const TradeoffLadder ladder = tradeoff_ladder(load_scene(source_path("scenarios/sag-1x30.toml")), o);
  ASSERT_EQ(ladder.settings.size(), 3u);
  EXPECT_EQ(ladder.settings[1].label, "standard");
  EXPECT_EQ(ladder.settings[2].label, "draft");
}

TEST(TradeoffLadder, ReseededReferenceAndStandardMeasureTheNoise) {
  const Scene scene = load_scene(source_path("scenarios/sag-1x30.toml"));
  const TradeoffLadder ladder = tradeoff_ladder(scene, {});
  int seeds = 0;
  for (const auto& s : ladder.settings) {
    if (s.knob != "seed") continue;
    ++seeds;
    const bool ref = s.label.rfind("reference", 0) == 0;
    Scene preset = scene;
    apply_fidelity(preset, ref ? "reference" : "standard");
    // Only the seed differs from the preset run.
    EXPECT_EQ(s.scenes[0].solver.seed, preset.solver.seed + 1) << s.label;
    EXPECT_EQ(s.scenes[0].fidelity, preset.fidelity) << s.label;
    EXPECT_DOUBLE_EQ(s.scenes[0].solver.time_step_s, preset.solver.time_step_s) << s.label;
    EXPECT_DOUBLE_EQ(s.scenes[0].wear.window_revolutions, preset.wear.window_revolutions) << s.label;
  }
  EXPECT_EQ(seeds, 2);
}

TEST(TradeoffLadder, OnlyKeepsTheReferenceAndTheNamedSettings) {
  const Scene scene = load_scene(source_path("scenarios/sag-1x30.toml"));
  TradeoffOptions o;
  o.only = {"window=4", "standard"};
  const TradeoffLadder ladder = tradeoff_ladder(scene, o);
  ASSERT_EQ(ladder.settings.size(), 3u);
  EXPECT_EQ(ladder.settings[0].label, "reference");
  EXPECT_EQ(ladder.settings[1].label, "standard");  // in the ladder's order
  EXPECT_EQ(ladder.settings[2].label, "window=4");
  o.only = {"standard", "window=5"};
  try {
    tradeoff_ladder(scene, o);
    ADD_FAILURE() << "an unknown label was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--only");
    EXPECT_NE(std::string(e.what()).find("window=5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("window=4"), std::string::npos) << e.what();  // lists the labels
  }
  // A label twice was run once and recorded twice.
  o.only = {"standard", "window=4", "standard"};
  try {
    tradeoff_ladder(scene, o);
    ADD_FAILURE() << "a label given twice was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--only");
    EXPECT_NE(std::string(e.what()).find("each label once, got \"standard\" twice"), std::string::npos) << e.what();
  }
}

TEST(TradeoffLadder, KnobsTheSceneSetsAreHeld) {
  // The lab mill sets its own time step, mesh, window, depth step and smoothing.
  const TradeoffLadder ladder = tradeoff_ladder(testing::lab_mill(), {});
  EXPECT_GE(ladder.held_knobs.size(), 5u);
  for (const auto& s : ladder.settings) {
    EXPECT_NE(s.knob, "time_step");
    EXPECT_NE(s.knob, "mesh");
  }
}

TEST(TradeoffCli, BadSceneIsExitTwoAndWritesNothing) {
  const testing::TempDir dir("millwear-tradeoff-bad");
  const std::string out = (dir / "out").string();
  const std::string cmd = std::string(MILLWEAR_BINARY) + " tradeoff " + source_path("profiles/1x30.toml") +
                          " -o " + out + " --quick > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_FALSE(std::ifstream(out + "/tradeoff.csv").good());
}

// The folder records what made it: the scene, the --set overrides in order, the seed they
// give, the command's settings and every file written. A label's spaces around it are not
// part of it.
TEST(TradeoffCli, TheManifestRecordsTheOverridesSettingsAndFiles) {
  namespace fs = std::filesystem;
  const testing::TempDir dir("millwear-tradeoff-manifest");
  const fs::path out = dir / "out";
  const auto r = testing::run_millwear("tradeoff " + testing::quoted(source_path("scenarios/lab-mill.toml")) +
                                       " -o " + testing::quoted(out) +
                                       " --only ' draft' --stages 1 --stage-hours 1 --no-plot"
                                       " --set solver.seed=5 --set charge.filling=0.3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto m = nlohmann::json::parse(testing::read_text(out / "manifest.json"));
  EXPECT_EQ(m["command"], "tradeoff");
  EXPECT_EQ(m["set"], nlohmann::json::array({"solver.seed=5", "charge.filling=0.3"}));
  EXPECT_EQ(m["seed"], 5);
  EXPECT_EQ(m["settings"]["only"], "draft");
  EXPECT_EQ(m["settings"]["stages"], "1");
  for (const std::string f : m["files"]) EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
  EXPECT_NE(std::find(m["files"].begin(), m["files"].end(), "tradeoff.csv"), m["files"].end());
  fs::remove_all(out);
}

// A history that stops (here rule 1's bound on wear.factor at the first update) is a failed
// setting, not a result: with the reference's failed, the ladder has nothing to compare
// against, and the command exits 1 naming the failure, with no table of zero deviations.
TEST(TradeoffCli, AHistoryThatStopsIsAFailureNotAResult) {
  namespace fs = std::filesystem;
  const testing::TempDir dir("millwear-tradeoff-fails");
  const auto r = testing::run_millwear("tradeoff " + testing::quoted(source_path("scenarios/lab-mill.toml")) +
                                       " -o " + testing::quoted(dir / "out") +
                                       " --quick --stages 1 --no-plot --set wear.mode=continuous"
                                       " --set wear.factor=3e6");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("the reference run failed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lower wear.factor"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "tradeoff.csv"));
}

// A ladder of one setting (--only reference) has nothing to trade off: no figure, and exit 0
// (gnuplot crashed on its empty x range). Without gnuplot the tables stand alone: a warning
// and exit 0, as for every command.
TEST(TradeoffCli, OneSettingDrawsNoFigureAndNoGnuplotIsAWarning) {
  namespace fs = std::filesystem;
  const testing::TempDir dir("millwear-tradeoff-figure");
  const std::string lab = testing::quoted(source_path("scenarios/lab-mill.toml"));
  auto r = testing::run_millwear("tradeoff " + lab + " -o " + testing::quoted(dir / "one") +
                                 " --only reference --stages 1 --stage-hours 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no figure: one setting, nothing to trade off"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir / "one" / "tradeoff.csv"));
  r = testing::run_shell("env PATH=" + testing::quoted(dir.path()) + " \"" + MILLWEAR_BINARY + "\" tradeoff " + lab +
                         " -o " + testing::quoted(dir / "bare") + " --only draft --stages 1 --stage-hours 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: figures: gnuplot not found"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir / "bare" / "tradeoff.csv"));
  EXPECT_FALSE(fs::exists(dir / "bare" / "tradeoff.png"));
}

TEST(TradeoffLadder, AFineChargeLaddersTheFiftyMillimetreCutOff) {
  const Scene fine = load_scene(source_path("scenarios/sag-2x30-fine.toml"));
  TradeoffOptions o;
  o.stages = 2;
  std::set<std::string> cuts;
  for (const auto& s : tradeoff_ladder(fine, o).settings)
    if (s.knob == "size_cutoff") cuts.insert(s.label);
  // Rock classes 25, 37.5, 62.5 ... mm: 1.25 and 1.5 x the smallest (31.25 and 37.5 mm) both
  // drop the 25 mm class alone, so only the first is laddered; 50 mm drops 25 and 37.5 (25 mm
  // would cut nothing).
  EXPECT_EQ(cuts, (std::set<std::string>{"size_cutoff=31.25mm", "size_cutoff=50mm"}));
  // The default comparison's rocks start at 100 mm: no absolute rows there.
  std::set<std::string> coarse;
  for (const auto& s : tradeoff_ladder(load_scene(source_path("scenarios/sag-2x30.toml")), o).settings)
    if (s.knob == "size_cutoff") coarse.insert(s.label);
  EXPECT_EQ(coarse, (std::set<std::string>{"size_cutoff=125mm", "size_cutoff=150mm"}));
}

}  // namespace
}  // namespace millwear
