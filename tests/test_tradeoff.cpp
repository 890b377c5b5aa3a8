// The speed-against-accuracy runner (wear/tradeoff.hpp): the ladder it builds, the
// profile deviation it measures, the Pareto front it marks. The runs themselves are
// measured by `millwear tradeoff` (README "Speed against accuracy"), not here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>

#include "engine_fixtures.hpp"
#include "scene/fidelity.hpp"
#include "wear/tradeoff.hpp"

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
                                row("mid", 30, 2), row("failed", 1, NAN)};
  rows[4].error = "solver.time_step";
  mark_pareto(rows);
  EXPECT_TRUE(rows[0].pareto);
  EXPECT_TRUE(rows[1].pareto);
  EXPECT_FALSE(rows[2].pareto);  // slower and worse than "fast"
  EXPECT_TRUE(rows[3].pareto);
  EXPECT_FALSE(rows[4].pareto);  // a failed run is never on the front
}

TEST(TradeoffLadder, StartsWithTheReferenceAndMovesOneKnobFromStandard) {
  const Scene scene = load_scene(source_path("scenarios/sag-1x30.toml"));
  TradeoffOptions o;
  o.stages = 1;
  const TradeoffLadder ladder = tradeoff_ladder(scene, o);
  ASSERT_GE(ladder.settings.size(), 3u);
  EXPECT_EQ(ladder.settings[0].label, "reference");
  EXPECT_EQ(ladder.settings[0].scene.fidelity, "reference");
  EXPECT_EQ(ladder.settings[0].scene.wear.stages, 1);
  EXPECT_TRUE(ladder.held_knobs.empty());  // the SAG scene leaves every knob to the preset
  std::set<std::string> knobs;
  const FidelityDef& std_p = fidelity_preset("standard");
  for (const auto& s : ladder.settings) {
    knobs.insert(s.knob);
    if (s.knob == "time_step") {
      // Only the knob moved: the rest is the standard preset.
      EXPECT_EQ(s.scene.solver.velocity_iterations, std_p.velocity_iterations) << s.label;
      EXPECT_DOUBLE_EQ(s.scene.wear.window_revolutions, std_p.window_revolutions) << s.label;
      EXPECT_DOUBLE_EQ(s.scene.mill.mesh.lifter_edge_m, std_p.lifter_edge_m) << s.label;
    }
  }
  for (const char* k : {"preset", "time_step", "iterations", "window", "depth_step", "size_cutoff", "mesh", "smoothing"})
    EXPECT_EQ(knobs.count(k), 1u) << k;
}

TEST(TradeoffLadder, QuickIsThePresetsOnly) {
  TradeoffOptions o;
  o.quick = true;
  const TradeoffLadder ladder = tradeoff_ladder(load_scene(source_path("scenarios/sag-1x30.toml")), o);
  ASSERT_EQ(ladder.settings.size(), 3u);
  EXPECT_EQ(ladder.settings[1].label, "standard");
  EXPECT_EQ(ladder.settings[2].label, "draft");
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
  const std::string out = ::testing::TempDir() + "/tradeoff_bad";
  const std::string cmd = std::string(MILLWEAR_BINARY) + " tradeoff " + source_path("profiles/1x30.toml") +
                          " -o " + out + " --quick > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_FALSE(std::ifstream(out + "/tradeoff.csv").good());
}

}  // namespace
}  // namespace millwear
