// What the study commands' library calls hand back and write, on small made-up inputs.
// The commands end to end are tests/test_app_run.cpp, tests/test_calibrate_cli.cpp and
// tests/test_tradeoff.cpp.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "common/errors.hpp"
#include "engine_fixtures.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "plots/plots.hpp"
#include "study/animation.hpp"
#include "study/calibration_run.hpp"
#include "study/plan.hpp"
#include "study/run_designs.hpp"
#include "study/run_progress.hpp"
#include "study/tradeoff_study.hpp"
#include "study/validation_run.hpp"
#include "temp_dir.hpp"

namespace millwear {
namespace {

namespace fs = std::filesystem;

StageRecord stage(int k, double hours, double area_m2, double power_kW_per_m, double collision_kW_per_m) {
  StageRecord r;
  r.stage = k;
  r.hours = hours;
  r.lifter.area_m2 = area_m2;
  r.lifter.height_m = 0.02;
  r.charge.power_kW_per_m = power_kW_per_m;
  r.charge.collision_kW_per_m = collision_kW_per_m;
  return r;
}

struct OneDesignRun {
  study::Plan plan;
  std::unique_ptr<study::RunState> state;
  OneDesignRun() {
    Scene s;
    s.mill.length_m = 2.0;
    s.wear.stages = 4;
    s.wear.stage_hours = 100.0;
    plan.designs.push_back({"lab", "lab", 1, s, {}, "", "", -1, 0.0, {}});
    plan.reference = "lab";
    state = std::make_unique<study::RunState>(plan);
    state->designs.push_back(std::make_unique<study::DesignState>());
  }
  study::DesignState& design() { return *state->designs[0]; }
};

TEST(CalibrationTables, TheResidualUnitFollowsWhatWasFitted) {
  const testing::TempDir dir("millwear-study-calibration");
  const std::string out = dir.path().string();
  validation::CalibrationResult res;
  validation::CalibrationRun run;
  run.run = 1;
  run.fit.rms = 2e-6;
  res.runs = {run};
  res.survey_hours = {50.0, 100.0};
  res.survey_c = {1e-10, 1.1e-10};
  res.fit_error_known = false;
  validation::write_calibration_tables(out, res, true);
  const io::CsvData areas = io::read_csv(out + "/calibration.csv");
  EXPECT_DOUBLE_EQ(areas.number(0, "rms_mm2"), 2.0);
  EXPECT_EQ(io::read_csv(out + "/calibration_surveys.csv").row_count(), 2u);
  const io::CsvData result = io::read_csv(out + "/calibration_result.csv");
  EXPECT_EQ(result.text(0, result.column("fit_on")), "area_loss");
  // One worn area: the fit's error unknown, an empty cell (a 0 would say the fit has none).
  EXPECT_EQ(result.text(0, result.column("fit_error_known")), "0");
  EXPECT_EQ(result.text(0, result.column("sigma_fit_m3_per_J")), "");
  res.fit_error_known = true;
  res.sigma_fit_m3_per_J = 3e-12;
  validation::write_calibration_tables(out, res, true);
  EXPECT_DOUBLE_EQ(io::read_csv(out + "/calibration_result.csv").number(0, "sigma_fit_m3_per_J"), 3e-12);
  validation::write_calibration_tables(out, res, false);
  EXPECT_NEAR(io::read_csv(out + "/calibration.csv").number(0, "rms_mm"), 0.002, 1e-15);
}

// The spread of the surveys' own estimates is known from two worn surveys on; with one it is
// an empty cell, not a spread of 0 (the fit keeps its default there).
TEST(CalibrationTables, TheSurveysSpreadIsEmptyWithOneWornSurvey) {
  const testing::TempDir dir("millwear-study-calibration-spread");
  const std::string out = dir.path().string();
  validation::CalibrationResult res;
  validation::CalibrationRun one, two;
  one.run = 1;
  one.fit.sigma_curvature = 0.02;
  one.fit.survey_hours = {100.0};
  one.fit.survey_scale = {1.1};
  two.run = 2;
  two.fit.sigma_curvature = 0.02;
  two.fit.sigma_spread = 0.03;
  two.fit.survey_hours = {50.0, 100.0};
  two.fit.survey_scale = {1.0, 1.06};
  res.runs = {one, two};
  validation::write_calibration_tables(out, res, true);
  const io::CsvData runs = io::read_csv(out + "/calibration.csv");
  const std::size_t spread = runs.column("sigma_scale_spread");
  EXPECT_EQ(runs.text(0, spread), "");
  EXPECT_DOUBLE_EQ(runs.number(1, "sigma_scale_spread"), 0.03);
  EXPECT_DOUBLE_EQ(runs.number(0, "sigma_scale_curvature"), 0.02);
}

TEST(ValidationFiles, AProfileBlockIsATitleThenMillimetrePoints) {
  const Polyline line{{-0.01, 0.0}, {0.0025, 0.02}};
  EXPECT_EQ(validation::profile_block("50 h", line, true), "50 h,-\n-10,0\n2.5,20\n");
  EXPECT_EQ(validation::profile_block("100 h", line, false), "\n\n100 h,-\n-10,0\n2.5,20\n");
}

TEST(TradeoffFiles, LengthsAndAreasAreWrittenInMillimetres) {
  const testing::TempDir dir("millwear-study-tradeoff");
  const std::string out = dir.path().string();
  TradeoffReport r;
  r.scene_name = "lab";
  r.design_names = {"lab"};
  r.lifter_height_m = {0.02};
  r.lifter_area_m2 = {4.3e-4};
  TradeoffRow row;
  row.label = "reference";
  row.knob = "preset";
  row.dev_max_m = 0.0015;
  row.pareto = true;
  TradeoffDesign d;
  d.name = "lab";
  d.final_area_m2 = 3.5e-4;
  d.final_height_m = 0.018;
  d.final_profile = {{-0.01, 0.0}, {0.0, 0.018}};
  row.designs = {d};
  r.rows = {row};
  write_tradeoff_files(r, out);
  const io::CsvData t = io::read_csv(out + "/tradeoff.csv");
  EXPECT_DOUBLE_EQ(t.number(0, "dev_max_mm"), 1.5);
  const io::CsvData per = io::read_csv(out + "/tradeoff_designs.csv");
  EXPECT_DOUBLE_EQ(per.number(0, "final_area_mm2"), 350.0);
  EXPECT_DOUBLE_EQ(per.number(0, "final_height_mm"), 18.0);
  const io::CsvData prof = io::read_csv(out + "/tradeoff_profiles.csv");
  ASSERT_EQ(prof.row_count(), 2u);
  EXPECT_DOUBLE_EQ(prof.number(1, "y_mm"), 18.0);
  EXPECT_EQ(io::read_csv(out + "/tradeoff_front.csv").row_count(), 1u);
  EXPECT_NE(io::read_file(out + "/tradeoff.md").find("new lifter 20.0 mm high, 430 mm^2"), std::string::npos);
}

TEST(Animation, AnOutputThatIsNotAGifIsAnInputErrorBeforeAnythingRuns) {
  study::AnimationRequest r;
  r.scene_file = testing::source_path("tests/data/lab-quick.toml");
  const testing::TempDir dir("millwear-study-animation");
  r.out = (dir / "charge.png").string();
  try {
    study::make_animation(r);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "-o");
  }
  r.scene_file = "no-such-scene.toml";
  EXPECT_THROW(study::make_animation(r), InputError);
}

// Without gnuplot the GIF cannot be drawn: said at once, before any simulation, and
// nothing written.
TEST(Animation, WithoutGnuplotNothingRunsAndTheErrorSaysSo) {
  study::AnimationRequest r;
  r.scene_file = testing::source_path("tests/data/lab-quick.toml");
  const testing::TempDir dir("millwear-study-animation-bare");
  r.out = (dir / "charge.gif").string();
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", dir.path().c_str(), 1);  // a folder without gnuplot
  std::string msg;
  try {
    study::make_animation(r);
  } catch (const RunError& e) {
    msg = e.what();
  }
  ::setenv("PATH", old_path.c_str(), 1);
  EXPECT_NE(msg.find("gnuplot not found on PATH"), std::string::npos) << msg;
  EXPECT_NE(msg.find("nothing was simulated or written"), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(dir / "charge.gif"));
  EXPECT_FALSE(std::filesystem::exists(dir / "charge_frames"));
}

TEST(Animation, AHistoryWithoutTheDesignsStagesIsAnInputError) {
  study::AnimationRequest r;
  r.scene_file = testing::source_path("tests/data/lab-quick.toml");
  const testing::TempDir dir("millwear-study-animation-history"), run("millwear-study-animation-empty-run");
  r.out = (dir / "charge.gif").string();
  r.history = run.path().string();
  try {
    study::make_animation(r);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--history");
  }
}

// The frames name the species as the scene does and colour them as the snapshots do.
TEST(Animation, TheFramesNameAndColourTheScenesSpecies) {
  const testing::TempDir scratch("millwear-study-animation-species");
  const std::string dir = scratch.path().string();
  study::AnimationRequest r;
  r.scene_file = testing::source_path("tests/data/lab-quick.toml");
  r.out = dir + "/charge.gif";
  r.frames = 10;
  r.seconds = 0.2;
  r.size = 200;
  r.keep_data = true;
  study::make_animation(r);
  const std::string meta = io::read_file(dir + "/charge_frames/frames_meta.gp");
  EXPECT_NE(meta.find("sp_name[1] = \"ball\""), std::string::npos) << meta;
  // Balls take the first ball colour, #4f6d8f.
  EXPECT_NE(meta.find("sp_rgb[1] = " + std::to_string(0x4f6d8f)), std::string::npos) << meta;
  EXPECT_EQ(plots::species_colours({true, false, false, true}),
            (std::vector<std::string>{"#4f6d8f", "#a08c70", "#c2b59b", "#7d9bbd"}));
}

// --keep-data writes into FILE_frames/: an earlier animation's folder is written again, a
// folder holding anything of the user's (even under the name frames.dat) is refused before
// anything runs, and the user's file stays.
TEST(Animation, KeptFramesGoOnlyIntoAFolderAnAnimationLeft) {
  const testing::TempDir scratch("millwear-study-animation-keep");
  const std::string dir = scratch.path().string();
  study::AnimationRequest r;
  r.scene_file = testing::source_path("tests/data/lab-quick.toml");
  r.frames = 10;
  r.seconds = 0.2;
  r.size = 200;
  r.keep_data = true;
  r.out = dir + "/charge.gif";
  study::make_animation(r);
  study::make_animation(r);  // its own earlier frames: written again
  EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/charge_frames/frames.dat"));

  std::filesystem::create_directories(dir + "/mine_frames");
  std::ofstream(dir + "/mine_frames/frames.dat") << "mine\n";
  r.out = dir + "/mine.gif";
  try {
    study::make_animation(r);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--keep-data");
    EXPECT_NE(std::string(e.what()).find("mine_frames"), std::string::npos) << e.what();
  }
  EXPECT_EQ(io::read_file(dir + "/mine_frames/frames.dat"), "mine\n");
  EXPECT_FALSE(std::filesystem::exists(dir + "/mine.gif"));
}

// A stop that comes once every design has finished (here at the last progress tick, before
// the figures) finds the run finished: its figures are drawn, it is not an interruption and
// its manifest says finished.
TEST(RunDesigns, AStopAfterTheLastStageLeavesTheRunFinished) {
  const testing::TempDir dir("millwear-study-late-stop");
  study::PlanArgs args;
  args.scenes = {std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml"};
  args.fidelity = "draft";
  args.overrides = {"wear.stages=1"};
  args.out = (dir.path() / "out").string();
  const study::Plan plan = study::make_plan(args);
  study::RunState state(plan);
  std::atomic<int> stop{0};
  study::RunOptions opt;
  opt.out = args.out;
  opt.jobs = 1;
  opt.stop_signal = &stop;
  opt.on_tick = [&state, &stop] {
    bool all_done = !state.designs.empty();
    for (const auto& d : state.designs) all_done = all_done && d->status == study::DesignStatus::Done;
    if (all_done) stop = SIGINT;
  };
  const study::RunOutcome o = study::run_designs(state, opt);
  EXPECT_EQ(stop.load(), SIGINT) << "the stop came";
  EXPECT_FALSE(o.interrupted);
  EXPECT_FALSE(o.figures_failed) << o.figure_error;
  EXPECT_GT(o.figures_written, 0u);
  EXPECT_NE(io::read_file((dir.path() / "out/manifest.json").string()).find("\"finished\": true"), std::string::npos);
}

TEST(RunProgress, StageLinesCarryTheLossSinceNew) {
  OneDesignRun run;
  study::DesignState& d = run.design();
  d.stages[0] = stage(0, 0.0, 4e-4, 3.0, 0.75);
  d.stages[1] = stage(1, 100.0, 3e-4, 2.0, 0.4);
  d.have_history = true;
  d.life_h = 1234.0;
  d.life_extrapolated = false;
  d.status = study::DesignStatus::Done;
  d.events = {"an event"};
  const std::vector<study::DesignLines> lines = study::design_lines(*run.state);
  ASSERT_EQ(lines.size(), 1u);
  ASSERT_EQ(lines[0].stages.size(), 2u);
  EXPECT_EQ(lines[0].name, "lab");
  EXPECT_EQ(lines[0].stages[0].area_loss_fraction, 0.0);
  EXPECT_DOUBLE_EQ(lines[0].stages[1].area_loss_fraction, 0.25);
  EXPECT_EQ(lines[0].life_h, 1234.0);
  EXPECT_FALSE(lines[0].life_extrapolated);
  EXPECT_EQ(lines[0].events, std::vector<std::string>{"an event"});
}

TEST(RunProgress, WithoutItsNewStageADesignHasNoLossFraction) {
  OneDesignRun run;
  run.design().stages[2] = stage(2, 200.0, 3e-4, 2.0, 0.4);
  EXPECT_TRUE(std::isnan(study::design_lines(*run.state)[0].stages[0].area_loss_fraction));
}

TEST(RunProgress, ARunningDesignHasNoTimeLeftUntilItsHoursAdvance) {
  OneDesignRun run;
  study::DesignState& d = run.design();
  d.status = study::DesignStatus::Running;
  d.started = d.progress_at = study::Clock::now();
  study::DesignProgress p = study::design_progress(*run.state, 0);
  EXPECT_TRUE(p.measuring);
  EXPECT_TRUE(std::isnan(p.left_s));
  EXPECT_EQ(p.stages, 4);
  // A report at 100 of 400 h one second in: three seconds left, less the time since.
  d.progress.stage = 1;
  d.progress.hours = 100.0;
  d.progress.simulated_s = 5.0;
  d.started = study::Clock::now() - std::chrono::seconds(1);
  d.progress_at = study::Clock::now();
  p = study::design_progress(*run.state, 0);
  EXPECT_FALSE(p.measuring);
  EXPECT_NEAR(p.left_s, 3.0, 0.2);  // the time between the report and the call: the test being descheduled
  EXPECT_GE(p.elapsed_s, 1.0);
}

TEST(RunProgress, AWornLinersHoursCountFromItsStart) {
  OneDesignRun run;
  run.plan.designs[0].scene.wear.start_hours = 2000.0;
  run.state = std::make_unique<study::RunState>(run.plan);
  run.state->designs.push_back(std::make_unique<study::DesignState>());
  study::DesignState& d = run.design();
  d.status = study::DesignStatus::Running;
  // A report at 2100 of 2000-2400 h one second in: three seconds left, as from new.
  d.progress.stage = 1;
  d.progress.hours = 2100.0;
  d.progress.simulated_s = 5.0;
  d.started = study::Clock::now() - std::chrono::seconds(1);
  d.progress_at = study::Clock::now();
  const study::DesignProgress p = study::design_progress(*run.state, 0);
  EXPECT_DOUBLE_EQ(p.start_hours, 2000.0);
  EXPECT_NEAR(p.left_s, 3.0, 0.2);
}

}  // namespace
}  // namespace millwear
