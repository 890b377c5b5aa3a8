// Validation: survey files (profiles and areas only), measured against simulated profiles
// and areas, calibration of C, and the ore-hardness correction. Round trips on the lab mill
// (draft fidelity, one stage; two 50 h stages for the areas, tests/data/lab-quick.toml).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "cli_support.hpp"
#include "common/errors.hpp"
#include "engine_fixtures.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "plots/plots.hpp"
#include "study/area_fit.hpp"
#include "study/area_surveys.hpp"
#include "study/hardness.hpp"
#include "study/profile_fit.hpp"
#include "study/surveys.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;

namespace millwear {
namespace {

using validation::AreaSurvey;
using validation::AreaSurveys;
using validation::Survey;

// ---- helpers ----

using testing::CliResult;
constexpr auto run_cli = &testing::run_millwear;

// The lab mill turning one way, one 100 h stage, 1 mm depth steps: the cheapest history
// that wears the lifter visibly (a few seconds).
Scene quick_lab() {
  Scene s = testing::lab_mill();
  s.mill.direction = Direction::Forward;
  s.wear.stages = 1;
  s.wear.max_depth_step_m = 0.001;
  return s;
}
const WearHistory& quick_history() {
  static const WearHistory h = run_wear_history(quick_lab());
  return h;
}

// Synthetic surveys made by a simulation carry that simulation's statistical error as well
// as the fit's: the expanded bound on C_fit - C_true is 2 sqrt(sigma^2 + sigma_truth^2), with
// sigma_truth the truth history's own error (rule 2's batch means) up to the last survey.
double synthetic_bound(const validation::CalibrationResult& r, const Scene& truth_scene,
                       const WearHistory& truth, double c_true) {
  const double last_h = truth.stages.back().hours;
  const double sigma_truth = c_true * validation::history_relative_error(truth_scene, truth.stages, last_h);
  return 2.0 * std::hypot(r.sigma_m3_per_J, sigma_truth);
}

// Surveys "measured" from a history: the lifter region of every stage, with optional
// Gaussian noise (sd in m) on x and y.
std::vector<Survey> surveys_from(const WearHistory& h, double noise_m = 0.0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Survey> out;
  for (const auto& st : h.stages) {
    Survey s;
    s.hours = st.hours;
    const LinerUnit& u = st.units.front();
    for (const Vec2& p : u.surface)
      if (std::fabs(p.x) <= 1.25 * u.lifter_half_base_m)
        s.profile_m.push_back({p.x + noise_m * n(rng), p.y + noise_m * n(rng)});
    out.push_back(s);
  }
  return out;
}

// ---- survey files ----

TEST(ValidationSurveys, FileRoundTripKeepsBlocksAndPoints) {
  const std::string text =
      "# a comment line\n"
      "hours,x_mm,y_mm\n"
      "0,-20,0\n0,-10,20\n0,10,20\n0,20,0\n"
      "# surveys may be separated by comments\n"
      "750,20,0\n750,8,15\n750,-8,15\n750,-20,0\n";  // written +x to -x: reversed on reading
  const auto s = validation::parse_surveys(text, "s.csv");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].hours, 0.0);
  EXPECT_EQ(s[1].hours, 750.0);
  EXPECT_EQ(s[0].first_line, 3u);
  EXPECT_EQ(s[1].first_line, 8u);
  ASSERT_EQ(s[1].profile_m.size(), 4u);
  EXPECT_DOUBLE_EQ(s[1].profile_m.front().x, -0.020);  // mm -> m, ordered -x to +x
  const auto back = validation::parse_surveys(validation::format_surveys(s, "two\nlines"), "t.csv");
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    ASSERT_EQ(back[k].profile_m.size(), s[k].profile_m.size());
    for (std::size_t i = 0; i < s[k].profile_m.size(); ++i) {
      EXPECT_DOUBLE_EQ(back[k].profile_m[i].x, s[k].profile_m[i].x);
      EXPECT_DOUBLE_EQ(back[k].profile_m[i].y, s[k].profile_m[i].y);
    }
  }
}

// A bad survey file names the file and the line of the problem.
void expect_survey_error(const std::string& text, const std::string& where, const std::string& says) {
  try {
    validation::parse_surveys(text, "bad.csv");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "bad.csv");
    EXPECT_EQ(e.where, where) << e.what();
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

TEST(ValidationSurveys, MalformedFilesNameFileAndLine) {
  expect_survey_error("hours,x,y_mm\n0,1,2\n", "line 1", "x_mm");
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n0,abc,3\n", "line 3", "x_mm");
  expect_survey_error("# c\nhours,x_mm,y_mm\n0,1,2\n0,2,3,4\n", "line 4", "fields");
  expect_survey_error("hours,x_mm,y_mm\n-5,1,2\n-5,2,3\n", "line 2", "hours in [0, 1e6]");
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n0,2,2\n100,1,1\n100,2,1\n0,3,3\n", "line 6", "line 2");
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n100,1,1\n100,2,1\n", "line 2", "at least 2 points");
  // A point repeated is dropped (a scan's repeated reading): one point left.
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n0,1,2\n", "line 2", "at least 2 points");
  expect_survey_error("hours,x_mm,y_mm\n", "line 2", "survey rows");
  // Two points straight above each other span no width: their area error would be 0/0.
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n0,3,2\n100,0,0\n100,0,18\n", "line 4", "spanning a width");
}

// A laser scan is a survey as it is: the shipped scan writes a few points twice, each dropped
// instead of refused.
TEST(ValidationSurveys, AScanWithRepeatedReadingsIsASurveyAsItIs) {
  std::istringstream scan(testing::read_text(std::string(MILLWEAR_SOURCE_DIR) + "/profiles/lab-survey-2000h.csv"));
  std::string text = "hours,x_mm,y_mm\n";
  std::size_t rows = 0, repeats = 0;
  std::string last;
  for (std::string line; std::getline(scan, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("x_mm", 0) == 0) continue;
    repeats += line == last;
    last = line;
    text += "2000," + line + "\n";
    ++rows;
  }
  ASSERT_GT(repeats, 0u);
  const auto s = validation::parse_surveys(text, "scan.csv");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].profile_m.size(), rows - repeats);
}

// A survey's points follow the surface: shuffled points, or one lifter's points given twice in
// a block, cross the surface over itself and are refused; a loop as small as a gauge's noise
// on a steep face is taken as measured.
TEST(ValidationSurveys, PointsOutOfOrderAreRefusedAndANoiseLoopIsKept) {
  const std::string lifter = "-10,0\n-5,15\n5,15\n10,0\n";
  auto block = [](const std::string& hours, const std::string& points) {
    std::string out;
    for (std::size_t at = 0; at < points.size();) {
      const std::size_t end = points.find('\n', at);
      out += hours + "," + points.substr(at, end - at) + "\n";
      at = end + 1;
    }
    return out;
  };
  const std::string head = "hours,x_mm,y_mm\n" + block("0", lifter);
  // The shuffled block's first and last edges cross (lines 6 and 9 begin and end them); the
  // doubled one runs back over its own edges without crossing them, and is named by its block.
  expect_survey_error(head + block("100", "-10,0\n5,15\n-5,15\n10,0\n"), "line 9",
                      "crosses itself between lines 6 and 9");
  expect_survey_error(head + block("100", lifter + lifter), "line 6", "runs back over itself");
  // A point of each face swapped with the other's: the edges to and from them cross.
  expect_survey_error(head + block("100", "-10,0\n8,6\n-6,12\n-5,15\n0,15\n5,15\n6,12\n-8,6\n10,0\n"),
                      "line 13", "crosses itself between lines 7 and 13");
  // The face steps back across itself by a few hundredths of a square millimetre: kept as
  // measured, in a survey of the whole lifter and in one of that face alone.
  const std::string face = "-10,0\n-7,6\n-6.8,6.6\n-7.1,6.4\n-6.7,6.2\n-5,10\n";
  const auto s = validation::parse_surveys(head + block("100", face + "5,15\n10,0\n"), "noisy.csv");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].profile_m.size(), 8u);
  EXPECT_FALSE(is_simple_open(s[1].profile_m));
  const auto one_face = validation::parse_surveys(head + block("100", face), "face.csv");
  ASSERT_EQ(one_face.size(), 2u);
  EXPECT_EQ(one_face[1].profile_m.size(), 6u);
}

// A laser scan as a survey: 150,000 points a block along the lab lifter (20 mm high, 33 mm
// base). Its edges' crossings are found in a tree of bounding boxes, so two such blocks read in
// well under a second of CPU; testing every pair of edges takes over a minute (1.1e10 pairs a
// block). The bound, 10 s, leaves room for a slow, shared machine. Two points swapped between
// the faces in such a scan are still found.
TEST(ValidationSurveys, ADenseScanIsReadInTimeAndItsCrossingsAreFound) {
  const std::vector<Vec2> corners = {{-16.5, 0.0}, {-5.0, 20.0}, {5.0, 20.0}, {16.5, 0.0}};  // mm
  const std::size_t n = 150000;
  auto points = [&](double scale) {
    std::vector<Vec2> out;
    for (std::size_t k = 0; k < n; ++k) {
      const double t = 3.0 * static_cast<double>(k) / static_cast<double>(n - 1);
      const std::size_t edge = std::min<std::size_t>(2, static_cast<std::size_t>(t));
      const Vec2 a = corners[edge], b = corners[edge + 1];
      const double u = t - static_cast<double>(edge);
      out.push_back({a.x + u * (b.x - a.x), scale * (a.y + u * (b.y - a.y))});
    }
    return out;
  };
  auto block = [](const std::string& hours, const std::vector<Vec2>& p) {
    std::string out;
    char row[96];
    for (const Vec2& v : p) {
      std::snprintf(row, sizeof row, "%s,%.9g,%.9g\n", hours.c_str(), v.x, v.y);
      out += row;
    }
    return out;
  };
  const std::string head = "hours,x_mm,y_mm\n" + block("0", points(1.0));
  const std::clock_t start = std::clock();
  const auto s = validation::parse_surveys(head + block("100", points(0.8)), "scan.csv");
  const double cpu_s = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].profile_m.size(), n);
  EXPECT_LT(cpu_s, 10.0);
  // A point a third of the way up the trailing face swapped with its mirror on the leading one:
  // the worn block (from line n + 2) crosses itself around the lifter's top.
  std::vector<Vec2> swapped = points(0.8);
  std::swap(swapped[n / 6], swapped[n - 1 - n / 6]);
  try {
    validation::parse_surveys(head + block("100", swapped), "scan.csv");
    ADD_FAILURE() << "a dense survey with two points swapped between its faces was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("crosses itself"), std::string::npos) << e.what();
    const std::size_t first_line = n + 2;  // header, then the block at 0 h
    const std::size_t line = std::stoul(e.where.substr(5));
    EXPECT_GE(line, first_line + n / 6 - 1) << e.what();
    EXPECT_LE(line, first_line + n - n / 6) << e.what();
  }
}

// A survey beside the lifter (over the shell alone) has no lifter area to be a share of.
TEST(ValidationSurveys, ASurveyBesideTheLifterIsRefused) {
  const Scene scene = testing::lab_mill();
  const LinerUnit unit = new_liner_unit(scene);
  const auto beside = validation::parse_surveys("hours,x_mm,y_mm\n0,-19.22,-0.15\n0,-18.15,-0.15\n", "beside.csv");
  try {
    validation::check_surveys_over_lifter(beside, unit, scene.radius_m(), "beside.csv");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "line 2");
    EXPECT_NE(std::string(e.what()).find("no metal above the shell line"), std::string::npos) << e.what();
  }
  const auto over = validation::parse_surveys("hours,x_mm,y_mm\n0,-19.22,-0.15\n0,-10,5\n", "over.csv");
  EXPECT_NO_THROW(validation::check_surveys_over_lifter(over, unit, scene.radius_m(), "over.csv"));
}

TEST(ValidationCli, MalformedMeasurementFilesExitTwoNamingFileAndLine) {
  const TempDir d("millwear-test-validation-cli");
  const std::string bad = (d / "bad-surveys.csv").string();
  std::ofstream(bad) << "hours,x_mm,y_mm\n0,-10,0\n0,oops,5\n";
  const std::string scene = testing::source_path("scenarios/lab-mill.toml");
  for (const std::string cmd : {"validate", "calibrate"}) {
    const CliResult r = run_cli(cmd + " \"" + scene + "\" --measured \"" + bad + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(bad + ": line 3"), std::string::npos) << r.output;
  }
  const std::string hard = (d / "bad-hardness.csv").string();
  std::ofstream(hard) << "period,days,area_loss_mm2,hardness\n1,54,900,13\n2,-3,900,14\n3,20,400,15\n";
  const CliResult h = run_cli("hardness \"" + hard + "\" -o \"" + (d / "h").string() + "\"");
  EXPECT_EQ(h.exit_code, 2) << h.output;
  EXPECT_NE(h.output.find(hard + ": line 3"), std::string::npos) << h.output;
  EXPECT_FALSE(fs::exists(d / "out"));  // nothing written before the input is valid
}

TEST(ValidationCli, HardnessCommandWritesTheFitAndTheFigure) {
  const TempDir d("millwear-test-validation-hardness");
  const CliResult r = run_cli("hardness \"" + testing::source_path("validation/hardness-synthetic.csv") + "\" -o \"" +
                              d.path().string() + "\" --reference-hardness 14");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData fit = io::read_csv((d / "hardness_fit.csv").string());
  ASSERT_EQ(fit.row_count(), 1u);
  EXPECT_NEAR(fit.number(0, "b"), 2.0, 3.0 * fit.number(0, "b_se"));
  EXPECT_EQ(io::read_csv((d / "hardness_periods.csv").string()).row_count(), 8u);
  if (plots::gnuplot_available()) {
    EXPECT_TRUE(fs::exists(d / "hardness.png"));
    EXPECT_TRUE(fs::exists(d / "hardness.svg"));
  }
}

// ---- profiles ----

TEST(ValidationProfiles, InterpolationIsExactAtStagesAndProportionalBetween) {
  // Two flat liners 1 mm apart: a quarter of the way is 0.25 mm down, everywhere.
  Polyline a, b;
  for (int i = 0; i <= 10; ++i) {
    a.push_back({-0.05 + 0.01 * i, 0.0});
    b.push_back({-0.05 + 0.013 * i * (0.1 / 0.13), -0.001});
  }
  validation::ProfileHistory h{{0.0, 100.0}, {a, b}};
  for (const Vec2& p : h.profile_at(25.0)) EXPECT_NEAR(p.y, -0.00025, 1e-15);
  EXPECT_EQ(h.profile_at(100.0), b);  // exact stage geometry, not an interpolation
  EXPECT_EQ(h.profile_at(0.0), a);
  // Signed distance: above the surface (charge side) positive, in the metal negative.
  EXPECT_NEAR(validation::signed_distance({0.0, 0.002}, a), 0.002, 1e-15);
  EXPECT_NEAR(validation::signed_distance({0.0, -0.003}, a), -0.003, 1e-15);
}

TEST(ValidationProfiles, CommonStageHoursPutsStageBoundariesOnTheSurveys) {
  auto at = [](std::vector<double> hours) {
    std::vector<Survey> s;
    for (double h : hours) s.push_back({h, {{0, 0}, {1, 0}}, 0});
    return validation::common_stage_hours(s);
  };
  EXPECT_DOUBLE_EQ(at({0, 750, 1500, 2250}), 750.0);
  EXPECT_DOUBLE_EQ(at({0, 500, 1200}), 100.0);
  EXPECT_DOUBLE_EQ(at({1000, 1001}), 0.0);  // 1 h steps: too many stages, interpolate
  EXPECT_DOUBLE_EQ(at({0}), 0.0);
  // Surveys minutes apart would make stages shorter than a scene takes (wear.stage_hours in
  // [1, 1e6]), whose first update's re-smoothing, not wear, sets their loss: they fall between
  // the scene's own stages instead, and so does the step a fresh history of them runs.
  EXPECT_DOUBLE_EQ(at({0, 0.001, 0.002}), 0.0);
  EXPECT_DOUBLE_EQ(at({0, 0.5, 1.0}), 0.0);
  EXPECT_DOUBLE_EQ(at({0, 1.0, 2.0}), 1.0);
  const Scene s = quick_lab();
  const Scene fresh = validation::scene_for_survey_hours(s, {0.0, 0.001, 0.002}, 0.0);
  EXPECT_DOUBLE_EQ(fresh.wear.stage_hours, s.wear.stage_hours);
  EXPECT_EQ(fresh.wear.stages, 1);
}

TEST(ValidationProfiles, ProfileMeasuredFromASimulatedRunValidatesWithZeroError) {
  const WearHistory& h = quick_history();
  ASSERT_EQ(h.stages.size(), 2u);
  // Through the file format (mm, 10 significant digits), as a user's survey file would be.
  const auto surveys = validation::parse_surveys(validation::format_surveys(surveys_from(h)), "sim.csv");
  const auto history = validation::profile_history(h.stages);
  const Scene s = quick_lab();
  const auto& st0 = h.stages.front();
  for (const Survey& v : surveys) {
    const auto c = validation::compare_profile(v, history.profile_at(v.hours), s.radius_m(), st0.lifter.height_m,
                                               st0.units.front().surface);
    // 10 significant digits of ~10 mm coordinates: 1e-9 mm rounding, far below 1e-6 mm.
    EXPECT_LT(c.max_distance_m, 1e-9) << v.hours << " h";
    EXPECT_LT(c.mean_pct_height, 1e-5);
    EXPECT_LT(std::fabs(c.area_error_m2), 1e-12) << v.hours << " h";
    EXPECT_GT(c.measured_area_m2, 0.0);
  }
  // And the worn survey is not trivially equal to the new profile.
  const auto c_new = validation::compare_profile(surveys.back(), history.profile_at(0.0), s.radius_m(),
                                                 st0.lifter.height_m, st0.units.front().surface);
  EXPECT_GT(c_new.max_distance_m, 1e-3);
  EXPECT_GT(c_new.area_error_m2, 0.0);  // the new lifter has more metal than the worn survey
}

TEST(ValidationCalibration, RecoversAKnownWearRateWithinItsUncertainty) {
  const WearHistory& truth = quick_history();
  const double c_true = quick_lab().wear.wear_rate_m3_per_J;
  // Surveys from the true history with 0.1 mm of measurement noise (about the scatter of a
  // laser survey of a 20 mm lab lifter).
  const auto surveys = surveys_from(truth, 1e-4, 7);
  Scene guess = quick_lab();
  guess.wear.wear_rate_m3_per_J = 0.8 * c_true;
  const auto r = validation::calibrate_wear_rate(guess, surveys);
  EXPECT_TRUE(r.converged) << r.runs.size() << " runs";
  // Stated uncertainty: the calibration's U (k = 2) together with the truth's own error.
  const double bound = synthetic_bound(r, quick_lab(), truth, c_true);
  EXPECT_NEAR(r.c_m3_per_J, c_true, bound)
      << "C = " << r.c_m3_per_J << " +- " << r.expanded_m3_per_J << " (true " << c_true << ", bound " << bound << ")";
  // The uncertainty is informative (not a blanket 100%) and not zero.
  EXPECT_GT(r.expanded_m3_per_J, 0.0);
  EXPECT_LT(r.expanded_m3_per_J, 0.2 * c_true);
  EXPECT_LE(r.runs.size(), 4u);
  std::printf("[ calibration ] C = %.4g +- %.2g (true %.4g, bound %.2g) after %zu runs\n", r.c_m3_per_J,
              r.expanded_m3_per_J, c_true, bound, r.runs.size());
}

// ---- area surveys ----

TEST(ValidationAreaSurveys, FileRoundTripKeepsRowsAndRepeatedHours) {
  const std::string text =
      "# liner survey, two lifters per inspection\n"
      "hours, area_mm2 ,lifter\n"  // spaces around names and an extra column are fine
      "0,431.5,A\n"
      "\n"
      "500,400.25,A\n500,398.0,B\n"
      "# a comment between rows\n"
      "250,415,A\n";  // any order
  const AreaSurveys a = validation::parse_area_surveys(text, "a.csv");
  EXPECT_FALSE(a.losses);
  ASSERT_EQ(a.surveys.size(), 4u);
  EXPECT_EQ(a.surveys[2].hours, 500.0);
  EXPECT_DOUBLE_EQ(a.surveys[2].value_m2, 398.0e-6);  // mm^2 -> m^2
  EXPECT_EQ(a.surveys[0].line, 3u);
  EXPECT_EQ(a.surveys[3].line, 8u);
  const AreaSurveys back = validation::parse_area_surveys(validation::format_area_surveys(a, "x\ny"), "b.csv");
  ASSERT_EQ(back.surveys.size(), a.surveys.size());
  for (std::size_t i = 0; i < a.surveys.size(); ++i) {
    EXPECT_EQ(back.surveys[i].hours, a.surveys[i].hours);
    EXPECT_DOUBLE_EQ(back.surveys[i].value_m2, a.surveys[i].value_m2);
  }
  const AreaSurveys l = validation::parse_area_surveys("hours,area_loss_mm2\n100,12.5\n", "l.csv");
  EXPECT_TRUE(l.losses);
  EXPECT_TRUE(validation::parse_area_surveys(validation::format_area_surveys(l), "l2.csv").losses);
}

TEST(ValidationAreaSurveys, TheHeaderTellsProfilesFromAreas) {
  const auto p = validation::parse_measurements("hours,x_mm,y_mm\n0,-1,0\n0,1,0\n", "p.csv");
  EXPECT_FALSE(p.areas_only);
  EXPECT_EQ(p.count(), 1u);
  const auto a = validation::parse_measurements("# c\nhours,area_mm2\n0,400\n100,380\n", "a.csv");
  EXPECT_TRUE(a.areas_only);
  EXPECT_EQ(a.count(), 2u);
  EXPECT_EQ(a.hours(), (std::vector<double>{0.0, 100.0}));
  EXPECT_EQ(a.lines(), (std::vector<std::size_t>{3, 4}));
  // A header of both formats is refused as such (it was read as profiles, and refused for a
  // survey of too few points).
  try {
    validation::parse_measurements("hours,area_mm2,x_mm,y_mm\n0,419.1,0,0\n50,390,1,1\n", "both.csv");
    ADD_FAILURE() << "a header of both formats was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "line 1") << e.what();
    EXPECT_NE(e.expected.find("not both"), std::string::npos) << e.what();
  }
}

// Survey files as spreadsheets save them: "CSV UTF-8" (a byte-order mark, here before a
// comment line), CRLF line ends, and European ';' files with decimal commas.
TEST(ValidationAreaSurveys, SpreadsheetSavedFilesReadLikePlainOnes) {
  const auto plain = validation::parse_measurements("hours,area_mm2\n0,431.5\n100,400.25\n", "plain.csv");
  for (const std::string& text :
       {std::string("\xEF\xBB\xBFhours,area_mm2\n0,431.5\n100,400.25\n"),
        std::string("\xEF\xBB\xBF# surveyed by hand\r\nhours,area_mm2\r\n0,431.5\r\n100,400.25\r\n"),
        std::string("\xEF\xBB\xBFhours;area_mm2\r\n0;431,5\r\n100;400,25\r\n")}) {
    const auto m = validation::parse_measurements(text, "sheet.csv");
    EXPECT_TRUE(m.areas_only);
    ASSERT_EQ(m.areas.surveys.size(), plain.areas.surveys.size());
    for (std::size_t i = 0; i < m.areas.surveys.size(); ++i) {
      EXPECT_EQ(m.areas.surveys[i].hours, plain.areas.surveys[i].hours);
      EXPECT_EQ(m.areas.surveys[i].value_m2, plain.areas.surveys[i].value_m2);
    }
  }
  const auto profiles = validation::parse_measurements("\xEF\xBB\xBFhours;x_mm;y_mm\r\n0;-1,5;0\r\n0;1,5;0\r\n", "p.csv");
  EXPECT_FALSE(profiles.areas_only);
  EXPECT_EQ(profiles.count(), 1u);
  try {
    validation::parse_measurements("\xEF\xBB\xBFhours;area_mm2\r\n0;431,5\r\n100;abc\r\n", "sheet.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "sheet.csv");
    EXPECT_EQ(e.where, "line 3");
  }
}

TEST(ValidationAreaSurveys, LossIsFromTheMeasuredNewAreaElseTheScenes) {
  // With 0 h rows their mean is the reference; without, the scene's new lifter area.
  const auto with0 = validation::measured_areas(
      validation::parse_area_surveys("hours,area_mm2\n0,400\n0,404\n100,380\n", "a.csv"), 410e-6, 0.0);
  EXPECT_TRUE(with0.reference_measured);
  EXPECT_NEAR(with0.reference_m2, 402e-6, 1e-15);
  EXPECT_NEAR(with0.loss_m2[2], 22e-6, 1e-15);
  const auto without0 =
      validation::measured_areas(validation::parse_area_surveys("hours,area_mm2\n100,380\n", "a.csv"), 410e-6, 0.0);
  EXPECT_FALSE(without0.reference_measured);
  EXPECT_NEAR(without0.loss_m2[0], 30e-6, 1e-15);
  const auto loss =
      validation::measured_areas(validation::parse_area_surveys("hours,area_loss_mm2\n100,25\n", "l.csv"), 410e-6, 0.0);
  EXPECT_NEAR(loss.loss_m2[0], 25e-6, 1e-15);
  EXPECT_NEAR(loss.area_m2[0], 385e-6, 1e-15);
  // A history that starts worn at 2000 h: its rows at 2000 h are the reference, a 0 h row is not.
  const auto worn = validation::measured_areas(
      validation::parse_area_surveys("hours,area_mm2\n2000,300\n2100,280\n", "w.csv"), 310e-6, 2000.0);
  EXPECT_TRUE(worn.reference_measured);
  EXPECT_NEAR(worn.reference_m2, 300e-6, 1e-15);
  EXPECT_NEAR(worn.loss_m2[1], 20e-6, 1e-15);
}

TEST(ValidationAreaSurveys, ShippedExampleIsALabelledSyntheticAreaSurvey) {
  // validation/lab-mill-areas.csv: the lab-mill run's areas at 0 h (one row) and 100 and 200 h
  // (three lifters each), 2 mm^2 noise (its header says so; make_examples.py makes it).
  const std::string path = testing::source_path("validation/lab-mill-areas.csv");
  EXPECT_EQ(io::read_file(path).rfind("# SYNTHETIC, NOT MEASURED", 0), 0u);
  const auto m = validation::read_measurements(path);
  ASSERT_TRUE(m.areas_only);
  EXPECT_EQ(m.hours(), (std::vector<double>{0, 100, 100, 100, 200, 200, 200}));
  // The new lab lifter (lab-2x30) is 419.1 mm^2: the 0 h row is within its 2 mm^2 noise (3 sd).
  EXPECT_NEAR(m.areas.surveys[0].value_m2, 419.1e-6, 6e-6);
  const auto loss = validation::measured_areas(m.areas, 419.1e-6, 0.0);
  EXPECT_TRUE(loss.reference_measured);
  for (std::size_t i = 1; i < 7; ++i) EXPECT_GT(loss.loss_m2[i], 0.0);
}

// A bad area file names the file and the line of the problem.
void expect_measurement_error(const std::string& text, const std::string& where, const std::string& says) {
  try {
    validation::parse_measurements(text, "bad.csv");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "bad.csv");
    EXPECT_EQ(e.where, where) << e.what();
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

TEST(ValidationAreaSurveys, MalformedFilesNameFileAndLine) {
  expect_measurement_error("hours,area\n0,400\n", "line 1", "hours,area_mm2");       // neither format
  expect_measurement_error("# c\n# c\nhours,size\n0,400\n", "line 3", "x_mm,y_mm");  // the header's own line
  expect_measurement_error("time,area_mm2\n0,400\n", "line 1", "column named hours");
  expect_measurement_error("hours,area_mm2,area_loss_mm2\n0,400,0\n", "line 1", "not both");
  expect_measurement_error("# c\nhours,area_mm2\n", "line 3", "rows hours,area_mm2");
  expect_measurement_error("hours,area_mm2\n0,400\n100,abc\n", "line 3", "column area_mm2");
  expect_measurement_error("hours,area_mm2\n0,400\n100,-5\n", "line 3", "area in (0, 1e10]");
  expect_measurement_error("hours,area_mm2\n0,400\n100,0\n", "line 3", "area in (0, 1e10]");
  expect_measurement_error("hours,area_mm2\n0,400\n-1,380\n", "line 3", "hours in [0, 1e6]");
  expect_measurement_error("hours,area_mm2\n0,400\nnan,380\n", "line 3", "hours in [0, 1e6]");
  expect_measurement_error("hours,area_loss_mm2\n100,inf\n", "line 2", "area loss within +-1e10");
  expect_measurement_error("hours,area_mm2\n0,400\n100,380,1\n", "line 3", "fields");
}

TEST(ValidationCli, MalformedAreaFilesExitTwoNamingFileAndLine) {
  const TempDir d("millwear-test-validation-cli-areas");
  const std::string bad = (d / "bad-areas.csv").string();
  std::ofstream(bad) << "# areas\nhours,area_mm2\n0,419\n100,-3\n";
  const std::string scene = testing::source_path("scenarios/lab-mill.toml");
  for (const std::string cmd : {"validate", "calibrate"}) {
    const CliResult r = run_cli(cmd + " \"" + scene + "\" --measured \"" + bad + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(bad + ": line 4: a lifter area in (0, 1e10]"), std::string::npos) << r.output;
  }
  // Areas in m^2 (the lab lifter's 431 mm^2 written as 0.000431) and profile surveys in
  // metres: refused before any work, naming the line.
  const std::string square_metres = (d / "m2.csv").string();
  std::ofstream(square_metres) << "hours,area_mm2\n0,0.000431\n100,0.000400\n";
  std::string metres_text = "hours,x_mm,y_mm\n";
  for (const char* h : {"0", "100"}) metres_text += std::string(h) + ",-0.03,0\n" + h + ",-0.01,0.02\n" + h + ",0.01,0.02\n" + h + ",0.03,0\n";
  const std::string metres = (d / "m.csv").string();
  std::ofstream(metres) << metres_text;
  for (const std::string cmd : {"validate", "calibrate"}) {
    CliResult r = run_cli(cmd + " \"" + scene + "\" --measured \"" + square_metres + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(square_metres + ": line 2: a lifter area in mm^2, at least a thousandth of the scene's lifter"),
              std::string::npos) << r.output;
    r = run_cli(cmd + " \"" + scene + "\" --measured \"" + metres + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(metres + ": line 2: millimetres, spanning at least 1 mm across"), std::string::npos)
        << r.output;
  }
  // A loss beyond the whole lifter, or losses that do not grow with time: validate refuses
  // them as calibrate does, before any work.
  const std::string too_much = (d / "too-much.csv").string();
  std::ofstream(too_much) << "hours,area_loss_mm2\n100,5000\n";
  // A small negative loss is within a gauge's noise of the start, but nothing was lost; a
  // larger one is metal gained, said as such with the loss as given.
  const std::string gained = (d / "gained.csv").string();
  std::ofstream(gained) << "hours,area_loss_mm2\n100,-2\n";
  const std::string gained_more = (d / "gained-more.csv").string();
  std::ofstream(gained_more) << "hours,area_loss_mm2\n100,-20\n";
  for (const std::string cmd : {"validate", "calibrate"}) {
    CliResult r = run_cli(cmd + " \"" + scene + "\" --measured \"" + too_much + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(too_much + ": line 2: an area loss smaller than the lifter's area"), std::string::npos)
        << cmd << ": " << r.output;
    r = run_cli(cmd + " \"" + scene + "\" --measured \"" + gained + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find("these area losses are not positive"), std::string::npos) << cmd << ": " << r.output;
    r = run_cli(cmd + " \"" + scene + "\" --measured \"" + gained_more + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(gained_more + ": line 2: a lifter area no larger than the lifter's at the start"),
              std::string::npos)
        << cmd << ": " << r.output;
    EXPECT_NE(r.output.find("the survey at 100 h gives a loss of -20 mm^2, 20 mm^2 more"), std::string::npos)
        << cmd << ": " << r.output;
  }
  // Only the new lifter: nothing to calibrate on.
  const std::string unworn = (d / "unworn.csv").string();
  std::ofstream(unworn) << "hours,area_mm2\n0,419\n";
  const CliResult u = run_cli("calibrate \"" + scene + "\" --measured \"" + unworn + "\" -o \"" + (d / "out").string() + "\"");
  EXPECT_EQ(u.exit_code, 2) << u.output;
  EXPECT_NE(u.output.find(unworn + ": hours: at least one survey after the history's start (0 h"), std::string::npos) << u.output;
  EXPECT_FALSE(fs::exists(d / "out"));  // nothing written before the input is valid
}

// The message of the InputError `f` throws ("accepted" if none), with its line.
std::string refusal(const std::function<void()>& f, std::string* where = nullptr) {
  try {
    f();
  } catch (const InputError& e) {
    if (where) *where = e.where;
    return e.what();
  }
  return "accepted";
}

// An area_loss_mm2 file counts the loss from the history's start: rows there average to 0
// within a gauge's noise (1% of the lifter's 419 mm^2, 4.19 mm^2); rows that do not count from
// elsewhere, and are refused naming the first one's line (the start at 0 h, or a worn start's
// start_hours). Several lifters each reported against their mean at the start are taken.
TEST(ValidationAreaSurveys, LossesAtTheStartThatDoNotAverageZeroAreRefused) {
  const auto check = [](const std::string& text, double start_hours) {
    validation::check_areas_shrink(validation::parse_area_surveys(text, "l.csv"), 419e-6, start_hours, "l.csv");
  };
  std::string where;
  std::string m = refusal([&] { check("hours,area_loss_mm2\n0,5\n100,30\n", 0.0); }, &where);
  EXPECT_EQ(where, "line 2");
  EXPECT_NE(m.find("l.csv: line 2: area losses averaging 0 at the history's start (0 h)"), std::string::npos) << m;
  EXPECT_NE(m.find("this row gives 5 mm^2"), std::string::npos) << m;
  m = refusal([&] { check("hours,area_loss_mm2\n2100,30\n2000,-6\n2000,-4\n", 2000.0); }, &where);
  EXPECT_EQ(where, "line 3");
  EXPECT_NE(m.find("(2000 h)"), std::string::npos) << m;
  EXPECT_NE(m.find("the 2 rows there, from this one, average -5 mm^2"), std::string::npos) << m;
  EXPECT_EQ(refusal([&] { check("hours,area_loss_mm2\n0,0\n100,30\n", 0.0); }), "accepted");
  // Two lifters reported against their mean at the start, and a gauge's noise on one row.
  EXPECT_EQ(refusal([&] { check("hours,area_loss_mm2\n0,-1.5\n0,1.5\n100,30\n", 0.0); }), "accepted");
  EXPECT_EQ(refusal([&] { check("hours,area_loss_mm2\n2100,30\n2000,-0.5\n", 2000.0); }), "accepted");
  // Areas at the start are the reference of the loss, whatever their value.
  EXPECT_EQ(refusal([&] { check("hours,area_mm2\n0,430\n0,440\n100,400\n", 0.0); }), "accepted");
  // The command refuses it before any work.
  const TempDir d("millwear-test-validation-loss-at-start");
  const std::string file = (d / "losses.csv").string();
  std::ofstream(file) << "hours,area_loss_mm2\n0,5\n100,30\n";
  const std::string scene = testing::source_path("scenarios/lab-mill.toml");
  for (const std::string cmd : {"validate", "calibrate"}) {
    const CliResult r = run_cli(cmd + " \"" + scene + "\" --measured \"" + file + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(file + ": line 2: area losses averaging 0 at the history's start"), std::string::npos)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(d / "out"));
}

// A worn lifter's area above the one it wore from by more than a gauge's noise (1% of that
// area) is refused at its line, even where the other rows' losses make the sum positive (the
// check the rows' sum alone let through); 1% or less is noise and taken.
TEST(ValidationAreaSurveys, AWornAreaAboveTheStartsBeyondNoiseIsRefused) {
  const auto check = [](const std::string& text) {
    validation::check_areas_shrink(validation::parse_area_surveys(text, "a.csv"), 419e-6, 0.0, "a.csv");
  };
  std::string where;
  // Against the file's 0 h area (431): 500 at 100 h is 69 mm^2 more; 300 at 200 h makes the
  // hours x loss sum positive.
  std::string m = refusal([&] { check("hours,area_mm2\n0,431\n100,500\n200,300\n"); }, &where);
  EXPECT_EQ(where, "line 3");
  EXPECT_NE(m.find("has 500 mm^2, 69 mm^2 more"), std::string::npos) << m;
  EXPECT_NE(m.find("(431 mm^2, the survey at the start)"), std::string::npos) << m;
  // Without a 0 h row, against the scene's lifter (419 mm^2), a casting bigger than drawn is
  // allowed too (1% + 5%, 25.14 mm^2): 450 is 31 mm^2 over, refused, naming the exact reference.
  m = refusal([&] { check("hours,area_mm2\n100,450\n200,300\n"); }, &where);
  EXPECT_EQ(where, "line 2");
  EXPECT_NE(m.find("the scene's lifter at the start"), std::string::npos) << m;
  EXPECT_NE(m.find("a casting bigger than drawn (1% + 5% of it, 25.14 mm^2; a row at the start, hours 0, gives the "
                   "lifter as cast, the exact reference)"),
            std::string::npos)
      << m;
  // A casting 3% over drawn, surveyed after 1% wear (419 x 1.03 x 0.99 = 427.3 mm^2): taken.
  EXPECT_EQ(refusal([&] { check("hours,area_mm2\n100,427.3\n200,300\n"); }), "accepted");
  // A negative loss is a gain too.
  m = refusal([&] { check("hours,area_loss_mm2\n100,-50\n200,200\n"); }, &where);
  EXPECT_EQ(where, "line 2");
  EXPECT_NE(m.find("50 mm^2 more"), std::string::npos) << m;
  // Within 1% of the reference: noise, taken (433 is 2 mm^2 over 431, 4.31 allowed).
  EXPECT_EQ(refusal([&] { check("hours,area_mm2\n0,431\n100,433\n200,300\n"); }), "accepted");
  EXPECT_EQ(refusal([&] { check("hours,area_loss_mm2\n100,-4\n200,200\n"); }), "accepted");
}

// Profile surveys lose metal with the hours, as area surveys must: a survey after the start
// with more metal than the survey at the start over the span both cover, or than the scene's
// lifter when the file has no survey at the start, beyond 1% of the new lifter's area, is
// refused naming its line and the amount; less is a gauge's noise. Two later surveys are not
// compared with each other. Surveys: the lab lifter (20 mm high, base +-16.55 mm) with its
// heights scaled by f, so its metal is about f x 419 mm^2.
// In a pattern of lifters of other shapes, a survey without one at the start may be of any of
// them: not judged by the first kind's drawing. The lab hi-lo liner with its low lifter first:
// a survey of the high lifter has far more metal than the low one, and is taken.
TEST(ValidationSurveys, ASurveyOfAPatternsOtherLifterIsNotJudgedByTheFirstKind) {
  Scene scene = load_scene(testing::source_path("scenarios/lab-hi-lo.toml"));
  EXPECT_TRUE(testing::lab_mill().mill.one_lifter_shape());
  ASSERT_FALSE(scene.mill.one_lifter_shape());
  std::swap(scene.mill.pattern[0], scene.mill.pattern[1]);
  scene.mill.lifter = scene.mill.pattern[0];
  const LinerUnit low = new_liner_unit(scene);
  const double hb = 5.0 + 20.0 * std::tan(30.0 * kPi / 180.0);
  char buf[256];
  std::snprintf(buf, sizeof buf, "hours,x_mm,y_mm\n100,%.4f,0\n100,-5,19\n100,5,19\n100,%.4f,0\n", -hb, hb);
  const auto surveys = validation::parse_surveys(buf, "s.csv");
  EXPECT_NE(refusal([&] { validation::check_surveys_lose_metal(surveys, low, scene.radius_m(), 0.0, "s.csv"); }),
            "accepted")
      << "judged by the low lifter, the high one's survey gains metal";
  EXPECT_EQ(refusal([&] {
              validation::check_surveys_lose_metal(surveys, low, scene.radius_m(), 0.0, "s.csv",
                                                   scene.mill.one_lifter_shape());
            }),
            "accepted");
}

TEST(ValidationSurveys, ASurveyThatGainsMetalIsRefused) {
  const Scene scene = testing::lab_mill();
  const LinerUnit unit = new_liner_unit(scene);
  const double hb = 5.0 + 20.0 * std::tan(30.0 * kPi / 180.0);
  const auto survey = [hb](double hours, double f) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%g,%.4f,0\n%g,-5,%.4f\n%g,5,%.4f\n%g,%.4f,0\n", hours, -hb, hours, 20.0 * f,
                  hours, 20.0 * f, hours, hb);
    return std::string(buf);
  };
  const auto check = [&](const std::string& rows) {
    const auto surveys = validation::parse_surveys("hours,x_mm,y_mm\n" + rows, "s.csv");
    validation::check_surveys_lose_metal(surveys, unit, scene.radius_m(), 0.0, "s.csv");
  };
  std::string where;
  // Worn to 0.9 at 100 h, then 1.05 at 200 h: 5% of the lifter (about 21 mm^2) over the start.
  std::string m = refusal([&] { check(survey(0, 1.0) + survey(100, 0.9) + survey(200, 1.05)); }, &where);
  EXPECT_EQ(where, "line 10");
  EXPECT_NE(m.find("the survey at 200 h has"), std::string::npos) << m;
  EXPECT_NE(m.find("more metal than the survey at the start, 0 h (line 2)"), std::string::npos) << m;
  // 0.85 at 100 h, then 0.865 at 150 h (another lifter, or the gauge's noise): 1.5% above the
  // survey before it, still 13.5% below the start, taken. Only the start is the reference.
  EXPECT_EQ(refusal([&] { check(survey(0, 1.0) + survey(100, 0.85) + survey(150, 0.865)); }), "accepted");
  // No survey at the start: a survey above the scene's lifter by more than a gauge's noise and
  // a casting bigger than drawn (1% + 5%).
  m = refusal([&] { check(survey(100, 1.08)); }, &where);
  EXPECT_EQ(where, "line 2");
  EXPECT_NE(m.find("more metal than the scene's lifter at the history's start (0 h); a survey at the start, 0 h, "
                   "gives the lifter as cast"),
            std::string::npos)
      << m;
  // A casting 3% over drawn, surveyed after 1% wear: taken.
  EXPECT_EQ(refusal([&] { check(survey(100, 1.03 * 0.99)); }), "accepted");
  // A new lifter surveyed 3% above the scene's is the start: later surveys are judged by it.
  EXPECT_EQ(refusal([&] { check(survey(0, 1.03) + survey(100, 1.01) + survey(200, 0.9)); }), "accepted");
  // Half a per cent up between two surveys: a gauge's noise, taken.
  EXPECT_EQ(refusal([&] { check(survey(0, 1.0) + survey(100, 0.9) + survey(200, 0.905)); }), "accepted");
  // The commands refuse it before any work.
  const TempDir d("millwear-test-validation-gain");
  const std::string file = (d / "gain.csv").string();
  std::ofstream(file) << "hours,x_mm,y_mm\n" + survey(0, 1.0) + survey(100, 0.9) + survey(200, 1.05);
  const std::string lab = testing::source_path("scenarios/lab-mill.toml");
  for (const std::string cmd : {"validate", "calibrate"}) {
    const CliResult r = run_cli(cmd + " \"" + lab + "\" --measured \"" + file + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(file + ": line 10: surveys that lose metal with operating hours"), std::string::npos)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(d / "out"));
}

// A survey that has lost the lifter (under 1% of its metal left, kWornOutFraction: the lifter
// reached the shell, which ends a history), most likely with y_mm measured down, is one no
// history reaches: refused at its line before any work, as an area loss of the whole lifter is.
// validate compared it with a lifter still standing (exit 0); calibrate ran five histories that
// could not wear that far and exited 1.
TEST(ValidationSurveys, ASurveyThatLostTheWholeLifterIsRefused) {
  const Scene scene = testing::lab_mill();
  const LinerUnit unit = new_liner_unit(scene);
  const double hb = 5.0 + 20.0 * std::tan(30.0 * kPi / 180.0);
  const auto survey = [hb](double hours, double top_mm) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%g,%.4f,0\n%g,-5,%.4f\n%g,5,%.4f\n%g,%.4f,0\n", hours, -hb, hours, top_mm, hours,
                  top_mm, hours, hb);
    return std::string(buf);
  };
  const auto check = [&](const std::string& rows) {
    const auto surveys = validation::parse_surveys("hours,x_mm,y_mm\n" + rows, "s.csv");
    validation::check_surveys_lose_metal(surveys, unit, scene.radius_m(), 0.0, "s.csv");
  };
  std::string where;
  for (const std::string& start : {survey(0, 20.0), std::string()}) {  // judged by the survey at 0 h, or the scene
    const std::string m = refusal([&] { check(start + survey(100, 16.0) + survey(200, -14.0)); }, &where);
    EXPECT_EQ(where, start.empty() ? "line 6" : "line 10") << m;
    EXPECT_NE(m.find("the survey at 200 h has 0 mm^2 of metal above the shell line"), std::string::npos) << m;
    // Worn to 2% of its height (about 4% of its metal): still a lifter, taken.
    EXPECT_EQ(refusal([&] { check(start + survey(100, 16.0) + survey(200, 0.4)); }), "accepted");
  }
  // The commands refuse it before any work.
  const TempDir d("millwear-test-validation-whole-lifter");
  const std::string file = (d / "down.csv").string();
  std::ofstream(file) << "hours,x_mm,y_mm\n" + survey(0, 20.0) + survey(100, -2.0);
  const std::string lab = testing::source_path("scenarios/lab-mill.toml");
  for (const std::string cmd : {"validate", "calibrate"}) {
    const CliResult r = run_cli(cmd + " \"" + lab + "\" --measured \"" + file + "\" -o \"" + (d / "out").string() + "\"");
    EXPECT_EQ(r.exit_code, 2) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find(file + ": line 6: surveys that keep some of the lifter"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(d / "out"));
}

// ---- areas ----

TEST(ValidationAreas, AreaHistoryIsExactAtStagesAndLinearBetween) {
  const validation::AreaHistory h{{0.0, 100.0, 200.0}, {400e-6, 360e-6, 330e-6}};
  EXPECT_EQ(h.area_at(100.0), 360e-6);
  EXPECT_NEAR(h.area_at(25.0), 390e-6, 1e-18);
  EXPECT_NEAR(h.area_at(150.0), 345e-6, 1e-18);
  // Beyond the last stage the last slope goes on to a fifth of the last interval, then stops.
  EXPECT_DOUBLE_EQ(h.extrapolation_limit(), 220.0);
  EXPECT_NEAR(h.area_at(210.0), 327e-6, 1e-18);
  EXPECT_NEAR(h.area_at(400.0), 324e-6, 1e-18);
}

TEST(ValidationAreas, AreasMeasuredFromASimulatedRunValidateWithZeroError) {
  const WearHistory& h = quick_history();
  AreaSurveys measured;
  for (const auto& st : h.stages) measured.surveys.push_back({st.hours, st.lifter.area_m2, 0});
  // Through the file format (mm^2, 10 significant digits), as a user's file would be.
  const AreaSurveys surveys = validation::parse_area_surveys(validation::format_area_surveys(measured), "sim.csv");
  const auto rows = validation::compare_areas(surveys, validation::area_history(h.stages));
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& c : rows) {
    // 10 significant digits of ~400 mm^2: 5e-8 mm^2 rounding.
    EXPECT_LT(std::fabs(c.area_error_m2), 1e-13) << c.hours << " h";
    EXPECT_LT(std::fabs(c.area_error_pct), 1e-6);
    EXPECT_LT(std::fabs(c.loss_error_m2), 1e-13);
  }
  EXPECT_GT(rows[1].measured_loss_m2, 0.0);  // the worn survey did lose metal
  EXPECT_NEAR(rows[1].simulated_loss_m2, h.stages[0].lifter.area_m2 - h.stages[1].lifter.area_m2, 1e-18);
  EXPECT_TRUE(std::isnan(rows[0].loss_error_pct));  // 0 h: no loss to compare with
}

// Several lifters surveyed at the start scatter about their mean, the reference of the loss:
// each row's "loss" there is its gauge's scatter, not wear, and has no percentage error,
// while the rows after the start keep theirs.
TEST(ValidationAreas, RowsAtTheStartHaveNoLossPercentageWhateverTheirScatter) {
  const validation::AreaHistory h{{0.0, 100.0}, {400e-6, 360e-6}};
  for (const char* text : {"hours,area_mm2\n0,398\n0,402\n100,362\n",
                           "hours,area_loss_mm2\n0,-1.5\n0,1.5\n100,38\n"}) {
    const auto rows = validation::compare_areas(validation::parse_area_surveys(text, "a.csv"), h);
    ASSERT_EQ(rows.size(), 3u) << text;
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_NE(rows[i].measured_loss_m2, 0.0) << text;  // each start row is off the mean
      EXPECT_TRUE(std::isnan(rows[i].loss_error_pct)) << text << " row " << i << ": " << rows[i].loss_error_pct;
    }
    // 40 mm^2 simulated against 38 measured at 100 h: +2/38 of it.
    EXPECT_NEAR(rows[2].loss_error_pct, 100.0 * 2.0 / 38.0, 1e-6) << text;
  }
}

// A synthetic history in place of the engine: the lifter area falls by 0.3 mm^2/h at
// C = 1e-10 m^3/J, in proportion to C t, so the time-scaling and the linear interpolation
// between stages are exact, and the "simulation" carries no statistical error.
WearHistory synthetic_area_history(const Scene& s) {
  WearHistory h;
  h.wear_rate_m3_per_J = s.wear.wear_rate_m3_per_J;
  for (int k = 0; k <= s.wear.stages; ++k) {
    StageRecord r;
    r.stage = k;
    r.hours = k * s.wear.stage_hours;
    r.units = {LinerUnit{{{-0.02, 0.0}, {0.02, 0.0}}, 0.02}};
    r.lifter.area_m2 = 400e-6 - 0.3e-6 * (h.wear_rate_m3_per_J / 1e-10) * r.hours;
    r.simulated_s = 1.0;
    h.stages.push_back(r);
  }
  return h;
}

// A fit at either end of the search is flagged (and so never counts as converged): at the
// history's end, and at a thousandth of it, where surveys that show next to no wear put it
// (the lower end was not flagged, and calibrate took such fits as estimates of C).
TEST(ValidationCalibration, AFitAtEitherEndOfTheSearchIsFlagged) {
  const std::vector<double> worn = {100.0};
  const double reach = 200.0;  // s from 0.002 to 2
  const auto fit = [&](double (*residual)(double)) {
    return validation::fit_time_scale(worn, reach, [residual](std::size_t, double s, std::vector<double>& r) {
      r.push_back(residual(s));
    });
  };
  const validation::ScaleFit low = fit([](double s) { return s; });
  EXPECT_TRUE(low.at_bound);
  EXPECT_NEAR(low.scale, 0.002, 1e-8);
  const validation::ScaleFit high = fit([](double s) { return 1.0 / s; });
  EXPECT_TRUE(high.at_bound);
  EXPECT_NEAR(high.scale, 2.0, 1e-5);
  const validation::ScaleFit inside = fit([](double s) { return s - 1.0; });
  EXPECT_FALSE(inside.at_bound);
  EXPECT_NEAR(inside.scale, 1.0, 1e-5);
}

TEST(ValidationCalibration, AreasOnAnExactlyScalingHistoryGiveCBackAndTheFitErrorWhenKnown) {
  Scene guess = quick_lab();
  const double c_true = 1e-10;
  guess.wear.wear_rate_m3_per_J = 1.7 * c_true;
  Scene truth_scene = guess;
  truth_scene.wear.wear_rate_m3_per_J = c_true;
  truth_scene.wear.stage_hours = 100.0;
  truth_scene.wear.stages = 3;
  const WearHistory truth = synthetic_area_history(truth_scene);

  // One worn area: the fit is exact and its own error unknown (one residual).
  AreaSurveys one;
  one.surveys = {{0.0, truth.stages[0].lifter.area_m2, 2}, {200.0, truth.stages[2].lifter.area_m2, 3}};
  const auto r1 = validation::calibrate_wear_rate(guess, one, {}, {}, synthetic_area_history);
  EXPECT_TRUE(r1.converged);
  EXPECT_NEAR(r1.c_m3_per_J, c_true, 1e-6 * c_true);  // the golden section stops at 1e-7 of s
  EXPECT_FALSE(r1.fit_error_known);
  EXPECT_EQ(r1.sigma_fit_m3_per_J, 0.0);

  // Several noisy worn areas (sd 1 mm^2): the fit's error is known and covers the miss.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1e-6);
  AreaSurveys many;
  for (int k = 1; k <= 3; ++k)
    for (int lifter = 0; lifter < 3; ++lifter)
      many.surveys.push_back({truth.stages[k].hours, truth.stages[k].lifter.area_m2 + noise(rng), 0});
  const auto r = validation::calibrate_wear_rate(guess, many, {}, {}, synthetic_area_history);
  EXPECT_TRUE(r.converged);
  EXPECT_TRUE(r.fit_error_known);
  EXPECT_GT(r.sigma_fit_m3_per_J, 0.0);
  EXPECT_EQ(r.sigma_model_m3_per_J, 0.0);  // the synthetic history has no statistical error
  // 9 losses of 30-90 mm^2 with 1 mm^2 noise: C to about 1%.
  EXPECT_LT(r.expanded_m3_per_J, 0.05 * c_true);
  EXPECT_NEAR(r.c_m3_per_J, c_true, r.expanded_m3_per_J);
  EXPECT_EQ(r.survey_c.size(), 9u);
}

TEST(ValidationCalibration, HistoriesAfterTheFirstAreAveragedAndTheirSpreadIsTheModelError) {
  // Each "history" wears 4% more or less than the last, as independent runs of a noisy
  // simulation do, while claiming no statistical error of its own (rel_sem = 0). (Each fit
  // stays inside what its history reaches, 1.1 times the last survey's hours; one beyond it
  // gives a bound, left out of the mean: CalibrationBounds.)
  const double c_true = 1e-10;
  Scene guess = quick_lab();
  guess.wear.wear_rate_m3_per_J = 1.5 * c_true;
  guess.wear.stage_hours = 100.0;
  guess.wear.stages = 2;
  Scene truth_scene = guess;
  truth_scene.wear.wear_rate_m3_per_J = c_true;
  const WearHistory truth = synthetic_area_history(truth_scene);
  AreaSurveys surveys;
  for (const auto& st : truth.stages) surveys.surveys.push_back({st.hours, st.lifter.area_m2, 0});
  const double noise[] = {0.0, 0.04, -0.04, 0.04, -0.04};
  int call = 0;
  auto noisy = [&](const Scene& s) {
    WearHistory h = synthetic_area_history(s);
    const double f = 1.0 + noise[call++ % 5];
    for (auto& st : h.stages) st.lifter.area_m2 = 400e-6 - f * (400e-6 - st.lifter.area_m2);
    return h;
  };
  validation::CalibrationOptions opt;
  opt.rel_tol = 1e-6;  // never met: all five histories run
  const auto r = validation::calibrate_wear_rate(guess, surveys, opt, {}, noisy);
  ASSERT_EQ(r.runs.size(), 5u);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.histories_averaged, 4);
  double mean = 0.0;
  for (std::size_t k = 1; k < 5; ++k) mean += r.runs[k].c_estimate / 4.0;
  EXPECT_NEAR(r.c_m3_per_J, mean, 1e-9 * c_true);
  // The histories claim no error; their spread (+-4%) is the model error of the mean.
  double var = 0.0;
  for (std::size_t k = 1; k < 5; ++k) var += (r.runs[k].c_estimate - mean) * (r.runs[k].c_estimate - mean) / 3.0;
  EXPECT_NEAR(r.sigma_model_m3_per_J, std::sqrt(var) / 2.0, 1e-6 * c_true);
  EXPECT_GT(r.sigma_model_m3_per_J, 0.02 * c_true);
  for (std::size_t k = 0; k < 5; ++k) EXPECT_FALSE(r.runs[k].fit.at_bound) << k;
  // The last history alone is a few % off; the mean of the +-4% draws lands nearer the truth.
  EXPECT_GT(std::fabs(r.runs.back().c_estimate - c_true), 3.0 * std::fabs(r.c_m3_per_J - c_true));
  EXPECT_NEAR(r.c_m3_per_J, c_true, r.expanded_m3_per_J);
  EXPECT_LT(std::fabs(r.c_m3_per_J - c_true), 0.01 * c_true);
}

TEST(ValidationCalibration, RecoversAKnownWearRateFromAreasAloneWithinItsUncertainty) {
  const Scene truth_scene = load_scene(testing::source_path("tests/data/lab-quick.toml"));
  const WearHistory truth = run_wear_history(truth_scene);
  const double c_true = truth_scene.wear.wear_rate_m3_per_J;
  ASSERT_EQ(truth.stages.size(), 3u);
  // Area surveys: the new lifter, and three lifters at each of 50 and 100 h, each area with
  // Gaussian measurement noise of sd 1 mm^2 (0.25% of the 419 mm^2 lifter, about 3% of the
  // loss at 50 h), through the file format.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1e-6);
  AreaSurveys made;
  for (const auto& st : truth.stages)
    for (int lifter = 0; lifter < (st.hours > 0.0 ? 3 : 1); ++lifter)
      made.surveys.push_back({st.hours, st.lifter.area_m2 + noise(rng), 0});
  const AreaSurveys surveys = validation::parse_area_surveys(validation::format_area_surveys(made), "areas.csv");

  Scene guess = truth_scene;
  guess.wear.wear_rate_m3_per_J = 1.3 * c_true;
  validation::CalibrationOptions opt;
  // One lab-quick history's cumulative wear is uncertain by about 4% (its sigma_model): a 1%
  // tolerance on s is below what one history can resolve.
  opt.rel_tol = 0.05;
  const auto r = validation::calibrate_wear_rate(guess, surveys, opt);
  EXPECT_TRUE(r.converged) << r.runs.size() << " runs";
  EXPECT_TRUE(r.fit_error_known);
  // Stated uncertainty: the calibration's U (k = 2) together with the truth's own error.
  const double bound = synthetic_bound(r, truth_scene, truth, c_true);
  EXPECT_NEAR(r.c_m3_per_J, c_true, bound)
      << "C = " << r.c_m3_per_J << " +- " << r.expanded_m3_per_J << " (true " << c_true << ", bound " << bound << ")";
  EXPECT_GT(r.sigma_model_m3_per_J, 0.0);
  EXPECT_LT(r.expanded_m3_per_J, 0.25 * c_true);  // informative, not a blanket error
  EXPECT_EQ(r.survey_c.size(), 6u);
  std::printf("[ calibration ] areas: C = %.4g +- %.2g (true %.4g, bound %.2g) after %zu runs:", r.c_m3_per_J,
              r.expanded_m3_per_J, c_true, bound, r.runs.size());
  for (const auto& run : r.runs) std::printf(" %.4g (x %.3f)", run.c_m3_per_J, run.fit.scale);
  std::printf("\n");
}

// ---- hardness ----

TEST(Hardness, FitRecoversSyntheticAAndB) {
  // Synthetic periods: rate = 5 * a * H^b, a = 10^-b (CT = 1 at H = 10).
  const double b_true = 1.6, a_true = std::pow(10.0, -1.6);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> hard(7.0, 14.0), len(20.0, 60.0);
  std::string clean = "period,days,area_loss_mm2,hardness\n", noisy = clean;
  for (int i = 1; i <= 12; ++i) {
    const double h = hard(rng), t = len(rng), w = 5.0 * a_true * std::pow(h, b_true) * t;
    clean += std::to_string(i) + "," + io::format_exact(t) + "," + io::format_exact(w) + "," + io::format_exact(h) + "\n";
    noisy += std::to_string(i) + "," + io::format_exact(t) + "," + io::format_exact(w * std::exp(noise(rng))) + "," + io::format_exact(h) + "\n";
  }
  auto exact = validation::parse_hardness(clean, "clean.csv");
  const auto fe = validation::fit_hardness(exact, 10.0);
  EXPECT_NEAR(fe.b, b_true, 1e-9);  // noiseless: the log-log line is exact up to rounding
  EXPECT_NEAR(fe.a, a_true, 1e-9 * a_true);
  EXPECT_LT(fe.cv_after, 1e-9);
  auto data = validation::parse_hardness(noisy, "noisy.csv");
  const auto f = validation::fit_hardness(data, 10.0);
  // 1% noise on 12 periods: within 3 standard errors (and the errors are small).
  EXPECT_NEAR(f.b, b_true, 3.0 * f.b_se);
  EXPECT_NEAR(f.a, a_true, 3.0 * f.a_se);
  EXPECT_LT(f.b_se, 0.1);
  EXPECT_LT(f.cv_after, 0.2 * f.cv_before);
  for (const auto& p : data.periods) EXPECT_NEAR(p.ct, f.a * std::pow(p.hardness, f.b), 1e-12);
}

// Periods of one wear rate at several hardnesses: b = 0, and there is nothing for the line to
// explain, so no R^2 (an empty cell), not a perfect one; varying rates have one in [0, 1].
TEST(Hardness, RatesThatDoNotVaryHaveNoRSquared) {
  auto flat = validation::parse_hardness("period,days,area_loss_mm2,hardness\n1,10,120,10\n2,10,120,12\n3,10,120,14\n",
                                         "flat.csv");
  const auto f = validation::fit_hardness(flat);
  EXPECT_NEAR(f.b, 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(f.r_squared)) << f.r_squared;
  const TempDir dir("millwear-hardness-flat");
  validation::write_hardness_outputs(dir.path().string(), flat, f);
  const io::CsvData fit = io::read_csv((dir.path() / "hardness_fit.csv").string());
  EXPECT_EQ(fit.text(0, fit.column("r_squared")), "");
  auto varied = validation::parse_hardness(
      "period,days,area_loss_mm2,hardness\n1,10,100,10\n2,10,150,12\n3,10,170,14\n", "varied.csv");
  const double r2 = validation::fit_hardness(varied).r_squared;
  EXPECT_GE(r2, 0.0);
  EXPECT_LE(r2, 1.0);
}

TEST(Hardness, DefaultNormalisationKeepsTheTotalOperatingTime) {
  auto data = validation::parse_hardness(
      "period,hours,wear_rate,hardness\n1,100,2.0,10\n2,50,3.1,12\n3,80,1.7,9\n4,30,2.6,11\n", "r.csv");
  const auto f = validation::fit_hardness(data);
  double t = 0.0, ct = 0.0;
  for (const auto& p : data.periods) { t += p.length; ct += p.ct * p.length; }
  EXPECT_NEAR(ct, t, 1e-9 * t);
  EXPECT_DOUBLE_EQ(data.periods[1].rate, 3.1);  // a rate column is taken as a rate
  EXPECT_DOUBLE_EQ(data.periods[2].start, 150.0);
  EXPECT_GT(f.b, 0.0);
}

TEST(Hardness, ShippedSyntheticExampleRecoversItsStatedModel) {
  // validation/hardness-synthetic.csv: b = 2.0, a = 14^-2, 2% noise (its header says so).
  auto data = validation::read_hardness(testing::source_path("validation/hardness-synthetic.csv"));
  const auto f = validation::fit_hardness(data, 14.0);
  EXPECT_NEAR(f.b, 2.0, 3.0 * f.b_se);
  EXPECT_NEAR(f.a, std::pow(14.0, -2.0), 3.0 * f.a_se);
  EXPECT_LT(f.cv_after, 0.25 * f.cv_before);
}

TEST(Hardness, MalformedFilesNameFileAndLine) {
  auto expect = [](const std::string& text, const std::string& where, const std::string& says) {
    try {
      validation::parse_hardness(text, "h.csv");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file, "h.csv");
      EXPECT_EQ(e.where, where) << e.what();
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  expect("period,area_loss_mm2,hardness\n1,2,3\n", "line 1", "days, hours");
  expect("days,area_loss_mm2,mass_loss_kg,hardness\n1,2,3,4\n", "line 1", "several");
  // Below comment lines the header is on a later line, and the missing column is named there.
  expect("# mill 3\n# 2023\nperiod,area_loss_mm2,hardness\n1,2,3\n", "line 3", "days, hours");
  expect("# mill 3\n\nperiod,days,hardness\n1,2,3\n", "line 3", "wear column");
  expect("# c\ndays,area_loss_mm2,hardness\n1,2,3\n2,0,3\n3,2,3\n", "line 4", "wear in [1e-9, 1e9]");
  expect("days,area_loss_mm2,hardness\n1,2,3\n2,2,x\n3,2,3\n", "line 3", "hardness");
  expect("days,area_loss_mm2,hardness\n1,2,3\n2,2,4\n", "line 4", "at least 3 periods");
  expect("days,area_loss_mm2,hardness\n1,2,3\n2,2,3\n3,2,3\n", "column hardness", "0.1% or more apart");
  expect("period,days,area_loss_mm2,hardness\n1,1,2,3\n1,1,2,4\n3,1,2,5\n", "line 3", "each period once");
  expect("period,days,area_loss_mm2,hardness\n1,1,2,3\n3,1,2,4\n2,1,2,5\n", "line 4", "time order");
  expect("period,days,area_loss_mm2,hardness\n1,1,2,3\n,1,2,4\n3,1,2,5\n", "line 3", "period label");
  // Values apart in their tenth digit fitted b = 3.6e10 and wrote NaN.
  expect("days,area_loss_mm2,hardness\n1,2,13.2\n2,2.1,13.2000000001\n3,2,13.2\n", "column hardness",
         "0.1% or more apart");
  // Rates eighteen orders apart over hardness 0.1% apart: the exponent's correction factor
  // overflowed (ct = inf, cv_after = nan, exit 0). Refused by the fit, with or without a
  // reference hardness.
  for (const double reference : {0.0, 100.0}) {
    validation::HardnessData data = validation::parse_hardness(
        "period,days,area_loss_mm2,hardness\n1,10,1e-9,100\n2,10,1e9,100.1\n3,10,1e9,100.1\n", "h.csv");
    try {
      validation::fit_hardness(data, reference);
      ADD_FAILURE() << "fitted, reference " << reference;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where, "column hardness");
      EXPECT_NE(std::string(e.what()).find("puts it past that"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace millwear

namespace millwear::validation {

// `calibrate --replicates N`: after the iterations, N - 1 more histories at the calibrated C
// with seeds s+1 .. s+N-1, each fitted on its own; C is the mean of every estimate after the
// first history, and the simulation's error is their spread over sqrt(estimates). Here a
// history "fits" C exactly times a factor set by its seed, so the mean and spread are known.
TEST(CalibrationReplicates, OtherSeedsJoinTheMeanAndTheirSpreadIsTheError) {
  Scene scene = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml");
  scene.wear.wear_rate_m3_per_J = 1e-10;
  std::uint64_t seed_run = 0;
  const auto run_history = [&](const Scene& s) {
    seed_run = s.solver.seed;
    WearHistory h;
    h.wear_rate_m3_per_J = s.wear.wear_rate_m3_per_J;
    StageRecord st;
    st.hours = 100.0;
    h.stages = {StageRecord{}, st};
    return h;
  };
  // The scene's seed fits exactly (scale 1); seed s+k fits at 1 + 0.02 k.
  const auto fit = [&](const std::vector<StageRecord>&) {
    ScaleFit f;
    f.scale = 1.0 + 0.02 * static_cast<double>(seed_run - scene.solver.seed);
    f.points = 2;
    return f;
  };
  CalibrationOptions opt;
  opt.min_runs = 2;
  opt.replicates = 3;
  const CalibrationResult r = calibrate_by_time_scale(scene, {100.0}, fit, opt, nullptr, run_history);
  ASSERT_EQ(r.runs.size(), 4u);  // two iterations (both at the scene's seed), two replicates
  EXPECT_EQ(r.runs[2].replicate, 2);
  EXPECT_EQ(r.runs[2].seed, scene.solver.seed + 1);
  EXPECT_EQ(r.runs[3].seed, scene.solver.seed + 2);
  // Estimates after the first history: 1.00, 1.02, 1.04 (x 1e-10).
  EXPECT_EQ(r.histories_averaged, 3);
  EXPECT_NEAR(r.c_m3_per_J, 1.02e-10, 1e-22);
  EXPECT_NEAR(r.sigma_model_m3_per_J, 0.02e-10 / std::sqrt(3.0), 1e-22);
}

}  // namespace millwear::validation

namespace millwear::validation {

// A history whose fit stops at an end of the search gives a bound on C, not an estimate
// (its best scale is the largest its hours reach): it is left out of the mean and the
// spread. Three bounds (1.1x each) before a fit inside the search: C is that fit's alone,
// where averaging the bounds in put it 8% low.
TEST(CalibrationBounds, HistoriesFittedAtAnEndOfTheSearchAreLeftOutOfTheMean) {
  Scene scene = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml");
  scene.wear.wear_rate_m3_per_J = 1e-10;
  const double c_true = 1.5e-10;
  double c_run = 0.0;
  const auto run_history = [&](const Scene& s) {
    c_run = s.wear.wear_rate_m3_per_J;
    WearHistory h;
    h.wear_rate_m3_per_J = c_run;
    StageRecord st;
    st.hours = 100.0;
    h.stages = {StageRecord{}, st};
    return h;
  };
  int calls = 0;
  const auto fit = [&](const std::vector<StageRecord>&) {
    ScaleFit f;
    f.points = 2;
    if (++calls <= 3) {  // the history ends before the surveys' wear: a bound
      f.scale = 1.1;
      f.at_bound = true;
    } else {
      f.scale = c_true / c_run;
    }
    return f;
  };
  CalibrationOptions opt;
  const CalibrationResult r = calibrate_by_time_scale(scene, {100.0}, fit, opt, nullptr, run_history);
  ASSERT_EQ(r.runs.size(), 5u);  // three bounds, then two fits inside the search
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.histories_averaged, 2);
  EXPECT_NEAR(r.c_m3_per_J, c_true, 1e-9 * c_true);
  EXPECT_EQ(r.sigma_model_m3_per_J, 0.0);  // the two fits agree exactly

  // Every history at a bound (never converged): the last bound is reported alone.
  calls = -100;
  const CalibrationResult b = calibrate_by_time_scale(scene, {100.0}, fit, opt, nullptr, run_history);
  EXPECT_FALSE(b.converged);
  EXPECT_EQ(b.histories_averaged, 1);
  EXPECT_DOUBLE_EQ(b.c_m3_per_J, b.runs.back().c_estimate);
}

}  // namespace millwear::validation

namespace millwear::validation {

// A fit beyond what its history reaches gives only a lower bound on C (the history wore too
// little for the surveys): the same history, same seed and rate, runs again as far as the first
// and its fit takes the place of the bound. Leaving the bound out instead would leave out the
// draws that wore little, and bias C low; crept up on, C rose 1.1x a history.
TEST(CalibrationBounds, AFitBeyondItsHistorysReachIsRunAgainAsFarAsTheFirst) {
  Scene scene = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml");
  scene.wear.wear_rate_m3_per_J = 1e-10;
  std::vector<int> stages;
  std::vector<double> rates;
  const auto run_history = [&](const Scene& s) {
    stages.push_back(s.wear.stages);
    rates.push_back(s.wear.wear_rate_m3_per_J);
    WearHistory h;
    h.wear_rate_m3_per_J = s.wear.wear_rate_m3_per_J;
    for (int k = 0; k <= s.wear.stages; ++k) {
      StageRecord st;
      st.hours = s.wear.stage_hours * k;
      h.stages.push_back(st);
    }
    return h;
  };
  // The second history (one stage) wears too little: its fit is at the end of its reach. Run
  // to two stages, the same draw fits at 1.05.
  int calls = 0;
  const auto fit = [&](const std::vector<StageRecord>& st) {
    ScaleFit f;
    f.points = 2;
    ++calls;
    f.scale = calls == 2 ? 1.1 : calls == 3 ? (st.size() == 3 ? 1.05 : 0.0) : 1.0;
    f.at_bound = f.beyond_reach = calls == 2;
    return f;
  };
  CalibrationOptions opt;
  opt.min_runs = 3;
  opt.rel_tol = 0.01;
  const CalibrationResult r = calibrate_by_time_scale(scene, {200.0}, fit, opt, nullptr, run_history);
  // A survey at 200 h: stages of 200 h; the first history to 1.6 x 200 h (2 stages), the next
  // to 200 h (1 stage), at the bound, then the same rate to 2 stages again; the third to 1.
  EXPECT_EQ(stages, (std::vector<int>{2, 1, 2, 1}));
  ASSERT_EQ(rates.size(), 4u);
  EXPECT_EQ(rates[2], rates[1]);
  ASSERT_EQ(r.runs.size(), 3u);  // the bound's place taken by the longer history
  for (const CalibrationRun& run : r.runs) EXPECT_FALSE(run.fit.at_bound) << run.run;
  EXPECT_EQ(r.runs[1].run, 2);
  EXPECT_DOUBLE_EQ(r.runs[1].c_estimate, 1.05 * rates[1]);
  EXPECT_EQ(r.histories_averaged, 2);
}

}  // namespace millwear::validation
