// `millwear run` end to end on the lab-mill scene at draft fidelity (and `animate`):
// the output folder, summary.csv, normalisation, figures, interrupt + --resume, exit codes.
// One uninterrupted run is shared by every test of the suite (it takes ~15 s).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "scene/scene.hpp"
#include "study/run_outputs.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;

namespace {

using Result = millwear::testing::CliResult;
constexpr auto run = &millwear::testing::run_millwear;

std::string src(const std::string& rel) {
  return "\"" + std::string(MILLWEAR_SOURCE_DIR) + "/" + rel + "\"";
}
constexpr auto q = &millwear::testing::quoted;

constexpr auto slurp = &millwear::testing::read_text;

bool has_magic(const fs::path& p, const std::string& magic) {
  const std::string s = slurp(p);
  return s.size() > magic.size() && s.compare(0, magic.size(), magic) == 0;
}

// Every figure FIG with its standard error FIG_se beside it.
const char* const kColumns[] = {
    "design", "stage", "hours", "replicates", "error_source",
    "area_mm2", "area_mm2_se", "area_loss_pct", "area_loss_pct_se", "height_mm", "height_mm_se",
    "power_kw", "power_kw_se", "collision_kw", "collision_kw_se", "utilization", "utilization_se",
    "liner_shear_kw", "liner_shear_kw_se", "packed_shear_pct", "packed_shear_pct_se", "charge_t", "charge_t_se",
    "specific_power_kw_per_t", "specific_power_kw_per_t_se", "liner_wear_g_per_kwh", "liner_wear_g_per_kwh_se",
    "centre_of_mass_deg", "centre_of_mass_deg_se", "toe_deg", "toe_deg_se", "shoulder_deg", "shoulder_deg_se",
    "area_norm", "area_norm_se", "power_norm", "power_norm_se", "collision_norm", "collision_norm_se",
    "utilization_norm", "utilization_norm_se", "life_h", "life_h_se", "life_extrapolated", "centrifuged"};

}  // namespace

// What the shared run depends on: the binary and the scene files (size and mtime).
std::string shared_run_stamp() {
  std::string s;
  for (const std::string& f : {std::string(MILLWEAR_BINARY),
                               std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml",
                               std::string(MILLWEAR_SOURCE_DIR) + "/profiles/lab-2x30.toml"}) {
    std::error_code ec;
    s += f + " " + std::to_string(fs::file_size(f, ec)) + " " +
         std::to_string(fs::last_write_time(f, ec).time_since_epoch().count()) + "\n";
  }
  return s;
}

class AppRun : public ::testing::Test {
 protected:
  // CTest runs every test in its own process, so the shared uninterrupted run lives next to
  // the test binary and is reused while the binary and the scene are unchanged; a file lock
  // keeps parallel test processes from making it twice.
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("millwear-test-app-run-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    const fs::path cache = fs::path(MILLWEAR_BINARY).parent_path() / "test_app_run_cache";
    fs::create_directories(cache);
    full_ = cache / "full";
    const int lock = ::open((cache / "lock").c_str(), O_CREAT | O_RDWR, 0644);
    if (lock >= 0) ::flock(lock, LOCK_EX);
    const std::string stamp = shared_run_stamp();
    if (fs::exists(full_ / "plots/snapshot_lab-mill.png") && slurp(cache / "stamp") == stamp) {
      full_result_.exit_code = 0;
    } else {
      fs::remove_all(full_);
      full_result_ = run("run " + src("scenarios/lab-mill.toml") + " -o " + q(full_) + " --fidelity draft --quiet");
      if (full_result_.exit_code == 0) std::ofstream(cache / "stamp") << stamp;
    }
    if (lock >= 0) ::close(lock);  // releases the lock
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override { ASSERT_EQ(full_result_.exit_code, 0) << full_result_.output; }

  static fs::path root_, full_;
  static Result full_result_;
};
fs::path AppRun::root_, AppRun::full_;
Result AppRun::full_result_;

TEST_F(AppRun, WritesEveryListedFile) {
  // lab-mill: 2 stages after the new one, one design.
  for (const char* f :
       {"manifest.json", "summary.csv", "spectrum.csv", "snapshot_lab-mill.csv", "liner_lab-mill.csv",
        "inputs/lab-mill.toml", "inputs/lab-2x30.toml", "profiles/lab-mill_stage0.csv",
        "profiles/lab-mill_stage1.csv", "profiles/lab-mill_stage2.csv", "stages/lab-mill_stage2.done",
        "plots/fig6_profiles.png", "plots/fig7_area.png", "plots/fig8_power.png",
        "plots/fig9_collision.png", "plots/fig10_utilization.png", "plots/spectrum.png",
        "plots/snapshot_lab-mill.png", "plots/fig6_profiles.svg", "plots/fig10_utilization.svg"})
    EXPECT_TRUE(fs::is_regular_file(full_ / f)) << f;
  // No temporaries left behind (every file is written under a temporary name, then renamed).
  for (const auto& e : fs::recursive_directory_iterator(full_))
    EXPECT_FALSE(millwear::io::is_temp_name(e.path().filename().string())) << e.path();
}

TEST_F(AppRun, SummaryParsesWithTheNamedColumns) {
  const millwear::io::CsvData s = millwear::io::read_csv((full_ / "summary.csv").string());
  for (const char* c : kColumns) EXPECT_TRUE(s.has_column(c)) << c;
  // A plain liner's summary has exactly these columns, in this order (per-kind columns come
  // only with a pattern of kinds).
  ASSERT_EQ(s.header.size(), std::size(kColumns));
  for (std::size_t i = 0; i < s.header.size(); ++i) EXPECT_EQ(s.header[i], kColumns[i]) << i;
  ASSERT_EQ(s.row_count(), 3u);  // stages 0, 1, 2
  const auto hours = s.numbers("hours"), area = s.numbers("area_mm2"), loss = s.numbers("area_loss_pct");
  EXPECT_EQ(hours[0], 0.0);
  EXPECT_EQ(hours[2], 200.0);  // 2 stages of 100 h
  EXPECT_LT(area[2], area[0]);  // wear removes metal
  EXPECT_GT(loss[2], 0.0);
  // utilization = collision / power (both kW per mill); 10 significant digits written.
  const auto u = s.numbers("utilization"), c = s.numbers("collision_kw"), p = s.numbers("power_kw");
  for (std::size_t r = 0; r < s.row_count(); ++r) EXPECT_NEAR(u[r], c[r] / p[r], 1e-8 * std::fabs(u[r]));
  for (double pct : s.numbers("packed_shear_pct")) {
    EXPECT_GE(pct, 0.0);
    EXPECT_LE(pct, 100.0);
  }
}

TEST_F(AppRun, ReferenceNewStageNormalisedValuesAreOne) {
  const millwear::io::CsvData s = millwear::io::read_csv((full_ / "summary.csv").string());
  ASSERT_EQ(s.text(0, s.column("design")), "lab-mill");
  ASSERT_EQ(s.number(0, "stage"), 0.0);
  for (const char* c : {"area_norm", "power_norm", "collision_norm", "utilization_norm"})
    EXPECT_EQ(s.number(0, c), 1.0) << c;  // x / x, exact
  EXPECT_EQ(s.number(0, "area_loss_pct"), 0.0);
}

TEST_F(AppRun, FiguresAreNonEmptyPngImages) {
  for (const char* f : {"fig6_profiles", "fig7_area", "fig8_power", "fig9_collision", "fig10_utilization",
                        "spectrum", "snapshot_lab-mill"}) {
    const fs::path p = full_ / "plots" / (std::string(f) + ".png");
    ASSERT_TRUE(fs::is_regular_file(p)) << p;
    EXPECT_GT(fs::file_size(p), 1000u) << p;
    EXPECT_TRUE(has_magic(p, "\x89PNG\r\n\x1a\n")) << p;
  }
}

TEST_F(AppRun, ManifestRecordsVersionSeedFidelityAndStageTimes) {
  const auto m = nlohmann::json::parse(slurp(full_ / "manifest.json"));
  EXPECT_EQ(m.at("version"), MILLWEAR_VERSION);
  EXPECT_FALSE(m.at("commit").get<std::string>().empty());
  EXPECT_EQ(m.at("fidelity"), "draft");
  EXPECT_EQ(m.at("finished"), true);
  const auto& d = m.at("designs").at(0);
  EXPECT_EQ(d.at("seed"), 1);
  EXPECT_EQ(d.at("status"), "finished");
  EXPECT_GT(d.at("life_h").get<double>(), 0.0);
  ASSERT_FALSE(d.at("stages").empty());
  for (const auto& st : d.at("stages")) {
    EXPECT_GE(st.at("wall_s").get<double>(), 0.0);
    EXPECT_GT(st.at("simulated_s").get<double>(), 0.0);
  }
  const auto& solver = d.at("settings").at("solver");
  EXPECT_EQ(solver.at("backend"), "soft");
  // The scene leaves the contact frequency to the solver: an eighth of the substep rate.
  EXPECT_EQ(solver.at("contact_hertz").get<double>(), 0.0);
  EXPECT_NEAR(solver.at("contact_hertz_used").get<double>(),
              solver.at("substeps").get<double>() / solver.at("time_step_s").get<double>() / 8.0, 1e-9);
  // The heaviest disk over the lightest (25 mm over 15 mm balls), and the push-out floor that
  // ratio sets: what eight times the heaviest disk's weight on the lightest needs.
  const double ratio = solver.at("particle_mass_ratio").get<double>();
  EXPECT_NEAR(ratio, 25.0 * 25.0 / (15.0 * 15.0), 1e-9);
  const double w = 2.0 * millwear::kPi * solver.at("contact_hertz_used").get<double>();
  const double h = solver.at("time_step_s").get<double>() / solver.at("substeps").get<double>();
  const double floor = 8.0 * millwear::kGravity * (1.0 + ratio) / (w * (2.0 * solver.at("damping_ratio").get<double>() + h * w));
  EXPECT_NEAR(solver.at("push_out_floor_m_s").get<double>(), floor, 1e-9 * floor);
  // The smoothing radius as given and as used (the scene's 2 mm; without it, the smallest
  // particle radius).
  const auto& wear = d.at("settings").at("wear");
  EXPECT_EQ(wear.at("smoothing_radius_m").get<double>(), 0.002);
  EXPECT_EQ(wear.at("smoothing_radius_used_m").get<double>(), 0.002);
  // The library backend's settings are not the soft design's: left out.
  EXPECT_FALSE(solver.contains("velocity_iterations"));
  EXPECT_FALSE(solver.contains("position_iterations"));
}

TEST_F(AppRun, SettingsChangesNameTheOtherBackendsSettings) {
  const std::string scene = std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml";
  const auto changes = millwear::study::settings_changes(
      full_.string(), "lab-mill", millwear::load_scene(scene, {"solver.backend=box2d"}));
  const auto has = [&](const std::string& head) {
    return std::any_of(changes.begin(), changes.end(),
                       [&](const std::string& c) { return c.rfind(head, 0) == 0; });
  };
  EXPECT_TRUE(has("solver.backend: \"soft\" -> \"box2d\"")) << ::testing::PrintToString(changes);
  EXPECT_TRUE(has("solver.velocity_iterations: (none) -> ")) << ::testing::PrintToString(changes);
  EXPECT_FALSE(has("solver.substeps")) << ::testing::PrintToString(changes);
}

// A mill that reverses between stages measures the next window on a steady charge: the
// energy going into the charge (kinetic and potential) stays a small part of the drive power,
// as in the first stage. Half a revolution after reversing left 9% of it (the charge still
// falling over to the other side).
TEST(ReversingMill, EveryStageIsMeasuredOnASteadyCharge) {
  const TempDir out("millwear-test-reversing");
  const Result r = run("run " + src("tests/data/lab-quick.toml") + " -o " + q(out) +
                       " --quiet --set mill.direction=bidirectional --set mill.reverse_every=50");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto value = [](const std::string& text, const std::string& key) {
    const std::size_t at = text.find("\n" + key + "=");
    return at == std::string::npos ? NAN : std::stod(text.substr(at + key.size() + 2));
  };
  for (int stage = 0; stage <= 2; ++stage) {
    const std::string record = slurp(out / "stages" / ("lab-quick_stage" + std::to_string(stage) + ".record"));
    const double power = value(record, "summary.power_W"), change = value(record, "summary.kinetic_change_W");
    ASSERT_GT(power, 0.0) << stage;
    EXPECT_LT(std::fabs(change) / power, 0.05) << "stage " << stage << ": " << change << " W of " << power << " W";
  }
}

TEST_F(AppRun, ProfilesAreLifterLocalMillimetres) {
  const millwear::io::CsvData p = millwear::io::read_csv((full_ / "profiles/lab-mill_stage0.csv").string());
  double ymax = 0, xmax = 0;
  for (double y : p.numbers("y_mm")) ymax = std::max(ymax, y);
  for (double x : p.numbers("x_mm")) xmax = std::max(xmax, std::fabs(x));
  EXPECT_NEAR(ymax, 20.0, 1e-6);  // lab-2x30 is 20 mm high when new
  // Base half-width 16.6 mm; the file keeps the lifter plus up to 25% of it of shell.
  EXPECT_GT(xmax, 16.0);
  EXPECT_LT(xmax, 1.25 * 16.6);
}

TEST_F(AppRun, InterruptAfterStage1ThenResumeGivesTheSameSummary) {
  const fs::path out = root_ / "resumed";
  const std::string base = "run " + src("scenarios/lab-mill.toml") + " -o " + q(out) + " --fidelity draft --quiet";
  const Result stopped = run(base + " --stop-after-stage 1");
  EXPECT_NE(stopped.exit_code, 0) << stopped.output;
  EXPECT_NE(stopped.output.find("--resume"), std::string::npos) << stopped.output;
  EXPECT_TRUE(fs::exists(out / "stages/lab-mill_stage1.done"));
  EXPECT_FALSE(fs::exists(out / "stages/lab-mill_stage2.done"));
  const Result resumed = run(base + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  // Byte for byte: the stage state is stored exactly (%.17g) and each stage is deterministic.
  EXPECT_EQ(slurp(out / "summary.csv"), slurp(full_ / "summary.csv"));
  EXPECT_EQ(slurp(out / "profiles/lab-mill_stage2.csv"), slurp(full_ / "profiles/lab-mill_stage2.csv"));
}

// The same run again without --resume starts over: the earlier run's files go first, so an
// interrupted rerun leaves no figure or stage of the earlier run beside its own.
TEST_F(AppRun, ARerunWithoutResumeRemovesTheEarlierRunsFilesFirst) {
  const fs::path out = root_ / "rerun";
  fs::copy(full_, out, fs::copy_options::recursive);
  ASSERT_TRUE(fs::exists(out / "plots/fig6_profiles.png"));
  ASSERT_TRUE(fs::exists(out / "profiles/lab-mill_stage2.csv"));
  std::ofstream(out / "plots/my-notes.txt") << "the user's\n";
  const Result stopped = run("run " + src("scenarios/lab-mill.toml") + " -o " + q(out) +
                             " --fidelity draft --quiet --stop-after-stage 0");
  EXPECT_EQ(stopped.exit_code, 130) << stopped.output;
  EXPECT_FALSE(fs::exists(out / "plots/fig6_profiles.png"));
  EXPECT_FALSE(fs::exists(out / "plots/data/lab-mill_summary.csv"));
  EXPECT_FALSE(fs::exists(out / "profiles/lab-mill_stage1.csv"));
  EXPECT_FALSE(fs::exists(out / "stages/lab-mill_stage1.done"));
  EXPECT_TRUE(fs::exists(out / "profiles/lab-mill_stage0.csv"));
  EXPECT_EQ(slurp(out / "plots/my-notes.txt"), "the user's\n");
  // Every file is the new run's and listed in its manifest, but the user's.
  const nlohmann::json m = nlohmann::json::parse(slurp(out / "manifest.json"));
  std::set<std::string> listed;
  for (const auto& f : m["files"]) listed.insert(f.get<std::string>());
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), out).string();
    if (rel != "plots/my-notes.txt") {
      EXPECT_EQ(listed.count(rel), 1u) << rel << " is not the new run's";
    }
  }
}

TEST_F(AppRun, ComparisonFileNormalisesToItsReference) {
  const fs::path out = root_ / "comparison";
  const Result r = run("run " + src("tests/data/lab-comparison.toml") + " -o " + q(out) + " --fidelity draft --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const millwear::io::CsvData s = millwear::io::read_csv((out / "summary.csv").string());
  ASSERT_EQ(s.row_count(), 6u);  // two designs x stages 0..2
  const std::size_t dc = s.column("design");
  double ref_power = NAN, ref_coll = NAN;
  for (std::size_t i = 0; i < s.row_count(); ++i)
    if (s.text(i, dc) == "lab-reverse" && s.number(i, "stage") == 0) {
      for (const char* c : {"area_norm", "power_norm", "collision_norm", "utilization_norm"})
        EXPECT_EQ(s.number(i, c), 1.0) << c;
      ref_power = s.number(i, "power_kw");
      ref_coll = s.number(i, "collision_kw");
    }
  ASSERT_TRUE(std::isfinite(ref_power));
  const millwear::io::CsvData full = millwear::io::read_csv((full_ / "summary.csv").string());
  for (std::size_t i = 0, k = 0; i < s.row_count(); ++i) {
    if (s.text(i, dc) != "lab-mill") continue;
    // Relative to the reference (10 significant digits written, so 1e-8 relative).
    EXPECT_NEAR(s.number(i, "power_norm"), s.number(i, "power_kw") / ref_power, 1e-8);
    EXPECT_NEAR(s.number(i, "collision_norm"), s.number(i, "collision_kw") / ref_coll, 1e-8);
    // The same design alone or in a comparison (and in parallel) gives the same numbers.
    EXPECT_EQ(s.text(i, s.column("power_kw")), full.text(k, full.column("power_kw")));
    EXPECT_EQ(s.text(i, s.column("area_mm2")), full.text(k, full.column("area_mm2")));
    ++k;
  }
  EXPECT_TRUE(fs::is_regular_file(out / "inputs/lab-comparison.toml"));
  EXPECT_TRUE(fs::is_regular_file(out / "inputs/lab-reverse.toml"));
  EXPECT_TRUE(fs::is_regular_file(out / "plots/snapshot_lab-reverse.png"));
}

TEST_F(AppRun, AnimateWritesAGifFromAFinishedRun) {
  const fs::path gif = root_ / "anim.gif";
  const Result r = run("animate " + src("scenarios/lab-mill.toml") + " -o " + q(gif) +
                       " --seconds 0.5 --frames 10 --history " + q(full_));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_magic(gif, "GIF8")) << r.output;
  EXPECT_GT(fs::file_size(gif), 1000u);
}

// With --history every finished stage gets a frame: 10 frames over 13 stages skipped stages 4,
// 8 and 12 (the most worn liner) and said "stages 0-12". Fewer frames than stages is refused
// before anything is simulated; as many shows each stage once.
TEST_F(AppRun, AnimateFromAHistoryShowsEveryFinishedStage) {
  const fs::path history = root_ / "history13";
  const std::string set = " --set wear.stages=12 --set wear.stage_hours=5";
  const Result done = run("run " + src("tests/data/lab-quick.toml") + " -o " + q(history) + set + " --quiet");
  ASSERT_EQ(done.exit_code, 0) << done.output;
  const fs::path gif = root_ / "history13.gif";
  const std::string animate = "animate " + src("tests/data/lab-quick.toml") + " -o " + q(gif) + set +
                              " --seconds 0.5 --size 200 --keep-data --history " + q(history);
  const Result few = run(animate + " --frames 10");
  EXPECT_EQ(few.exit_code, 2) << few.output;
  EXPECT_NE(few.output.find("--frames: at least one frame per finished stage"), std::string::npos) << few.output;
  EXPECT_NE(few.output.find("(13 stages) with --history, got 10"), std::string::npos) << few.output;
  EXPECT_FALSE(fs::exists(gif));
  const Result every = run(animate + " --frames 13");
  ASSERT_EQ(every.exit_code, 0) << every.output;
  const std::string meta = slurp(root_ / "history13_frames" / "frames_meta.gp");
  for (int stage = 0; stage <= 12; ++stage)
    EXPECT_NE(meta.find("after stage " + std::to_string(stage) + " ("), std::string::npos) << stage << "\n" << meta;
}

// SIGTERM while gnuplot draws the GIF (a gnuplot slowed by a second here, so that the stop
// finds it drawing): animate waits for it, then removes its temporary frame folder and the GIF
// it drew and ends 143 saying so, where it was killed and left the folder behind.
TEST(AnimateSignals, ASigtermWhileTheGifIsDrawnLeavesNoTemporaryFolderAndNoGif) {
  const TempDir dir("millwear-test-animate-stop");
  const fs::path tmp = dir / "tmp", bin = dir / "bin", gif = dir / "gif" / "a.gif";
  fs::create_directories(tmp);
  fs::create_directories(gif.parent_path());
  // The slow gnuplot: the real one (the next on PATH) a second late.
  dir.write("bin/gnuplot", "#!/bin/sh\nsleep 1\nPATH=${PATH#*:} exec gnuplot \"$@\"\n");
  fs::permissions(bin / "gnuplot", fs::perms::owner_all);
  const fs::path log = dir / "animate.log";
  const pid_t pid = millwear::testing::spawn_millwear(
      "animate " + src("tests/data/lab-quick.toml") + " -o " + q(gif) + " --seconds 0.5 --frames 10 --size 200", log,
      "TMPDIR=" + q(tmp) + " PATH=" + q(bin) + ":\"$PATH\"");
  ASSERT_GT(pid, 0);
  const fs::path frames = tmp / ("millwear-animate-" + std::to_string(pid)) / "frames_meta.gp";
  const auto r = millwear::testing::stop_when(pid, [&] { return fs::exists(frames); }, SIGTERM);
  const std::string out = slurp(log);
  ASSERT_TRUE(r.sent) << "the frame files were not written within 30 s\n" << out;
  ASSERT_TRUE(r.stopped_in_time) << out;
  ASSERT_TRUE(WIFEXITED(r.status)) << "killed by signal " << WTERMSIG(r.status) << "\n" << out;
  EXPECT_EQ(WEXITSTATUS(r.status), 128 + SIGTERM) << out;
  EXPECT_NE(out.find("millwear animate: interrupted by SIGTERM; no GIF written"), std::string::npos) << out;
  EXPECT_TRUE(fs::is_empty(tmp)) << "left in the temporary folder: " << fs::directory_iterator(tmp)->path();
  EXPECT_TRUE(fs::is_empty(gif.parent_path())) << "left beside the GIF: "
                                               << fs::directory_iterator(gif.parent_path())->path();
}

// A gnuplot that ends without drawing the GIF fails the command (exit 1), and the gnuplot.log
// its message points to is still there to read (the temporary folder holding it was removed
// on the way out).
TEST(AnimateSignals, AGnuplotThatDrawsNothingLeavesTheLogItsMessageNames) {
  const TempDir dir("millwear-test-animate-nogif");
  const fs::path tmp = dir / "tmp", bin = dir / "bin", gif = dir / "gif" / "a.gif";
  fs::create_directories(tmp);
  fs::create_directories(gif.parent_path());
  dir.write("bin/gnuplot", "#!/bin/sh\necho 'no gif terminal here' >&2\nexit 0\n");
  fs::permissions(bin / "gnuplot", fs::perms::owner_all);
  const auto r = millwear::testing::run_shell("TMPDIR=" + q(tmp) + " PATH=" + q(bin) + ":\"$PATH\" \"" +
                                              MILLWEAR_BINARY + "\" animate " + src("tests/data/lab-quick.toml") +
                                              " -o " + q(gif) + " --seconds 0.5 --frames 10 --size 200");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const std::size_t see = r.output.find("; see ");
  ASSERT_NE(see, std::string::npos) << r.output;
  const std::string log = r.output.substr(see + 6, r.output.find("gnuplot.log", see) + 11 - see - 6);
  EXPECT_TRUE(fs::is_regular_file(log)) << log << "\n" << r.output;
  EXPECT_FALSE(fs::exists(gif));
}

// ---- bad command lines: exit 2 and a message, before any work ----

class AppRunCli : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  void expect_bad(const std::string& args, const std::string& message) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << "nothing is written before validation passes";
  }
  TempDir dir_{"millwear-test-app-cli"};
};

TEST_F(AppRunCli, UnknownOptionExits2) {
  expect_bad("run " + src("scenarios/lab-mill.toml") + " -o " + q(dir_ / "out") + " --no-such-option",
             "--no-such-option");
}

TEST_F(AppRunCli, MissingSceneExits2) {
  expect_bad("run " + q(dir_ / "nope.toml") + " -o " + q(dir_ / "out"), "nope.toml");
  expect_bad("run -o " + q(dir_ / "out"), "scene");
}

// A comparison file given to a command of one design: the message names it as one and the
// scenes it compares.
TEST_F(AppRunCli, AComparisonGivenToAOneDesignCommandIsNamedAsOne) {
  for (const std::string cmd : {"charge", "rule1"})
    expect_bad(cmd + " " + src("scenarios/sag-2x30-vs-1x30.toml") + " -o " + q(dir_ / "out"),
               "sag-2x30-vs-1x30.toml: comparison: a scene of one design; this file is a comparison of designs");
  expect_bad("charge " + src("scenarios/sag-2x30-vs-1x30.toml") + " -o " + q(dir_ / "out"),
             "(sag-2x30.toml, sag-1x30.toml, beside it)");
}

TEST_F(AppRunCli, BadFidelityNameExits2) {
  expect_bad("run " + src("scenarios/lab-mill.toml") + " -o " + q(dir_ / "out") + " --fidelity sloppy",
             "fidelity");
}

TEST_F(AppRunCli, ComparisonWithUnknownReferenceExits2) {
  const std::string lab = std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml";
  const std::string f = write("cmp.toml", "[comparison]\ndesigns = [\"" + lab + "\"]\nreference = \"nobody\"\n");
  expect_bad("run " + q(f) + " -o " + q(dir_ / "out"), "comparison.reference");
}

TEST_F(AppRunCli, ComparisonWithMissingDesignFileExits2) {
  const std::string f = write("cmp.toml", "[comparison]\ndesigns = [\"missing.toml\"]\n");
  expect_bad("run " + q(f) + " -o " + q(dir_ / "out"), "comparison.designs[0]");
}

// Two scene files of one name would write one design's files twice: refused naming the key.
// One file given twice is the same design twice: refused as such.
TEST_F(AppRunCli, TwoDesignsWithOneNameExit2) {
  std::string copy = slurp(fs::path(MILLWEAR_SOURCE_DIR) / "scenarios/lab-mill.toml");
  const std::string profile = "\"../profiles/lab-2x30.toml\"";
  copy.replace(copy.find(profile), profile.size(), "\"" + std::string(MILLWEAR_SOURCE_DIR) + "/profiles/lab-2x30.toml\"");
  std::ofstream(dir_ / "copy.toml") << copy;
  expect_bad("run " + src("scenarios/lab-mill.toml") + " " + q(dir_ / "copy.toml") + " -o " + q(dir_ / "out"),
             "copy.toml: name: a design name different from that of");
  expect_bad("run " + src("scenarios/lab-mill.toml") + " " + src("scenarios/lab-mill.toml") + " -o " +
                 q(dir_ / "out"),
             "each scene once");
}

// A scene outside a measured numerical limit stops before any work too (exit 2, nothing
// written), naming the key: the time step, and a smoothing radius wider than the lifter.
TEST_F(AppRunCli, SceneOutsideANumericalLimitExits2BeforeAnyWork) {
  const std::string lab = slurp(fs::path(MILLWEAR_SOURCE_DIR) / "scenarios/lab-mill.toml");
  const std::string profile = std::string(MILLWEAR_SOURCE_DIR) + "/profiles/lab-2x30.toml";
  auto scene_with = [&](const std::string& from, const std::string& to) {
    std::string t = lab;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) t.replace(at, from.size(), to);
    const auto p = t.find("\"../profiles/lab-2x30.toml\"");
    if (p != std::string::npos) t.replace(p, std::string("\"../profiles/lab-2x30.toml\"").size(), "\"" + profile + "\"");
    return t;
  };
  const std::string dt = write("dt.toml", scene_with("time_step = 0.001", "time_step = 0.05"));
  expect_bad("run " + q(dt) + " -o " + q(dir_ / "out"), "solver.time_step");
  const std::string wide = write("wide.toml", scene_with("smoothing_radius = 2.0", "smoothing_radius = 30.0"));
  expect_bad("run " + q(wide) + " -o " + q(dir_ / "out"), "wear.smoothing_radius");
}

// A scene pays only for the outputs it asks for: without the collision spectrum the run
// completes, spectrum.csv has no rows for it and no spectrum figure is drawn.
TEST_F(AppRunCli, SceneWithoutTheSpectrumRunsAndDrawsNoSpectrumFigure) {
  std::string t = slurp(fs::path(MILLWEAR_SOURCE_DIR) / "tests/data/lab-quick.toml");
  const std::string rel = "\"../../profiles/lab-2x30.toml\"";
  const auto p = t.find(rel);
  ASSERT_NE(p, std::string::npos);
  t.replace(p, rel.size(), "\"" + std::string(MILLWEAR_SOURCE_DIR) + "/profiles/lab-2x30.toml\"");
  const std::string on = "collision_spectrum = true";
  const auto o = t.find(on);
  ASSERT_NE(o, std::string::npos);
  t.replace(o, on.size(), "collision_spectrum = false");
  const std::string f = write("no-spectrum.toml", t);
  const Result r = run("run " + q(f) + " -o " + q(dir_ / "out") + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const std::string spectrum = slurp(dir_ / "out/spectrum.csv");
  EXPECT_EQ(spectrum.find("lab-quick"), std::string::npos) << spectrum;
  EXPECT_FALSE(fs::exists(dir_ / "out/plots/spectrum.png"));
  EXPECT_TRUE(fs::exists(dir_ / "out/summary.csv"));
}

TEST_F(AppRunCli, ShippedComparisonSceneIsValid) {
  // The default scene (the paper's comparison) validates; --check runs nothing.
  const Result r = run("run " + src("scenarios/sag-2x30-vs-1x30.toml") + " -o " + q(dir_ / "out") + " --check");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("sag-2x30: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sag-1x30: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("reference"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" disks)"), std::string::npos) << r.output;  // the charge's size, before it is run
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// `charge --check` gives the charge's size and runs nothing: a diameter in mm written as m
// shows as over a million disks before hours of computing.
TEST_F(AppRunCli, ChargeCheckGivesTheDisksAndRunsNothing) {
  const std::string base = "charge " + src("scenarios/lab-mill.toml") + " -o " + q(dir_ / "out") + " --check";
  const Result small = run(base);
  EXPECT_EQ(small.exit_code, 0) << small.output;
  const Result big = run(base + " --set mill.diameter=50");
  EXPECT_EQ(big.exit_code, 0) << big.output;
  const auto disks = [](const std::string& text) {
    const std::size_t at = text.find("about ");
    return at == std::string::npos ? 0.0 : std::stod(text.substr(at + 6));
  };
  EXPECT_GT(disks(small.output), 100.0) << small.output;
  EXPECT_LT(disks(small.output), 1000.0) << small.output;
  EXPECT_GT(disks(big.output), 1e6) << big.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  // The folder is checked as the command would check it: one holding a user's file is refused.
  fs::create_directories(dir_ / "out");
  std::ofstream(dir_ / "out" / "notes.txt") << "mine\n";
  const Result taken = run(base);
  EXPECT_EQ(taken.exit_code, 2) << taken.output;
  EXPECT_NE(taken.output.find("this folder holds notes.txt"), std::string::npos) << taken.output;
}

// A run started again from the copies of its inputs in OUT/inputs/ (same inputs, no --resume):
// the earlier run's files go, its inputs stay, and the run starts over from them.
TEST_F(AppRunCli, ARunAgainFromItsOwnInputCopiesKeepsThem) {
  // The copy in inputs/ must find its profile: the scene names it by its absolute path.
  std::string text = slurp(std::string(MILLWEAR_SOURCE_DIR) + "/tests/data/lab-quick.toml");
  const std::string relative = "profile = \"../../profiles/lab-2x30.toml\"";
  const std::size_t at = text.find(relative);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, relative.size(), "profile = \"" + std::string(MILLWEAR_SOURCE_DIR) + "/profiles/lab-2x30.toml\"");
  const std::string scene = write("self.toml", text);
  const fs::path out = dir_ / "out";
  Result r = run("run " + q(scene) + " -o " + q(out) + " --quiet --set wear.stages=1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "inputs/self.toml"));
  r = run("run " + q(out / "inputs/self.toml") + " -o " + q(out) + " --quiet --set wear.stages=1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(out / "inputs/self.toml"), text);
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
}

// A folder of the earlier charge's that is a link to one elsewhere: the charge again deletes
// nothing there (the files listed under it are not OUT's).
TEST_F(AppRunCli, AChargeAgainDeletesNothingThroughALinkedFolder) {
  const std::string base = "charge " + src("scenarios/lab-mill.toml") + " -o " + q(dir_ / "out") +
                           " --fidelity draft --revolutions 0.5 --quiet";
  ASSERT_EQ(run(base + " --set name=first").exit_code, 0);
  ASSERT_TRUE(fs::exists(dir_ / "out/plots/snapshot_first.png"));
  fs::create_directories(dir_ / "elsewhere");
  std::ofstream(dir_ / "elsewhere/snapshot_first.png") << "not the charge's\n";
  fs::remove_all(dir_ / "out/plots");
  fs::create_directory_symlink(dir_ / "elsewhere", dir_ / "out/plots");
  ASSERT_EQ(run(base).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(dir_ / "out/plots"));
  EXPECT_EQ(slurp(dir_ / "elsewhere/snapshot_first.png"), "not the charge's\n");
}

// `charge` again into its folder: the earlier charge's files (its manifest lists them) go
// first, so a contact log or a design name of that charge does not stay beside the new one's;
// a user's own file stays.
// A stage's ParaView files are written before its marker: a stage whose files could not be
// written (here a folder in the way of its .pvd) is run again by --resume, which then writes
// them. Written after the marker, the resume skipped the stage and left it without them.
TEST_F(AppRunCli, AStageWhoseParaViewFilesFailedIsRunAgainOnResume) {
  const std::string base = "run " + src("tests/data/lab-quick.toml") + " -o " + q(dir_ / "out") +
                           " --vtk --set wear.stages=2 --set wear.stage_hours=10 -q";
  ASSERT_EQ(run(base + " --stop-after-stage 0").exit_code, 130);
  const fs::path pvd1 = dir_ / "out" / "vtk" / "lab-quick_stage1.pvd";
  fs::create_directories(pvd1);
  const Result failed = run(base + " --resume");
  EXPECT_EQ(failed.exit_code, 1) << failed.output;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "stages" / "lab-quick_stage1.done"));
  fs::remove(pvd1);
  const Result resumed = run(base + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  for (int k = 0; k <= 2; ++k) {
    const fs::path index = dir_ / "out" / "vtk" / ("lab-quick_stage" + std::to_string(k) + ".pvd");
    ASSERT_TRUE(fs::is_regular_file(index)) << index;
    EXPECT_NE(slurp(index).find("<DataSet"), std::string::npos) << index;
  }
}

TEST_F(AppRunCli, AChargeAgainRemovesTheEarlierChargesFiles) {
  const std::string base = "charge " + src("scenarios/lab-mill.toml") + " -o " + q(dir_ / "out") +
                           " --fidelity draft --revolutions 0.5 --quiet";
  Result r = run(base + " --set outputs.contact_log=true");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(dir_ / "out/contacts.csv"));
  ASSERT_TRUE(fs::exists(dir_ / "out/snapshot_lab-mill.csv"));
  std::ofstream(dir_ / "out/my-notes.txt") << "mine\n";
  r = run(base + " --set name=other");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* gone : {"contacts.csv", "snapshot_lab-mill.csv", "liner_lab-mill.csv", "trajectories_lab-mill.csv",
                           "plots/snapshot_lab-mill.png", "plots/data/lab-mill_spectrum.csv"})
    EXPECT_FALSE(fs::exists(dir_ / "out" / gone)) << gone;
  EXPECT_TRUE(fs::exists(dir_ / "out/snapshot_other.csv"));
  EXPECT_EQ(slurp(dir_ / "out/my-notes.txt"), "mine\n");
  const nlohmann::json m = nlohmann::json::parse(slurp(dir_ / "out/manifest.json"));
  EXPECT_EQ(m["command"], "charge");
  std::set<std::string> listed;
  for (const auto& f : m["files"]) listed.insert(f.get<std::string>());
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "out")) {
    const std::string rel = fs::relative(e.path(), dir_ / "out").string();
    if (e.is_regular_file() && rel != "my-notes.txt" && rel != ".millwear-results") {
      EXPECT_EQ(listed.count(rel), 1u) << rel << " is not listed";
    }
  }
}

// ---- One run per output folder ----
// The small lab-quick scene (two 50 h stages at draft fidelity, a few seconds a run). One
// undisturbed run into a folder that already holds a user's files is shared by the tests.

namespace {

// `millwear ARGS` started in the background (stdout and stderr to `log`); its pid.
pid_t start_millwear(const std::string& args, const fs::path& log) {
  const std::string cmd = "exec \"" + std::string(MILLWEAR_BINARY) + "\" " + args + " >" + q(log) + " 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

int wait_exit_code(pid_t pid) {
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Every file under a folder (relative path -> content).
std::map<std::string, std::string> folder_contents(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return files;
}

// What an undisturbed run writes that must come out the same byte for byte: the tables and
// every stage profile.
std::map<std::string, std::string> results_in(const std::map<std::string, std::string>& contents) {
  std::map<std::string, std::string> r;
  for (const auto& [f, text] : contents)
    if (f == "summary.csv" || f == "spectrum.csv" || f.rfind("profiles/", 0) == 0) r[f] = text;
  return r;
}
std::map<std::string, std::string> results_of(const fs::path& dir) { return results_in(folder_contents(dir)); }

// Files a user keeps in the folder that millwear must never touch; two are named like the
// temporaries of earlier millwear versions.
const std::map<std::string, std::string> kUserFiles = {
    {"notes.txt", "my notes\n"}, {"x.tmp.1", "mine\n"}, {"summary.csv.tmp.12.0", "mine too\n"}};

void put_user_files(const fs::path& dir) {
  fs::create_directories(dir);
  for (const auto& [f, text] : kUserFiles) std::ofstream(dir / f) << text;
}

std::string quick_scene() { return src("tests/data/lab-quick.toml"); }

}  // namespace

class FolderRuns : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("millwear-test-folder-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    put_user_files(root_ / "ref");
    ref_result_ = run("run " + quick_scene() + " -o " + q(root_ / "ref") + " --quiet");
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override {
    ASSERT_EQ(ref_result_.exit_code, 0) << ref_result_.output;
    ASSERT_FALSE(results_of(root_ / "ref").empty());
  }
  static fs::path root_;
  static Result ref_result_;
};
fs::path FolderRuns::root_;
Result FolderRuns::ref_result_;

TEST_F(FolderRuns, AUsersFilesNamedLikeTemporariesSurviveARun) {
  for (const auto& [f, text] : kUserFiles) EXPECT_EQ(slurp(root_ / "ref" / f), text) << f;
  EXPECT_FALSE(fs::exists(root_ / "ref/.millwear.lock")) << "the lock goes with the run";
}

// A user's file under a name a run writes, in a folder no run recorded, is not overwritten:
// the run is refused naming it, and nothing is written.
TEST_F(FolderRuns, AUsersFileUnderAResultsNameIsRefusedNotOverwritten) {
  const fs::path out = root_ / "users-summary";
  fs::create_directories(out / "profiles");
  std::ofstream(out / "summary.csv") << "my own table\n";
  const Result check = run("run " + quick_scene() + " -o " + q(out) + " --check");  // found by --check too
  EXPECT_EQ(check.exit_code, 2) << check.output;
  EXPECT_NE(check.output.find("summary.csv is there and no run recorded it"), std::string::npos) << check.output;
  const Result r = run("run " + quick_scene() + " -o " + q(out) + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("summary.csv is there and no run recorded it"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(out / "summary.csv"), "my own table\n");
  EXPECT_FALSE(fs::exists(out / "manifest.json"));
  EXPECT_FALSE(fs::exists(out / "stages"));
  // Only the folder under a run's name: the same file moved aside, the run goes ahead.
  fs::rename(out / "summary.csv", out / "my-summary.csv");
  fs::remove(out / "profiles");
  const Result ok = run("run " + quick_scene() + " -o " + q(out) + " --quiet");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_EQ(slurp(out / "my-summary.csv"), "my own table\n");
}

// A second run into a folder another run is writing is refused at once (exit 2, naming the
// folder and the running process); the first run's results are an undisturbed run's.
TEST_F(FolderRuns, ASecondRunIntoABusyFolderIsRefusedAndTheFirstIsUndisturbed) {
  const fs::path out = root_ / "busy";
  const pid_t first = start_millwear("run " + quick_scene() + " -o " + q(out) + " --quiet", root_ / "first.log");
  ASSERT_GT(first, 0);
  // Wait until the first run holds the lock (it then runs for seconds).
  bool held = false;
  for (int i = 0; i < 400 && !held; ++i) {
    held = slurp(out / ".millwear.lock").find("pid=" + std::to_string(first)) != std::string::npos;
    if (!held) ::usleep(10000);
  }
  const Result second = run("run " + quick_scene() + " -o " + q(out) + " --quiet");
  const int first_exit = wait_exit_code(first);
  ASSERT_TRUE(held) << slurp(root_ / "first.log");
  EXPECT_EQ(second.exit_code, 2) << second.output;
  EXPECT_NE(second.output.find(out.string()), std::string::npos) << second.output;
  EXPECT_NE(second.output.find("process " + std::to_string(first)), std::string::npos) << second.output;
  ASSERT_EQ(first_exit, 0) << slurp(root_ / "first.log");
  EXPECT_EQ(results_of(out), results_of(root_ / "ref"));
  EXPECT_FALSE(fs::exists(out / ".millwear.lock"));
}

// Two runs started together: one runs, one is refused; none fails half-way.
TEST_F(FolderRuns, TwoRunsStartedTogetherGiveOneRunAndOneRefusal) {
  const fs::path out = root_ / "together";
  const pid_t a = start_millwear("run " + quick_scene() + " -o " + q(out) + " --quiet", root_ / "a.log");
  const pid_t b = start_millwear("run " + quick_scene() + " -o " + q(out) + " --quiet", root_ / "b.log");
  const int ea = wait_exit_code(a), eb = wait_exit_code(b);
  // Started together, the one that takes the lock runs for seconds while the other is refused.
  ASSERT_EQ(std::min(ea, eb), 0) << slurp(root_ / "a.log") << slurp(root_ / "b.log");
  ASSERT_EQ(std::max(ea, eb), 2) << slurp(root_ / "a.log") << slurp(root_ / "b.log");
  const std::string refused = slurp(root_ / (ea == 2 ? "a.log" : "b.log"));
  EXPECT_NE(refused.find("process " + std::to_string(ea == 2 ? b : a)), std::string::npos) << refused;
  EXPECT_EQ(results_of(out), results_of(root_ / "ref"));
}

// A folder holding another scene's results is not mixed with a new run's: refused with
// nothing changed; with --force, exactly the earlier run's files go and the user's stay.
TEST_F(FolderRuns, AnotherScenesFolderIsRefusedThenTakenOverWithForce) {
  const fs::path out = root_ / "taken";
  fs::copy(root_ / "ref", out, fs::copy_options::recursive);
  std::ofstream(out / "profiles/my-survey.csv") << "x_mm,y_mm\n0,0\n";
  std::string t = slurp(fs::path(MILLWEAR_SOURCE_DIR) / "tests/data/lab-quick.toml");
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"name = \"lab-quick\"", "name = \"lab-other\""},
           {"stages = 2", "stages = 1"},
           {"\"../../profiles/lab-2x30.toml\"", "\"" + std::string(MILLWEAR_SOURCE_DIR) + "/profiles/lab-2x30.toml\""}}) {
    const auto at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
  }
  const fs::path other = root_ / "lab-other.toml";
  std::ofstream(other) << t;

  const auto before = folder_contents(out);
  const Result refused = run("run " + q(other) + " -o " + q(out) + " --quiet");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find(out.string()), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("lab-quick"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--force"), std::string::npos) << refused.output;
  EXPECT_EQ(folder_contents(out), before) << "a refused run changes nothing";
  // --check --force says what the run would delete, and deletes nothing.
  const Result check = run("run " + q(other) + " -o " + q(out) + " --check --force");
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_NE(check.output.find("--force: " + out.string() + " holds the results of design(s) lab-quick"),
            std::string::npos) << check.output;
  EXPECT_NE(check.output.find("the run first deletes that run's files"), std::string::npos) << check.output;
  EXPECT_EQ(folder_contents(out), before) << "--check changes nothing";
  // The run's own folder: --check says the run deletes its files and starts over, or with
  // --resume continues it.
  const Result same = run("run " + quick_scene() + " -o " + q(root_ / "ref") + " --check");
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("holds a run of these same inputs: the run first deletes that run's files"),
            std::string::npos) << same.output;
  const Result resume = run("run " + quick_scene() + " -o " + q(root_ / "ref") + " --check --resume");
  EXPECT_NE(resume.output.find("the run continues after its finished stages"), std::string::npos) << resume.output;
  // Other overrides or another fidelity make it another run's folder, and the refusal says
  // which: the run's and this one's.
  const Result other_set = run("run " + quick_scene() + " -o " + q(root_ / "ref") + " --check --resume --set mill.speed=0.7");
  EXPECT_EQ(other_set.exit_code, 2) << other_set.output;
  EXPECT_NE(other_set.output.find("(--set overrides: none then, --set mill.speed=0.7 now, for lab-quick)"),
            std::string::npos) << other_set.output;
  const Result other_fidelity = run("run " + quick_scene() + " -o " + q(root_ / "ref") + " --check --resume --fidelity reference");
  EXPECT_EQ(other_fidelity.exit_code, 2) << other_fidelity.output;
  EXPECT_NE(other_fidelity.output.find("(fidelity: draft then, reference now, for lab-quick)"), std::string::npos)
      << other_fidelity.output;

  const Result forced = run("run " + q(other) + " -o " + q(out) + " --quiet --force");
  ASSERT_EQ(forced.exit_code, 0) << forced.output;
  const auto after = folder_contents(out);
  for (const auto& [f, text] : kUserFiles) EXPECT_EQ(after.count(f) ? after.at(f) : "", text) << f;
  EXPECT_EQ(after.count("profiles/my-survey.csv"), 1u);
  // Every other file is the new run's own, and its manifest lists it.
  const auto manifest = nlohmann::json::parse(slurp(out / "manifest.json"));
  std::set<std::string> listed;
  for (const auto& f : manifest.at("files")) listed.insert(f.get<std::string>());
  for (const auto& [f, text] : after) {
    if (kUserFiles.count(f) || f == "profiles/my-survey.csv") continue;
    EXPECT_EQ(f.find("lab-quick"), std::string::npos) << "left from the earlier run: " << f;
    EXPECT_EQ(listed.count(f), 1u) << "not in the manifest: " << f;
  }
  for (const auto& f : listed) EXPECT_EQ(after.count(f), 1u) << "listed but missing: " << f;
  EXPECT_EQ(listed.count("profiles/lab-other_stage1.csv"), 1u);

  // The same scene again into its own folder replaces its results as before.
  const Result again = run("run " + q(other) + " -o " + q(out) + " --quiet");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(results_of(out), results_in(after));
}

// An existing file given as the output folder is bad input for every command that writes
// one: exit 2, naming the path and that a folder was expected, the file left as it was.
TEST_F(FolderRuns, AFileAsTheOutputFolderExits2ForEveryCommand) {
  const fs::path file = root_ / "a-file";
  std::ofstream(file) << "not a folder\n";
  const std::string lab = src("scenarios/lab-mill.toml"), f = q(file);
  for (const std::string& args :
       {"run " + quick_scene() + " -o " + f, "charge " + lab + " -o " + f, "tradeoff " + lab + " -o " + f,
        "validate " + lab + " --measured " + src("validation/lab-mill-areas.csv") + " -o " + f,
        "calibrate " + lab + " --measured " + src("validation/lab-mill-areas.csv") + " -o " + f,
        "hardness " + src("validation/hardness-synthetic.csv") + " -o " + f,
        "screen " + src("tests/data/screen-lab.toml") + " -o " + f, "screen-task " + f + " 0",
        "profile " + src("profiles/lab-2x30.toml") + " --csv " + f}) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(file.string()), std::string::npos) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("folder"), std::string::npos) << args << "\n" << r.output;
  }
  EXPECT_EQ(slurp(file), "not a folder\n");
}

// `millwear charge` draws its own figures: the collision spectrum and the snapshot, whose
// legend names the scene's species and which marks the toe and shoulder it measured.
namespace {

// A run of the quick scene told to settle for 1000 simulated seconds (minutes of computing),
// sent SIGTERM `times` times, 20 ms apart, once it settles: its exit status and log. FAILs if it
// has not stopped 60 s after.
struct Stopped {
  int status = 0;
  bool held = false;
  std::string log;
  fs::path out;
};
Stopped stop_a_settling_run(const fs::path& root, int times) {
  Stopped r;
  r.out = root / "out";
  const fs::path log = root / "run.log";
  const pid_t pid =
      start_millwear("run " + quick_scene() + " -o " + q(r.out) + " --quiet --set solver.settle_time=1000", log);
  if (pid <= 0) return r;
  for (int i = 0; i < 400 && !r.held; ++i) {
    r.held = slurp(r.out / ".millwear.lock").find("pid=" + std::to_string(pid)) != std::string::npos;
    if (!r.held) ::usleep(10000);
  }
  ::usleep(500000);  // the fill is done in milliseconds: the run is settling
  // Two signals sent at once are often merged into one by the kernel; 20 ms apart each is
  // delivered, as `timeout`'s two are when the first has been handled by then.
  for (int k = 0; k < times; ++k) {
    if (k > 0) ::usleep(20000);
    ::kill(pid, SIGTERM);
  }
  const auto sent = std::chrono::steady_clock::now();
  while (::waitpid(pid, &r.status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() - sent > std::chrono::seconds(60)) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &r.status, 0);
      ADD_FAILURE() << "the run did not stop within 60 s of SIGTERM";
      break;
    }
    ::usleep(20000);
  }
  r.log = slurp(log);
  return r;
}

}  // namespace

// SIGTERM (a batch system's, `timeout`'s) is heard inside a phase, not only between measuring
// windows: a settling of 1000 simulated seconds (minutes of computing) stops within seconds,
// with the interrupted run's message and exit code.
TEST(RunSignals, ASigtermDuringALongSettlingStopsTheRunWithinSeconds) {
  const TempDir root("millwear-test-sigterm");
  const Stopped r = stop_a_settling_run(root, 1);
  ASSERT_TRUE(r.held) << r.log;
  ASSERT_TRUE(WIFEXITED(r.status)) << r.log;
  EXPECT_EQ(WEXITSTATUS(r.status), 128 + SIGTERM) << r.log;
  EXPECT_NE(r.log.find("interrupted by SIGTERM"), std::string::npos) << r.log;
  EXPECT_FALSE(fs::exists(r.out / ".millwear.lock"));
}

// `timeout` sends its signal to the command and again to the command's process group, and a
// job controller may send it twice: the same signal again at once is that one stop, not a
// second Ctrl-C, and the run stops cleanly (its message, its manifest no longer "running").
TEST(RunSignals, TheSameSignalTwiceAtOnceIsOneStop) {
  const TempDir root("millwear-test-sigterm-twice");
  const Stopped r = stop_a_settling_run(root, 2);
  ASSERT_TRUE(r.held) << r.log;
  ASSERT_TRUE(WIFEXITED(r.status)) << "killed by signal " << (WIFSIGNALED(r.status) ? WTERMSIG(r.status) : 0);
  EXPECT_EQ(WEXITSTATUS(r.status), 128 + SIGTERM) << r.log;
  EXPECT_NE(r.log.find("interrupted by SIGTERM"), std::string::npos) << r.log;
  EXPECT_EQ(slurp(r.out / "manifest.json").find("\"running\""), std::string::npos);
}

TEST(AppCharge, WritesTheSpectrumAndSnapshotFigures) {
  const TempDir out("millwear-test-charge-figures");
  const Result r = run("charge " + src("scenarios/lab-mill.toml") + " -o " + q(out) + " --revolutions 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"spectrum.png", "spectrum.svg", "snapshot_lab-mill.png", "snapshot_lab-mill.svg"})
    EXPECT_TRUE(fs::exists(out / "plots" / f)) << f;
  EXPECT_TRUE(has_magic(out / "plots" / "snapshot_lab-mill.png", "\x89PNG"));
  const std::string svg = slurp(out / "plots" / "snapshot_lab-mill.svg");
  for (const char* text : {"ball", "toe", "shoulder", "turning counter-clockwise"})
    EXPECT_NE(svg.find(text), std::string::npos) << text;
}

// Without a terminal (a log, cron, Slurm) `run` prints plain progress lines, each with the
// time of day, at every stage and when a design finishes; --quiet prints none.
TEST(AppRunProgress, PlainLinesWithoutATerminalAndNoneWhenQuiet) {
  const TempDir dir("millwear-test-plain-progress");
  const Result r = run("run " + src("tests/data/lab-quick.toml") + " -o " + q(dir / "plain") + " --progress-every 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("progress every 1s"), std::string::npos) << r.output;
  // "YYYY-MM-DD HH:MM:SS  lab-quick  stage 2/2" and "... lab-quick  finished in".
  std::istringstream lines(r.output);
  int stage_lines = 0, finished_lines = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.size() < 21 || line[4] != '-' || line[13] != ':' || line.compare(19, 2, "  ") != 0) continue;
    if (line.find("lab-quick  stage ") != std::string::npos) ++stage_lines;
    if (line.find("lab-quick  finished in") != std::string::npos) ++finished_lines;
  }
  EXPECT_GE(stage_lines, 2) << r.output;  // at least one line in each of the two stages
  EXPECT_EQ(finished_lines, 1) << r.output;
  const Result quiet = run("run " + src("tests/data/lab-quick.toml") + " -o " + q(dir / "quiet") + " --quiet");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("finished in"), std::string::npos) << quiet.output;
}
