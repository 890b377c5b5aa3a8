// What the study commands' library calls hand back and write, on small made-up inputs.
// The commands end to end are tests/test_app_run.cpp, tests/test_calibrate_cli.cpp and
// tests/test_tradeoff.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "common/errors.hpp"
#include "engine_fixtures.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "study/animation.hpp"
#include "study/calibration_run.hpp"
#include "study/tradeoff_study.hpp"
#include "study/validation_run.hpp"

namespace millwear {
namespace {

namespace fs = std::filesystem;

std::string fresh_dir(const std::string& name) {
  const fs::path d = fs::path(::testing::TempDir()) / ("study_outputs_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

TEST(CalibrationTables, TheResidualUnitFollowsWhatWasFitted) {
  const std::string out = fresh_dir("calibration");
  validation::CalibrationResult res;
  validation::CalibrationRun run;
  run.run = 1;
  run.fit.rms = 2e-6;
  res.runs = {run};
  res.survey_hours = {50.0, 100.0};
  res.survey_c = {1e-10, 1.1e-10};
  validation::write_calibration_tables(out, res, true);
  const io::CsvData areas = io::read_csv(out + "/calibration.csv");
  EXPECT_DOUBLE_EQ(areas.number(0, "rms_mm2"), 2.0);
  EXPECT_EQ(io::read_csv(out + "/calibration_surveys.csv").row_count(), 2u);
  const io::CsvData result = io::read_csv(out + "/calibration_result.csv");
  EXPECT_EQ(result.text(0, result.column("fit_on")), "area_loss");
  validation::write_calibration_tables(out, res, false);
  EXPECT_NEAR(io::read_csv(out + "/calibration.csv").number(0, "rms_mm"), 0.002, 1e-15);
}

TEST(ValidationFiles, AProfileBlockIsATitleThenMillimetrePoints) {
  const Polyline line{{-0.01, 0.0}, {0.0025, 0.02}};
  EXPECT_EQ(validation::profile_block("50 h", line, true), "50 h,-\n-10,0\n2.5,20\n");
  EXPECT_EQ(validation::profile_block("100 h", line, false), "\n\n100 h,-\n-10,0\n2.5,20\n");
}

TEST(TradeoffFiles, LengthsAndAreasAreWrittenInMillimetres) {
  const std::string out = fresh_dir("tradeoff");
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
  r.out = fresh_dir("animation") + "/charge.png";
  try {
    study::make_animation(r);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "-o");
  }
  r.scene_file = "no-such-scene.toml";
  EXPECT_THROW(study::make_animation(r), InputError);
}

TEST(Animation, AHistoryWithoutTheDesignsStagesIsAnInputError) {
  study::AnimationRequest r;
  r.scene_file = testing::source_path("tests/data/lab-quick.toml");
  r.out = fresh_dir("animation_history") + "/charge.gif";
  r.history = fresh_dir("animation_empty_run");
  try {
    study::make_animation(r);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--history");
  }
}

}  // namespace
}  // namespace millwear
