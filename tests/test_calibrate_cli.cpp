// `millwear validate` and `millwear calibrate` end to end, as a user runs them: the built
// binary on the quick lab mill (tests/data/lab-quick.toml: scenarios/lab-mill.toml at draft
// fidelity, one way, two 50 h stages, about 3 s a history). Surveys are made from a
// `millwear run` of that scene (its OUT/summary.csv areas and OUT/profiles/*.csv), so
// validate must find zero error and calibrate must find the scene's own C.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_support.hpp"
#include "io/csv.hpp"
#include "scene/scene.hpp"
#include "study/area_surveys.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;

namespace millwear {
namespace {

using Result = millwear::testing::CliResult;
constexpr auto run = &millwear::testing::run_millwear;

constexpr auto q = &millwear::testing::quoted;

constexpr auto slurp = &millwear::testing::read_text;

const fs::path kScene = fs::path(MILLWEAR_SOURCE_DIR) / "tests/data/lab-quick.toml";

// Every test gets its own folder and one `millwear run` of the quick scene in it.
class CalibrateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    run_dir_ = dir_ / "run";
    const Result r = run("run " + q(kScene) + " -o " + q(run_dir_) + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }

  // The run's lifter areas (OUT/summary.csv) as an area survey file: one row per stage.
  fs::path areas_from_run() const {
    const io::CsvData summary = io::read_csv((run_dir_ / "summary.csv").string());
    std::string text = "# made from `millwear run` of tests/data/lab-quick.toml\nhours,area_mm2\n";
    for (std::size_t i = 0; i < summary.row_count(); ++i)
      text += summary.text(i, summary.column("hours")) + "," + summary.text(i, summary.column("area_mm2")) + "\n";
    const fs::path p = dir_ / "areas.csv";
    std::ofstream(p) << text;
    return p;
  }

  TempDir dir_{"millwear-calibrate-cli"};
  fs::path run_dir_;
};

TEST_F(CalibrateCli, ValidateFindsZeroAreaErrorOnAreasMadeFromTheRun) {
  const fs::path areas = areas_from_run();
  const fs::path out = dir_ / "val";
  const Result r = run("validate " + q(kScene) + " --measured " + q(areas) + " -o " + q(out) + " --from " + q(run_dir_));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The folder says what made it: the command, the measured file, the run it read.
  const std::string manifest = slurp(out / "manifest.json");
  for (const std::string& s : {std::string("\"command\": \"validate\""), "\"measured\": " + q(areas),
                               "\"from\": " + q(run_dir_), std::string("\"validation.csv\""),
                               std::string("\"simulated_areas.csv\"")})
    EXPECT_NE(manifest.find(s), std::string::npos) << s << " in\n" << manifest;

  const io::CsvData v = io::read_csv((out / "validation.csv").string());
  EXPECT_EQ(v.header, (std::vector<std::string>{"survey", "line", "hours", "measured_area_mm2", "simulated_area_mm2",
                                                "area_error_mm2", "area_error_pct", "measured_loss_mm2",
                                                "simulated_loss_mm2", "loss_error_mm2", "loss_error_pct"}));
  ASSERT_EQ(v.row_count(), 3u);  // 0, 50 and 100 h
  for (std::size_t i = 0; i < v.row_count(); ++i) {
    // summary.csv carries 10 significant digits of ~400 mm^2: 5e-8 mm^2 of rounding.
    EXPECT_LT(std::fabs(v.number(i, "area_error_mm2")), 1e-6) << "row " << i;
    EXPECT_LT(std::fabs(v.number(i, "loss_error_mm2")), 1e-6) << "row " << i;
    EXPECT_GT(v.number(i, "measured_area_mm2"), 0.0);
  }
  EXPECT_GT(v.number(2, "measured_loss_mm2"), v.number(1, "measured_loss_mm2"));  // wear went on
  EXPECT_GT(v.number(1, "measured_loss_mm2"), 0.0);
  // The simulated areas are written in the area survey format, readable as measurements.
  const auto sim = validation::read_measurements((out / "simulated_areas.csv").string());
  EXPECT_TRUE(sim.areas_only);
  EXPECT_EQ(sim.count(), 3u);
  EXPECT_NE(r.output.find("area survey(s)"), std::string::npos) << r.output;
}

// A run's figures stand for the scene only as the run ran it: the scene with another speed
// (--set) or fidelity is refused, the differences named, and nothing is written: no folder
// made, and an earlier validation in the folder kept as it was.
TEST_F(CalibrateCli, ValidateRefusesARunOfOtherSettings) {
  const fs::path areas = areas_from_run();
  const fs::path earlier = dir_ / "earlier";
  ASSERT_EQ(run("validate " + q(kScene) + " --measured " + q(areas) + " -o " + q(earlier) + " --from " + q(run_dir_))
                .exit_code,
            0);
  const std::string earlier_table = slurp(earlier / "validation.csv");
  for (const std::string& extra : {std::string(" --set mill.speed=0.9"), std::string(" --fidelity standard")}) {
    for (const fs::path& out : {dir_ / "val", earlier}) {
      const Result r =
          run("validate " + q(kScene) + " --measured " + q(areas) + " -o " + q(out) + " --from " + q(run_dir_) + extra);
      EXPECT_EQ(r.exit_code, 2) << r.output;
      EXPECT_NE(r.output.find("--from"), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("settings differ"), std::string::npos) << r.output;
    }
    EXPECT_FALSE(fs::exists(dir_ / "val"));
    EXPECT_EQ(slurp(earlier / "validation.csv"), earlier_table);
  }
}

TEST_F(CalibrateCli, ValidateRunsTheSameHistoryItselfWithoutFrom) {
  // Without --from, validate runs the history itself with stages on the survey hours (the
  // scene's own 50 h here): same scene and seed, so the same areas bit for bit.
  const fs::path areas = areas_from_run();
  const fs::path out = dir_ / "val";
  const Result r = run("validate " + q(kScene) + " --measured " + q(areas) + " -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData v = io::read_csv((out / "validation.csv").string());
  ASSERT_EQ(v.row_count(), 3u);
  for (std::size_t i = 0; i < v.row_count(); ++i)
    EXPECT_LT(std::fabs(v.number(i, "area_error_pct")), 1e-6) << "row " << i;
}

TEST_F(CalibrateCli, ValidateFindsZeroDistanceOnProfilesMadeFromTheRun) {
  // The run's stage profiles (OUT/profiles/lab-quick_stageK.csv) as a profile survey file.
  std::string text = "hours,x_mm,y_mm\n";
  for (int k = 0; k <= 2; ++k) {
    const io::CsvData p = io::read_csv((run_dir_ / ("profiles/lab-quick_stage" + std::to_string(k) + ".csv")).string());
    for (std::size_t i = 0; i < p.row_count(); ++i)
      text += std::to_string(50 * k) + "," + p.text(i, p.column("x_mm")) + "," + p.text(i, p.column("y_mm")) + "\n";
  }
  const fs::path surveys = dir_ / "profiles.csv";
  std::ofstream(surveys) << text;
  const fs::path out = dir_ / "val";
  const Result r = run("validate " + q(kScene) + " --measured " + q(surveys) + " -o " + q(out) + " --from " + q(run_dir_));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData v = io::read_csv((out / "validation.csv").string());
  EXPECT_EQ(v.header.front(), "survey");
  ASSERT_EQ(v.row_count(), 3u);
  for (std::size_t i = 0; i < v.row_count(); ++i) {
    // 10 significant digits of ~10 mm coordinates (the run's profile files).
    EXPECT_LT(v.number(i, "max_mm"), 1e-6) << "row " << i;
    EXPECT_LT(std::fabs(v.number(i, "area_error_pct")), 1e-6) << "row " << i;
  }
  EXPECT_TRUE(fs::exists(out / "simulated_surveys.csv"));
}

TEST_F(CalibrateCli, CalibrateOnAreasAloneWritesTheSceneWithTheFittedRate) {
  const fs::path areas = areas_from_run();
  // The first guess: the same scene 30% off in C (its profile path made absolute, since the
  // copy lives in the test folder).
  std::string text = slurp(kScene);
  const std::string rate = "wear_rate = 1e-10 ", profile = "\"../../profiles/lab-2x30.toml\"";
  const double c_true = load_scene(kScene.string()).wear.wear_rate_m3_per_J;
  ASSERT_NE(text.find(rate), std::string::npos);
  ASSERT_NE(text.find(profile), std::string::npos);
  text.replace(text.find(rate), rate.size(), "wear_rate = 1.3e-10 ");
  text.replace(text.find(profile), profile.size(),
               "\"" + (fs::path(MILLWEAR_SOURCE_DIR) / "profiles/lab-2x30.toml").string() + "\"");
  const fs::path guess = dir_ / "guess.toml";
  std::ofstream(guess) << text;

  const fs::path out = dir_ / "cal";
  // One history of this scene has about 4% statistical error in its cumulative wear, so the
  // default 1% tolerance on the run's own C is below what it resolves; 10% converges in 2-3
  // histories.
  const Result r = run("calibrate " + q(guess) + " --measured " + q(areas) + " -o " + q(out) + " --tolerance 10");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("least squares on the area loss"), std::string::npos) << r.output;

  const io::CsvData res = io::read_csv((out / "calibration_result.csv").string());
  ASSERT_EQ(res.row_count(), 1u);
  EXPECT_EQ(res.text(0, res.column("fit_on")), "area_loss");
  EXPECT_EQ(res.number(0, "converged"), 1.0);
  EXPECT_EQ(res.number(0, "fit_error_known"), 1.0);  // two worn areas: 50 and 100 h
  const double c = res.number(0, "c_m3_per_J"), u = res.number(0, "expanded_m3_per_J");
  EXPECT_GT(u, 0.0);
  // The surveys are one realisation of the simulation and the fit another: the round trip
  // may miss by up to about sqrt(2) U (README, Validation).
  EXPECT_NEAR(c, c_true, std::sqrt(2.0) * u) << "C = " << c << " +- " << u;
  const io::CsvData runs = io::read_csv((out / "calibration.csv").string());
  EXPECT_TRUE(runs.has_column("rms_mm2"));
  EXPECT_EQ(runs.row_count(), static_cast<std::size_t>(res.number(0, "runs")));
  EXPECT_EQ(io::read_csv((out / "calibration_surveys.csv").string()).row_count(), 2u);

  // The calibrated copy loads as a scene with C filled in (6 significant digits).
  const Scene cal = load_scene((out / "guess-calibrated.toml").string());
  EXPECT_EQ(cal.wear.rate_source, WearRateSource::Given);
  EXPECT_NEAR(cal.wear.wear_rate_m3_per_J, c, 1e-5 * c);
  EXPECT_NE(slurp(out / "guess-calibrated.toml").find("calibrated on areas.csv (areas)"), std::string::npos);
  std::printf("[ calibrate cli ] areas: C = %.4g +- %.2g (true %.4g) after %d runs\n", c, u, c_true,
              static_cast<int>(res.number(0, "runs")));
}

// A scene that starts worn (scenarios/lab-worn-start.toml: a measured lifter at 2000 h, C =
// 1e-10) counts the calibration's time from its start: areas made from its own run at 2100
// and 2200 h give back its C from a first guess of 1.5e-10 (a clock from 0 h read those
// surveys 2100 h into the history and fitted 1.42e-10), validate runs the two stages to the
// last survey and finds zero error, and a survey before 2000 h is refused as input.
TEST(WornStart, CalibrationAndValidationCountFromTheStart) {
  TempDir dir("millwear-worn-start-cli");
  const fs::path worn = fs::path(MILLWEAR_SOURCE_DIR) / "scenarios/lab-worn-start.toml";
  const Result truth = run("run " + q(worn) + " -o " + q(dir.path() / "run") + " --quiet");
  ASSERT_EQ(truth.exit_code, 0) << truth.output;
  const io::CsvData summary = io::read_csv((dir.path() / "run/summary.csv").string());
  std::string text = "hours,area_mm2\n";
  for (std::size_t i = 1; i < summary.row_count(); ++i)  // 2100 and 2200 h
    text += summary.text(i, summary.column("hours")) + "," + summary.text(i, summary.column("area_mm2")) + "\n";
  const std::string areas = dir.write("areas.csv", text);

  const Result val = run("validate " + q(worn) + " --measured " + q(areas) + " -o " + q(dir.path() / "val"));
  ASSERT_EQ(val.exit_code, 0) << val.output;
  EXPECT_NE(val.output.find("running 2 stage(s) of 100 h"), std::string::npos) << val.output;
  const io::CsvData v = io::read_csv((dir.path() / "val/validation.csv").string());
  ASSERT_EQ(v.row_count(), 2u);
  for (std::size_t i = 0; i < v.row_count(); ++i)
    EXPECT_LT(std::fabs(v.number(i, "area_error_mm2")), 1e-6) << "row " << i;  // 10 digits of ~300 mm^2

  std::string guess = slurp(worn);
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"name = \"lab-worn-start\"", "name = \"worn-guess\""},
           {"wear_rate = 1e-10", "wear_rate = 1.5e-10"},
           {"\"../profiles/lab-survey-2000h.csv\"",
            "\"" + (fs::path(MILLWEAR_SOURCE_DIR) / "profiles/lab-survey-2000h.csv").string() + "\""}}) {
    const auto at = guess.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    guess.replace(at, from.size(), to);
  }
  const std::string guess_scene = dir.write("worn-guess.toml", guess);
  // Each history's own noise moves its estimate by a few percent here: converged within 5%.
  const Result cal = run("calibrate " + q(guess_scene) + " --measured " + q(areas) + " -o " + q(dir.path() / "cal") +
                         " --tolerance 5");
  ASSERT_EQ(cal.exit_code, 0) << cal.output;
  const io::CsvData res = io::read_csv((dir.path() / "cal/calibration_result.csv").string());
  const double c = res.number(0, "c_m3_per_J"), sigma = res.number(0, "sigma_m3_per_J");
  EXPECT_EQ(res.number(0, "converged"), 1.0);
  // Within three of its own standard errors of the C the surveys were made with.
  EXPECT_LT(std::fabs(c - 1e-10), 3.0 * sigma) << "C = " << c << " +- " << sigma;

  const std::string early = dir.write("early.csv", "hours,area_mm2\n1500,431\n" + text.substr(text.find('\n') + 1));
  // Hours counted from the worn start instead of from new, areas that shrink: the hours are
  // what is wrong, and validate says so as calibrate does (it said the areas do not shrink).
  const std::string relative = dir.write("relative.csv", "hours,area_mm2\n100,346\n200,286\n");
  for (const std::string& cmd : {"validate " + q(worn), "calibrate " + q(guess_scene)}) {
    for (const std::string& surveys : {early, relative}) {
      const fs::path out = dir.path() / "refused";
      const Result r = run(cmd + " --measured " + q(surveys) + " -o " + q(out));
      EXPECT_EQ(r.exit_code, 2) << r.output;
      EXPECT_NE(r.output.find("line 2: surveys at or after the history's start, the scene's lifters.start_hours (2000 h)"),
                std::string::npos) << r.output;
      EXPECT_FALSE(fs::exists(out)) << cmd;
    }
  }
}

// ---- Ctrl-C and SIGTERM ----

// Areas of the quick scene's history at its start and its two stage ends (within a few mm^2).
fs::path quick_areas(const TempDir& dir) { return dir.write("areas.csv", "hours,area_mm2\n0,419\n50,385\n100,355\n"); }

// `millwear ARGS` told to settle its charge for 1000 simulated seconds (minutes of computing),
// sent `sig` once it holds the lock of `out`: its wait status and output.
struct Stopped {
  testing::StopResult r;
  std::string log;
};
Stopped stop_while_settling(const TempDir& dir, const std::string& args, const fs::path& out, int sig) {
  Stopped s;
  const fs::path log = dir / "stopped.log";
  const pid_t pid = testing::spawn_millwear(args + " --set solver.settle_time=1000", log);
  EXPECT_GT(pid, 0);
  if (pid <= 0) return s;
  const std::string holder = "pid=" + std::to_string(pid);
  s.r = testing::stop_when(pid, [&] { return slurp(out / ".millwear.lock").find(holder) != std::string::npos; }, sig);
  s.log = slurp(log);
  return s;
}

// The command heard the stop in time and ended 128 + sig on its own, not killed by it.
void expect_exit_by_stop(const Stopped& s, int sig) {
  ASSERT_TRUE(s.r.sent) << s.log;
  ASSERT_TRUE(s.r.stopped_in_time) << s.log;
  ASSERT_TRUE(WIFEXITED(s.r.status)) << "killed by signal " << WTERMSIG(s.r.status) << "\n" << s.log;
  EXPECT_EQ(WEXITSTATUS(s.r.status), 128 + sig) << s.log;
}

// validate run again into its folder and stopped in its history (SIGTERM): it ends 143 saying
// so, and the folder holds the earlier validation byte for byte, its staging folder gone: the
// new results replace the earlier ones only once they are complete.
TEST(StoppedCommands, AValidationStoppedInItsHistoryLeavesTheEarlierResults) {
  const TempDir dir("millwear-stopped-validate");
  const fs::path areas = quick_areas(dir), out = dir / "val";
  const Result first = run("validate " + q(kScene) + " --measured " + q(areas) + " -o " + q(out));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto before = millwear::testing::files_under(out);
  ASSERT_EQ(before.count("validation.csv"), 1u);
  ASSERT_EQ(before.count("simulated_areas.csv"), 1u);
  const Stopped s =
      stop_while_settling(dir, "validate " + q(kScene) + " --measured " + q(areas) + " -o " + q(out), out, SIGTERM);
  ASSERT_NO_FATAL_FAILURE(expect_exit_by_stop(s, SIGTERM));
  EXPECT_NE(s.log.find("millwear validate: interrupted by SIGTERM"), std::string::npos) << s.log;
  EXPECT_EQ(millwear::testing::changed_files(before, millwear::testing::files_under(out)), "");
}

// calibrate stopped in a history (Ctrl-C): it ends 130 saying so and writes nothing: the folder
// its lock made is gone again, no calibrated copy.
TEST(StoppedCommands, ACalibrationStoppedInAHistoryWritesNothing) {
  const TempDir dir("millwear-stopped-calibrate");
  const fs::path areas = quick_areas(dir), out = dir / "cal";
  const Stopped s =
      stop_while_settling(dir, "calibrate " + q(kScene) + " --measured " + q(areas) + " -o " + q(out), out, SIGINT);
  ASSERT_NO_FATAL_FAILURE(expect_exit_by_stop(s, SIGINT));
  EXPECT_NE(s.log.find("millwear calibrate: interrupted by SIGINT; nothing of this calibration is written"),
            std::string::npos)
      << s.log;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace millwear
