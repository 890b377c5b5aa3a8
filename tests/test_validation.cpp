// Validation: survey files, measured against simulated profiles, calibration of C, and the
// ore-hardness correction. Round trips on the lab mill (draft fidelity, one stage).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/errors.hpp"
#include "engine_fixtures.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "plots/plots.hpp"
#include "validation/hardness.hpp"
#include "validation/profile_fit.hpp"
#include "validation/surveys.hpp"

namespace fs = std::filesystem;

namespace millwear {
namespace {

using validation::Survey;

// ---- helpers ----

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

CliResult run_cli(const std::string& args) {
  const std::string cmd = std::string("\"") + MILLWEAR_BINARY + "\" " + args + " 2>&1";
  CliResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  std::size_t got;
  while ((got = fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, got);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

fs::path temp_dir(const std::string& tag) {
  const fs::path d = fs::temp_directory_path() / ("millwear-test-validation-" + tag + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

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
  expect_survey_error("hours,x_mm,y_mm\n-5,1,2\n-5,2,3\n", "line 2", "hours >= 0");
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n0,2,2\n100,1,1\n100,2,1\n0,3,3\n", "line 6", "line 2");
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n100,1,1\n100,2,1\n", "line 2", "at least 2 points");
  expect_survey_error("hours,x_mm,y_mm\n0,1,2\n0,1,2\n", "line 3", "repeated");
  expect_survey_error("hours,x_mm,y_mm\n", "line 2", "survey rows");
}

TEST(ValidationCli, MalformedMeasurementFilesExitTwoNamingFileAndLine) {
  const fs::path d = temp_dir("cli");
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
  fs::remove_all(d);
}

TEST(ValidationCli, HardnessCommandWritesTheFitAndTheFigure) {
  const fs::path d = temp_dir("hardness");
  const CliResult r = run_cli("hardness \"" + testing::source_path("validation/hardness-synthetic.csv") + "\" -o \"" +
                              d.string() + "\" --reference-hardness 14");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData fit = io::read_csv((d / "hardness_fit.csv").string());
  ASSERT_EQ(fit.row_count(), 1u);
  EXPECT_NEAR(fit.number(0, "b"), 2.0, 3.0 * fit.number(0, "b_se"));
  EXPECT_EQ(io::read_csv((d / "hardness_periods.csv").string()).row_count(), 8u);
  if (plots::gnuplot_available()) {
    EXPECT_TRUE(fs::exists(d / "hardness.png"));
    EXPECT_TRUE(fs::exists(d / "hardness.svg"));
  }
  fs::remove_all(d);
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
  // Stated uncertainty: the expanded uncertainty U (k = 2) the calibration reports.
  EXPECT_NEAR(r.c_m3_per_J, c_true, r.expanded_m3_per_J)
      << "C = " << r.c_m3_per_J << " +- " << r.expanded_m3_per_J << " (true " << c_true << ")";
  // The uncertainty is informative (not a blanket 100%) and not zero.
  EXPECT_GT(r.expanded_m3_per_J, 0.0);
  EXPECT_LT(r.expanded_m3_per_J, 0.2 * c_true);
  EXPECT_LE(r.runs.size(), 4u);
  std::printf("[ calibration ] C = %.4g +- %.2g (true %.4g) after %zu runs\n", r.c_m3_per_J, r.expanded_m3_per_J,
              c_true, r.runs.size());
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
  expect("# c\ndays,area_loss_mm2,hardness\n1,2,3\n2,0,3\n3,2,3\n", "line 4", "wear > 0");
  expect("days,area_loss_mm2,hardness\n1,2,3\n2,2,x\n3,2,3\n", "line 3", "hardness");
  expect("days,area_loss_mm2,hardness\n1,2,3\n2,2,4\n", "line 4", "at least 3 periods");
  expect("days,area_loss_mm2,hardness\n1,2,3\n2,2,3\n3,2,3\n", "column hardness", "two different");
}

}  // namespace
}  // namespace millwear
