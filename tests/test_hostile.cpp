// Hostile input: every bound is checked before anything is filled, simulated or written, and
// the exit code says whether the figures are real (0), the run failed with an event named
// (1) or the input was refused naming the file and key (2).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.hpp"
#include "common/errors.hpp"
#include "common/names.hpp"
#include "engine/engine.hpp"
#include "geometry/polyline.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "plots/plots.hpp"
#include "scene/filling.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;
using millwear::testing::quoted;
using millwear::testing::read_text;
using millwear::testing::run_millwear;

namespace {

const std::string kSource = MILLWEAR_SOURCE_DIR;

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

// The lab mill scene with one line replaced (and its profile found from anywhere).
std::string lab_mill_with(const std::string& from, const std::string& to) {
  std::string s = read_text(kSource + "/scenarios/lab-mill.toml");
  const std::string prof = "\"../profiles/lab-2x30.toml\"";
  s.replace(s.find(prof), prof.size(), "\"" + kSource + "/profiles/lab-2x30.toml\"");
  if (!from.empty()) {
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
  }
  return s;
}

// tests/data/lab-quick.toml (the lab mill at draft, two 50 h stages) with its profile found
// from anywhere.
std::string lab_quick() {
  std::string s = read_text(kSource + "/tests/data/lab-quick.toml");
  const std::string prof = "\"../../profiles/lab-2x30.toml\"";
  s.replace(s.find(prof), prof.size(), "\"" + kSource + "/profiles/lab-2x30.toml\"");
  return s;
}

// One survey of the lab lifter (tests/data/lab-quick.toml) at `hours`: its feet on the shell
// and its 10 mm top at top_mm, as rows of hours,x_mm,y_mm.
std::string lab_survey_block(const std::string& hours, double top_mm) {
  const std::string top = std::to_string(top_mm);
  return hours + ",-16.547,0\n" + hours + ",-5," + top + "\n" + hours + ",5," + top + "\n" + hours + ",16.547,0\n";
}

// The lab mill scene with `profile` (a file in dir) as its lifter, written as dir/scene.toml.
fs::path lab_mill_with_profile(const fs::path& dir, const std::string& profile) {
  std::string s = lab_mill_with("", "");
  const std::string prof = "\"" + kSource + "/profiles/lab-2x30.toml\"";
  s.replace(s.find(prof), prof.size(), "\"" + profile + "\"");
  const fs::path scene = dir / "scene.toml";
  write(scene, s);
  return scene;
}

// A refusal: exit 2, the message names the file and the key, nothing was written.
void expect_refused(const millwear::testing::CliResult& r, const std::string& file, const std::string& key,
                    const fs::path& out) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(key), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << "the refusal wrote " << out;
}

}  // namespace

// ---- step counts ---------------------------------------------------------------------------

// A time step past the limit is refused with the largest step allowed, and that step is one
// the check takes (the limit rounded down to the digits shown, not up past it).
TEST(HostileSteps, TheTimeStepARefusalOffersIsAccepted) {
  const TempDir dir("millwear-hostile-step-offer");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  for (const std::string dt : {"0.0102", "0.05"}) {
    const auto r = run_millwear("charge " + lab + " -o " + quoted(dir / "out") + " --check --set solver.time_step=" + dt);
    ASSERT_EQ(r.exit_code, 2) << r.output;
    const std::string lead = "a time step of at most ";
    const auto at = r.output.find(lead);
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string offered = r.output.substr(at + lead.size(), r.output.find(' ', at + lead.size()) - at - lead.size());
    const auto again = run_millwear("charge " + lab + " -o " + quoted(dir / "out") + " --check --set solver.time_step=" +
                                    offered);
    EXPECT_EQ(again.exit_code, 0) << dt << " offered " << offered << "\n" << again.output;
  }
}

TEST(HostileSteps, CountsPastSixtyFourBitsSaturateInsteadOfWrapping) {
  EXPECT_EQ(millwear::steps_in(1e300, 1e-3), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(millwear::steps_in(3e6 * 1.3, 1e-3), 3'900'000'000LL);  // past int: no wrap to 0
  EXPECT_EQ(millwear::steps_in(0.0, 1e-3), 0);
  EXPECT_EQ(millwear::steps_in(1e-3, 1e-3), 1);
}

TEST(HostileSteps, ChargeRevolutionsPastTheLimitAreRefused) {
  const TempDir dir("millwear-hostile-revolutions");
  const auto r = run_millwear("charge " + quoted(fs::path(kSource + "/scenarios/lab-mill.toml")) + " -o " +
                              quoted(dir / "out") + " --revolutions 3e6");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--revolutions"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // Too few: the revolutions given are named as revolutions, and the steps they make as steps
  // ("got 1" read as one revolution).
  const auto few = run_millwear("charge " + quoted(fs::path(kSource + "/scenarios/lab-mill.toml")) + " -o " +
                                quoted(dir / "out") + " --revolutions 1e-6");
  EXPECT_EQ(few.exit_code, 2) << few.output;
  EXPECT_NE(few.output.find("got 1e-06 revolutions: 1 time step of "), std::string::npos) << few.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(HostileSteps, HugeOrTinyTimesInTheSceneAreRefusedNamingTheKey) {
  const TempDir dir("millwear-hostile-times");
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"window_revolutions = 1.0", "window_revolutions = 1e300", "wear.window_revolutions"},
      {"time_step = 0.001 ", "time_step = 1e-300 ", "solver.time_step"},
      {"speed = 0.75 ", "speed = 1e-300 ", "mill.speed"},
      {"settle_time = 0.5 ", "settle_time = 1e300 ", "solver.settle_time"},
      {"spinup_revolutions = 1.0", "spinup_revolutions = 1e300", "solver.spinup_revolutions"},
      {"stage_hours = 100.0", "stage_hours = 1e300", "wear.stage_hours"},
  };
  for (const auto& [from, to, key] : cases) {
    SCOPED_TRACE(to);
    const fs::path scene = dir / "scene.toml";
    write(scene, lab_mill_with(from, to));
    expect_refused(run_millwear("run " + quoted(scene) + " -o " + quoted(dir / "out")), scene.string(), key,
                   dir / "out");
    expect_refused(run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "out")), scene.string(), key,
                   dir / "out");
  }
}

// A window of 1e4 revolutions passes the key's own range but not the step count at a fine step.
TEST(HostileSteps, AWindowOfTooManyStepsIsRefusedWithTheLimit) {
  millwear::Scene s = millwear::load_scene(kSource + "/scenarios/lab-mill.toml");
  s.wear.window_revolutions = 1e4;
  s.solver.time_step_s = 1e-5;
  try {
    millwear::check_step_counts(s, "lab.toml");
    FAIL() << "not refused";
  } catch (const millwear::InputError& e) {
    EXPECT_EQ(e.where, "wear.window_revolutions");
    EXPECT_NE(e.expected.find("at most 1e+08 time steps"), std::string::npos) << e.expected;
  }
}

// The measured window is four batches for its errors: fewer than four steps would leave a
// batch empty, and its zeros would become a made-up spread. Four steps pass.
TEST(HostileSteps, AMeasuredWindowOfFewerStepsThanBatchesIsRefused) {
  millwear::Scene s = millwear::load_scene(kSource + "/scenarios/lab-mill.toml");
  const double step_revolutions = s.solver.time_step_s / s.revolution_time_s();
  s.run.revolutions = 2.5 * step_revolutions;  // 3 steps (a phase takes whole steps, rounded up)
  try {
    millwear::check_step_counts(s, "lab.toml");
    FAIL() << "not refused";
  } catch (const millwear::InputError& e) {
    EXPECT_EQ(e.where, "run.revolutions");
    EXPECT_NE(e.expected.find("at least 4 time steps"), std::string::npos) << e.expected;
  }
  s.run.revolutions = 3.5 * step_revolutions;  // 4 steps
  EXPECT_NO_THROW(millwear::check_step_counts(s, "lab.toml"));

  const TempDir dir("millwear-hostile-short-window");
  const std::string scene = kSource + "/scenarios/lab-mill.toml";
  expect_refused(run_millwear("charge " + quoted(fs::path(scene)) + " -o " + quoted(dir / "out") + " --revolutions 1e-6"),
                 scene, "run.revolutions", dir / "out");
}

// ---- physical ranges -------------------------------------------------------------------------

TEST(HostileRanges, ADensityOfNothingIsRefused) {
  const TempDir dir("millwear-hostile-density");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_mill_with("density = 7800.0", "density = 1e-300"));
  expect_refused(run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "out")), scene.string(),
                 "charge.species[0].density", dir / "out");
}

// Sizes this fine would fill the mill with more disks than any run can take, and a time step
// to match: refused at once, not after minutes of filling.
TEST(HostileRanges, DustSizesAreRefusedBeforeTheFill) {
  const TempDir dir("millwear-hostile-dust");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_mill_with("size_range = [15.0, 25.0]", "size_range = [0.05, 0.1]"));
  for (const char* cmd : {"charge", "rule1", "animate"}) {
    SCOPED_TRACE(cmd);
    const std::string out = std::string(cmd) == "animate" ? " -o " + quoted(dir / "out" / "a.gif")
                            : std::string(cmd) == "rule1" ? "" : " -o " + quoted(dir / "out");
    expect_refused(run_millwear(std::string(cmd) + " " + quoted(scene) + out), scene.string(),
                   "charge.species[0].size_range", dir / "out");
  }
}

// ---- names -----------------------------------------------------------------------------------

TEST(HostileNames, SafeNamesAreOneRule) {
  EXPECT_TRUE(millwear::is_safe_name("2x30"));
  EXPECT_TRUE(millwear::is_safe_name("sag-1x30_v2.1+hi"));
  for (const std::string bad : {"", ".hidden", "a,b", "a\"b", "a\nb", "a b", "../x", "a/b"})
    EXPECT_FALSE(millwear::is_safe_name(bad)) << bad;
  EXPECT_FALSE(millwear::is_safe_name(std::string(65, 'a')));
  EXPECT_EQ(millwear::safe_name_from("Mill 3, liner"), "Mill_3__liner");
  EXPECT_EQ(millwear::safe_name_from(".x"), "_x");
  EXPECT_EQ(millwear::safe_name_from(std::string(100, 'b')).size(), millwear::kMaxNameLength);
}

// A name with a comma, a quote or a line end would break the CSV files `charge` writes.
TEST(HostileNames, NamesThatWouldBreakCsvAreRefusedByCharge) {
  const TempDir dir("millwear-hostile-names");
  const fs::path scene = dir / "scene.toml";
  for (const std::string& name : std::vector<std::string>{"a,b", "a\\\"b", "a\\nb", std::string(1 << 20, 'n')}) {
    write(scene, lab_mill_with("name = \"lab-mill\"", "name = \"" + name + "\""));
    expect_refused(run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "out")), scene.string(),
                   "name", dir / "out");
  }
  write(scene, lab_mill_with("name = \"ball\"", "name = \"steel, hard\""));
  expect_refused(run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "out")), scene.string(),
                 "charge.species[0].name", dir / "out");
}

// ---- filling ---------------------------------------------------------------------------------

namespace {

// The lab mill with one ball species of n sizes in equal mass fractions, from d0 by step.
millwear::Scene many_sizes(int n, double d0_m, double step_m) {
  millwear::Scene s = millwear::load_scene(kSource + "/scenarios/lab-mill.toml");
  millwear::SpeciesDef& sp = s.charge.species[0];
  sp.diameters_m.clear();
  sp.mass_fractions.assign(n, 1.0 / n);
  for (int i = 0; i < n; ++i) sp.diameters_m.push_back(d0_m + i * step_m);
  return s;
}

// What the filling asks of each size, in disks (real-valued).
std::vector<double> exact_counts(const millwear::Scene& s) {
  const millwear::SpeciesDef& sp = s.charge.species[0];
  std::vector<double> n;
  for (std::size_t j = 0; j < sp.diameters_m.size(); ++j)
    n.push_back(millwear::species_area_m2(s, 0) * sp.mass_fractions[j] /
                (0.25 * M_PI * sp.diameters_m[j] * sp.diameters_m[j]));
  return n;
}

}  // namespace

// Rounding each size alone gave 0 disks for 1,000 sizes of mass fraction 0.001, and 270 for
// 300 sizes that ask for about 233. Handing the disks left over to the largest remainders by
// count alone gave 45 sizes from 10 to 54 mm, the larger of which ask for less than a disk,
// 79% of the species' area: the leftover disks went to the small sizes. Every size is within
// one disk of its own share and the species' area within half its largest disk of its own.
TEST(HostileFilling, ManySizesGetTheirShareWithinOneDisk) {
  for (const auto& [n, d0, step] : {std::tuple{1000, 0.010, 0.00001}, std::tuple{300, 0.015, 0.00003},
                                    std::tuple{3, 0.015, 0.005}, std::tuple{45, 0.010, 0.001}}) {
    SCOPED_TRACE(n);
    const millwear::Scene s = many_sizes(n, d0, step);
    const millwear::SpeciesDef& sp = s.charge.species[0];
    const std::vector<double> exact = exact_counts(s);
    const std::vector<std::int64_t> got = millwear::disks_per_size(s, 0);
    ASSERT_EQ(got.size(), exact.size());
    double placed_m2 = 0.0, largest_m2 = 0.0;
    for (std::size_t j = 0; j < got.size(); ++j) {
      const double disk_m2 = 0.25 * M_PI * sp.diameters_m[j] * sp.diameters_m[j];
      placed_m2 += static_cast<double>(got[j]) * disk_m2;
      largest_m2 = std::max(largest_m2, disk_m2);
      EXPECT_LT(std::abs(double(got[j]) - exact[j]), 1.0) << j;
    }
    const double share_m2 = millwear::species_area_m2(s, 0);
    EXPECT_LE(std::abs(placed_m2 - share_m2), 0.5 * largest_m2 * (1.0 + 1e-9))
        << "placed " << placed_m2 << " m^2 of " << share_m2;
    EXPECT_GT(std::accumulate(got.begin(), got.end(), std::int64_t{0}), 0);
  }
}

// A uniform size range draws its disks until half the next would overfill its share: a
// share under half its largest disk's area can draw no disk at all. The share of 0.6 mean
// disks here passed the check (at least half a mean disk) and then filled four seeds in six
// with no rock. It is refused, naming the filling and the largest size; a share of half the
// largest disk places a rock whatever the seed.
TEST(HostileFilling, ARangeWhoseShareCannotTakeItsLargestDiskIsRefused) {
  const TempDir dir("millwear-hostile-range-disk");
  const std::string scene = kSource + "/scenarios/sag-2x30.toml";
  const auto r = run_millwear("charge " + quoted(fs::path(scene)) + " -o " + quoted(dir / "out") +
                              " --check --set charge.filling=0.1202437");
  expect_refused(r, scene, "charge.filling", dir / "out");
  EXPECT_NE(r.output.find("holds 0.60 of its mean disk"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("half the largest's area (250 mm"), std::string::npos) << r.output;

  millwear::Scene s = millwear::load_scene(scene);
  const double mill_m2 = M_PI * s.radius_m() * s.radius_m();
  const double largest_m2 = 0.25 * M_PI * 0.25 * 0.25;
  s.charge.filling = s.charge.ball_filling + 0.5 * largest_m2 * (1.0 + 1e-6) / (mill_m2 * s.charge.bulk_packing);
  ASSERT_TRUE(millwear::species_gets_a_disk(s, 1));
  const millwear::MillGeometry mill = millwear::build_scene_mill(s);
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    s.solver.seed = seed;
    const millwear::ChargeState charge = millwear::fill_charge(s, mill);
    int rocks = 0;
    for (std::size_t i = 0; i < charge.size(); ++i) rocks += charge.species[i] == 1;
    EXPECT_GE(rocks, 1) << "seed " << seed;
  }
}

// A size cut-off that leaves a species only sizes its share cannot hold a disk of is named as
// the cut-off (it was blamed on the filling, which gives the species a disk with every size),
// and the tradeoff ladder leaves such cut-offs out instead of offering rows that cannot run.
TEST(HostileFilling, ACutOffThatLeavesASpeciesNoDiskIsNamedAndLeftOffTheLadder) {
  const TempDir dir("millwear-hostile-cutoff-disk");
  const std::string fine = kSource + "/scenarios/sag-2x30-fine.toml";
  const std::string tiny = " --set charge.filling=0.120004";
  auto r = run_millwear("charge " + quoted(fs::path(fine)) + " -o " + quoted(dir / "out") + " --check" + tiny);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_millwear("charge " + quoted(fs::path(fine)) + " -o " + quoted(dir / "out") + " --check" + tiny +
                   " --set solver.size_cutoff=50");
  expect_refused(r, fine, "solver.size_cutoff: a cut-off that leaves charge.species[1] ('rock') at least one disk",
                 dir / "out");
  EXPECT_NE(r.output.find("with its sizes from 62.5 mm only"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(with every size it gets 1)"), std::string::npos) << r.output;
  // --only with an unknown label lists the ladder's rows (and runs nothing).
  const std::string both = kSource + "/scenarios/sag-fine-2x30-vs-1x30.toml";
  r = run_millwear("tradeoff " + quoted(fs::path(both)) + " -o " + quoted(dir / "ladder") + " --only bogus");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("size_cutoff=31.25mm, size_cutoff=50mm"), std::string::npos) << r.output;
  r = run_millwear("tradeoff " + quoted(fs::path(both)) + " -o " + quoted(dir / "ladder") + " --only bogus" + tiny);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("smoothing=25mm"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("size_cutoff="), std::string::npos) << r.output;
}

TEST(HostileFilling, AFillingOfNoDiskIsRefused) {
  const TempDir dir("millwear-hostile-empty");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_mill_with("filling = 0.3                   # fraction of the mill area\nball_filling = 0.3",
                             "filling = 1e-5\nball_filling = 1e-5"));
  expect_refused(run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "out")), scene.string(),
                 "charge.ball_filling", dir / "out");
}

// ---- rule 1 ----------------------------------------------------------------------------------

// Stopped by rule 1 is a failed run with the event named, not a finished one with an
// infinite life.
TEST(HostileRule1, AContinuousRunStoppedByRuleOneExitsOne) {
  const TempDir dir("millwear-hostile-rule1");
  std::string s = lab_quick();
  s.replace(s.find("mode = \"staged\""), 15, "mode = \"continuous\"");
  const auto f = s.find("factor = ");
  s.replace(f, s.find('\n', f) - f, "factor = 1e9");
  const fs::path scene = dir / "scene.toml";
  write(scene, s);
  const auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("C_model is too large for rule 1"), std::string::npos) << r.output;
  const std::string manifest = read_text(dir / "out" / "manifest.json");
  EXPECT_NE(manifest.find("\"status\": \"failed\""), std::string::npos) << manifest;
}

// ---- profile features ------------------------------------------------------------------------

TEST(HostileProfile, ThinnestPartOfAFinIsItsThickness) {
  // A 4 mm fin, 30 mm tall, on a 40 mm base plate 5 mm high.
  const millwear::Polyline fin = {{-0.020, 0.0}, {-0.020, 0.005}, {-0.002, 0.005}, {-0.002, 0.035},
                                  {0.002, 0.035},  {0.002, 0.005},  {0.020, 0.005}, {0.020, 0.0}};
  EXPECT_NEAR(millwear::thinnest_part(fin, 0.0002), 0.004, 0.0004);
  // A trapezoid 60 mm across at the top has no part thinner than its top.
  const millwear::Polyline trapezoid = {{-0.06, 0.0}, {-0.03, 0.08}, {0.03, 0.08}, {0.06, 0.0}};
  EXPECT_GE(millwear::thinnest_part(trapezoid, 0.001), 0.06 - 0.002);
}

// A sawtooth of 1 mm teeth leaked disks through the liner within 0.2 revolutions: refused up
// front by every command, with the thickness found and the one needed.
TEST(HostileProfile, ASawtoothFinerThanTheParticlesIsRefused) {
  const TempDir dir("millwear-hostile-saw");
  std::string points = "[[-16.0, 0.0]";
  for (int i = 1; i <= 32; ++i) points += ", [" + std::to_string(-16 + i) + ".0, " + (i % 2 ? "40.0" : "1.0") + "]";
  points += ", [16.5, 0.0]]";
  write(dir / "saw.toml", "name = \"saw\"\nform = \"polyline\"\npoints = " + points + "\n");
  const fs::path scene = lab_mill_with_profile(dir, "saw.toml");
  for (const char* cmd : {"charge", "run"}) {
    const auto r = run_millwear(std::string(cmd) + " " + quoted(scene) + " -o " + quoted(dir / "out"));
    expect_refused(r, scene.string(), "lifters.profile", dir / "out");
    EXPECT_NE(r.output.find("at least 7.5 mm thick"), std::string::npos) << r.output;
  }
}

// Faces near 90 degrees put the centred base's feet kilometres out on both sides: the reach is
// given as +-, where the trailing foot's -5.7e+08 mm read as the leading face's.
TEST(HostileProfile, FacesThatThrowTheFeetOutNameTheirReachBothWays) {
  const TempDir dir("millwear-hostile-reach");
  write(dir / "steep.toml", "name = \"steep\"\nform = \"trapezoid\"\nheight = 20.0\ntop_width = 10.0\n"
                            "leading_face_angle = 89.999999\ntrailing_face_angle = 30.0\n");
  const auto r = run_millwear("profile " + quoted(dir / "steep.toml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("steep.toml: leading_face_angle:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("its feet reach x = +-"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("x = -"), std::string::npos) << r.output;
}

// A lifter wider than the whole shell was reported as "at most -1 rows".
TEST(HostileProfile, ALifterWiderThanTheShellNamesTheProfile) {
  const TempDir dir("millwear-hostile-wide");
  std::string p = read_text(kSource + "/profiles/lab-2x30.toml");
  p.replace(p.find("top_width = 10.0"), 16, "top_width = 4000");  // the shell is 1,885 mm round
  write(dir / "wide.toml", p);
  const fs::path scene = lab_mill_with_profile(dir, "wide.toml");
  const auto r = run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "out"));
  expect_refused(r, scene.string(), "lifters.profile", dir / "out");
  EXPECT_NE(r.output.find("circumference"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("-1 rows"), std::string::npos) << r.output;
}

// Too many rows for a pattern's lifters: the most that fit is a whole number of the pattern's
// repeats (57 rows of the hi-lo lab liner fit, and 57 is no pattern of two), and the width
// named is the lifter's widest, which an overhang puts above its base.
TEST(HostileProfile, TooManyRowsForAPatternNamesAWholeNumberOfRepeats) {
  const auto r = run_millwear("charge " + quoted(fs::path(kSource + "/scenarios/lab-hi-lo.toml")) +
                              " --check -o out --set lifters.rows=60");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("expected at most 56 rows (a multiple of the pattern's 2 kinds)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("33.094 mm at its widest"), std::string::npos) << r.output;
}

// A point typed onto another edge pinches the lifter into two parts joined at a point; in
// metres the point rounds to one side of the edge or the other, and either way it is refused,
// naming the point and the edge.
TEST(HostileProfile, APointOnAnotherOfItsEdgesOrGivenTwiceIsRefusedNamingBoth) {
  const TempDir dir("millwear-hostile-touch");
  // The line back from the leading face ends on the trailing face, y = 2 (x + 50).
  for (const std::string pt : {"-37.5, 25.0", "-37.65, 24.7", "-43.9, 12.2"}) {
    write(dir / "touch.toml", "name = \"touch\"\nform = \"polyline\"\npoints = [[-50.0, 0.0], [-25.0, 50.0], "
                              "[25.0, 50.0], [30.0, 25.0], [" + pt + "], [50.0, 0.0]]\n");
    const auto r = run_millwear("profile " + quoted(dir / "touch.toml"));
    EXPECT_EQ(r.exit_code, 2) << pt << "\n" << r.output;
    EXPECT_NE(r.output.find("touch.toml: points[4]"), std::string::npos) << pt << "\n" << r.output;
    EXPECT_NE(r.output.find("lies on the edge from points[0] to points[1]"), std::string::npos) << pt << "\n" << r.output;
  }
  // A point given twice is named as the point it repeats (a foot repeated was said to be a
  // point between the feet not above the shell).
  write(dir / "twice.toml", "name = \"twice\"\nform = \"polyline\"\npoints = [[-50.0, 0.0], [-50.0, 0.0], "
                            "[0.0, 40.0], [50.0, 0.0]]\n");
  auto r = run_millwear("profile " + quoted(dir / "twice.toml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("twice.toml: points[1]: expected each point once; this point (-50, 0 mm) is points[0] again"),
            std::string::npos) << r.output;
  // A micrometre and more off the edge is a lifter with a slot, as drawn.
  write(dir / "slot.toml", "name = \"slot\"\nform = \"polyline\"\npoints = [[-50.0, 0.0], [-25.0, 50.0], "
                           "[25.0, 50.0], [30.0, 25.0], [-37.49, 25.0], [50.0, 0.0]]\n");
  r = run_millwear("profile " + quoted(dir / "slot.toml"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// A T-shaped lifter (a stem 30 mm wide, wings 8 mm thick reaching 60 mm out): the liner is
// smoothed with its neighbours' copies either side, cut a margin past the unit's ends, and the
// neighbour's wing reaching back over that cut left a polygon that crossed itself. The scene
// was refused as a smoothing radius "wider than half its narrowest part" (2 mm against 8 mm
// parts). It is checked, and wears a stage, with its wings.
TEST(HostileProfile, ATShapedLifterIsSmoothedWithItsWings) {
  const TempDir dir("millwear-hostile-tee");
  for (const char* wing : {"60.0", "65.0"}) {
    write(dir / "tee.toml", std::string("name = \"tee\"\nform = \"polyline\"\npoints = [[-15.0, 0.0], [-15.0, 10.0], [-") +
                                wing + ", 10.0], [-" + wing + ", 18.0], [" + wing + ", 18.0], [" + wing +
                                ", 10.0], [15.0, 10.0], [15.0, 0.0]]\n");
    const auto r = run_millwear("run " + quoted(fs::path(kSource + "/tests/data/lab-quick.toml")) + " -o " +
                                quoted(dir / (std::string("out") + wing)) + " -q --set wear.stages=1 --set wear.stage_hours=10 "
                                "--set lifters.profile=" + quoted(dir / "tee.toml"));
    EXPECT_EQ(r.exit_code, 0) << wing << ": " << r.output;
    EXPECT_EQ(r.output.find("smoothing_radius"), std::string::npos) << r.output;
  }
}

// A drawn profile's checks take every pair of points: 100,000 points ran for minutes. Over
// 5,000 points are refused at once, pointing to the measured CSV; 5,000 are read.
TEST(HostileProfile, ADrawnProfileOfTooManyPointsIsRefusedAtOnce) {
  const TempDir dir("millwear-hostile-many-points");
  const auto arch = [](int n) {
    std::string text = "name = \"arch\"\nform = \"polyline\"\npoints = [";
    char p[64];
    for (int k = 0; k < n; ++k) {
      const double t = static_cast<double>(k) / (n - 1);
      std::snprintf(p, sizeof p, "%s[%.6f, %.6f]", k ? ", " : "", -165.0 + 330.0 * t, 200.0 * std::sin(3.14159265358979 * t));
      text += p;
    }
    return text + "]\n";
  };
  write(dir / "many.toml", arch(100000));
  const auto r = run_millwear("profile " + quoted(dir / "many.toml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("many.toml: points: expected at most 5000 points in a drawn profile, got 100000"),
            std::string::npos) << r.output;
  write(dir / "arch.toml", arch(5000));
  const auto ok = run_millwear("profile " + quoted(dir / "arch.toml"));
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

// ---- screens and surveys ---------------------------------------------------------------------

// Four parameters of 10,000 steps each are 1e16 candidates: refused before any is made.
TEST(HostileScreen, AGridPastTheCandidateLimitIsRefused) {
  const TempDir dir("millwear-hostile-grid");
  const fs::path screen = dir / "screen.toml";
  write(screen, "[screen]\nname = \"huge\"\nbase = \"" + kSource +
                    "/scenarios/lab-mill.toml\"\nstages = 1\nsampling = \"grid\"\n\n[family]\n"
                    "height = {min = 15.0, max = 25.0, steps = 10000}\n"
                    "top_width = {min = 5.0, max = 15.0, steps = 10000}\n"
                    "leading_face_angle = {min = 10.0, max = 40.0, steps = 10000}\n"
                    "trailing_face_angle = {min = 10.0, max = 40.0, steps = 10000}\n");
  const auto r = run_millwear("screen " + quoted(screen) + " -o " + quoted(dir / "out"));
  expect_refused(r, screen.string(), "family", dir / "out");
  EXPECT_NE(r.output.find("at most 100000 candidates"), std::string::npos) << r.output;
}

// Areas that grow with time cannot give a wear rate: refused before the first history. Beyond
// a gauge's noise it is metal gained, said at the first row that gains; within it (2 mm^2 of
// 419), the areas do not shrink.
TEST(HostileSurveys, CalibrateRefusesAreasThatGrow) {
  const TempDir dir("millwear-hostile-grow");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,430\n100,445\n");
  auto r = run_millwear("calibrate " + scene + " --measured " + quoted(dir / "areas.csv") + " -o " + quoted(dir / "out"));
  expect_refused(r, (dir / "areas.csv").string(), "line 3", dir / "out");
  EXPECT_NE(r.output.find("wear removes metal, and the survey at 50 h has 430 mm^2, 11 mm^2 more"), std::string::npos)
      << r.output;
  write(dir / "flat.csv", "hours,area_mm2\n0,419\n50,419\n100,421\n");
  r = run_millwear("calibrate " + scene + " --measured " + quoted(dir / "flat.csv") + " -o " + quoted(dir / "out"));
  expect_refused(r, (dir / "flat.csv").string(), "line 4", dir / "out");
  EXPECT_NE(r.output.find("areas do not shrink with time"), std::string::npos) << r.output;
}

// Profiles that lost no metal give no wear rate, as areas that do not shrink give none: refused
// at the last survey's line before the first history (it ran five histories, exit 1, and wrote a
// calibrated copy with C = 5e-25 m^3/J). Later surveys that copy the one at the start, or stand
// a gauge's noise above it, lost nothing.
TEST(HostileSurveys, CalibrateRefusesProfilesThatLostNoMetal) {
  const TempDir dir("millwear-hostile-no-wear");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  const std::string start = "hours,x_mm,y_mm\n" + lab_survey_block("0", 20.0);
  for (const std::string& later : {lab_survey_block("50", 20.0) + lab_survey_block("100", 20.0),
                                   lab_survey_block("50", 20.01) + lab_survey_block("100", 20.02)}) {
    write(dir / "profiles.csv", start + later);
    const auto r = run_millwear("calibrate " + scene + " --measured " + quoted(dir / "profiles.csv") + " -o " +
                                quoted(dir / "out"));
    expect_refused(r, (dir / "profiles.csv").string(), "line 10", dir / "out");
    EXPECT_NE(r.output.find("have lost none"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("history"), r.output.find("history's start")) << "a history ran: " << r.output;
  }
}

// Losses within a gauge's noise give no wear rate: the histories shrank C by a thousand a run
// (the re-smoothing alone takes more than the surveys lost) and ended without converging.
// Refused at the line of the survey that lost the most, before the first history.
TEST(HostileSurveys, CalibrateRefusesLossesWithinAGaugesNoise) {
  const TempDir dir("millwear-hostile-noise-loss");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,418.999\n100,419.0005\n");
  auto r = run_millwear("calibrate " + scene + " --measured " + quoted(dir / "areas.csv") + " -o " + quoted(dir / "out"));
  expect_refused(r, (dir / "areas.csv").string(), "line 3", dir / "out");
  EXPECT_NE(r.output.find("the survey that lost the most, at 50 h, lost 0.001 mm^2"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("history"), r.output.find("history's start")) << "a history ran: " << r.output;
  // 1% of 419 mm^2 is 4.19 mm^2: a survey that lost 5 mm^2 is calibrated on.
  write(dir / "worn.csv", "hours,area_loss_mm2\n0,0\n50,1\n100,5\n");
  r = run_millwear("calibrate " + scene + " --measured " + quoted(dir / "worn.csv") + " -o " + quoted(dir / "out") +
                   " --max-runs 1");
  EXPECT_NE(r.exit_code, 2) << r.output;
  // Profiles: a lifter 20 mm high, 10 mm across its top, lowered by 0.01 mm loses about 0.3 mm^2.
  write(dir / "profiles.csv", "hours,x_mm,y_mm\n" + lab_survey_block("0", 20.0) + lab_survey_block("50", 19.99) +
                                  lab_survey_block("100", 19.995));
  r = run_millwear("calibrate " + scene + " --measured " + quoted(dir / "profiles.csv") + " -o " + quoted(dir / "out2"));
  expect_refused(r, (dir / "profiles.csv").string(), "line 6", dir / "out2");
  EXPECT_NE(r.output.find("the survey that lost the most, at 50 h"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("history"), r.output.find("history's start")) << "a history ran: " << r.output;
}

// validate's table printed the hours to a whole hour, so a survey at 0.5 h read 0 h, as the
// survey at the start; the table keeps what the file says, as validation.csv does.
TEST(HostileSurveys, ValidatePrintsASurveyWithinTheFirstHourAtItsHours) {
  const TempDir dir("millwear-hostile-half-hour");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n0.5,418.5\n50,415\n");
  const auto r = run_millwear("validate " + scene + " --measured " + quoted(dir / "areas.csv") + " -o " +
                              quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("      2      3      0.5 "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("      3      4       50 "), std::string::npos) << r.output;
  EXPECT_NE(read_text(dir / "out" / "validation.csv").find("\n2,3,0.5,418.5,"), std::string::npos);
}

// A survey too far out for the scene's stages: 999,999 h in 50 h stages is 20,000 stages, twice
// what a scene may ask for (wear.stages); validate ran them all (hours of a lifter that hardly
// wears), calibrate 1.6 times as many. Refused at the survey's line, with a stage_hours that would
// do, before any history.
TEST(HostileSurveys, ASurveyPastTheStagesAHistoryMayRunIsRefused) {
  const TempDir dir("millwear-hostile-far-survey");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,418.9\n999999,418\n");
  // (calibrate takes no wear rate on its command line: the scene's is its first guess.)
  for (const std::string command : {"validate --set wear.wear_rate=1e-20", "calibrate"}) {
    const auto r = run_millwear(command + " " + scene + " --measured " + quoted(dir / "areas.csv") + " -o " +
                                quoted(dir / "out"));
    expect_refused(r, (dir / "areas.csv").string(), "line 4", dir / "out");
    EXPECT_NE(r.output.find("at most 10000 stages"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("stage 0 at"), std::string::npos) << "a history ran: " << r.output;
  }
  // Within the limit (9,999 stages of 50 h) validate's surveys pass this check and meet the next
  // one, made before any work too: the last row, above the start, gained metal.
  write(dir / "near.csv", "hours,area_mm2\n0,419\n50,418.9\n499950,450\n");
  const auto near = run_millwear("validate " + scene + " --measured " + quoted(dir / "near.csv") + " -o " +
                                 quoted(dir / "out") + " --set wear.wear_rate=1e-20");
  expect_refused(near, (dir / "near.csv").string(), "line 4", dir / "out");
  EXPECT_EQ(near.output.find("at most 10000 stages"), std::string::npos) << near.output;
  EXPECT_NE(near.output.find("wear removes metal"), std::string::npos) << near.output;
}

// A survey point far below the shell line (250 mm in the 0.6 m lab mill, where a measured
// surface may reach a tenth of the radius, 30 mm) is no liner: validate took it (a distance of
// 1245% of the height) and calibrate ran every history to the search's end. Refused at the
// survey's line before any history; plates a few mm below the line are taken.
TEST(HostileSurveys, ASurveyPointFarBelowTheShellLineIsRefused) {
  const TempDir dir("millwear-hostile-deep-survey");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  const std::string worn = "100,-16,0\n100,-10,10\n100,10,10\n100,16,0\n";
  write(dir / "deep.csv", "hours,x_mm,y_mm\n" + worn + "100,40,-250\n");
  write(dir / "plates.csv", "hours,x_mm,y_mm\n100,-40,-3\n" + worn + "100,40,-3\n");
  for (const char* command : {"validate", "calibrate"}) {
    const auto r = run_millwear(std::string(command) + " " + scene + " --measured " + quoted(dir / "deep.csv") +
                                " -o " + quoted(dir / "out"));
    expect_refused(r, (dir / "deep.csv").string(), "line 2", dir / "out");
    EXPECT_NE(r.output.find("at most a tenth of it (30.0 mm) below the shell line"), std::string::npos) << r.output;
  }
  const auto plates = run_millwear("validate " + scene + " --measured " + quoted(dir / "plates.csv") + " -o " +
                                   quoted(dir / "out"));
  EXPECT_EQ(plates.output.find("below the shell line"), std::string::npos) << plates.output;
}

// Areas in cm^2, or ten times too small, lose in proportion: calibrate fitted C = 9e-12 to
// them with exit 0 (true 1e-10). Rows at the start measure the scene's lifter as cast, so
// their mean is held within a factor of two of its area; a casting a few % off is taken.
TEST(HostileSurveys, AreasAtTheStartFarFromTheScenesLifterAreRefused) {
  const TempDir dir("millwear-hostile-area-units");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  write(dir / "tenth.csv", "hours,area_mm2\n0,41.91\n50,39.0\n100,35.95\n");
  write(dir / "cm2.csv", "hours,area_mm2\n0,4.191\n50,3.90\n100,3.595\n");
  for (const char* file : {"tenth.csv", "cm2.csv"})
    for (const char* command : {"validate", "calibrate"}) {
      const auto r = run_millwear(std::string(command) + " " + scene + " --measured " + quoted(dir / file) + " -o " +
                                  quoted(dir / "out"));
      expect_refused(r, (dir / file).string(), "line 2", dir / "out");
      EXPECT_NE(r.output.find("within a factor of two of the scene's lifter"), std::string::npos) << r.output;
    }
  write(dir / "cast.csv", "hours,area_mm2\n0,430\n50,400\n100,370\n");
  const auto cast = run_millwear("validate " + scene + " --measured " + quoted(dir / "cast.csv") + " -o " +
                                 quoted(dir / "out"));
  EXPECT_EQ(cast.exit_code, 0) << cast.output;
}

// calibrate finds the rate: a wear rate on its command line is refused however the override
// is written (a space before '=' passed the check and then failed the copy's read-back after
// every history), or set through the [wear] table that holds it.
TEST(HostileSurveys, CalibrateRefusesAWearRateOverrideInAnySpelling) {
  const TempDir dir("millwear-hostile-calibrate-rate");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,390\n100,360\n");
  for (const std::string set : {"'wear.wear_rate =2e-10'", "'wear.area_loss_rate= 100'", "'wear={wear_rate=2e-10}'",
                                "wear.height_loss_rate=1"}) {
    const auto r = run_millwear("calibrate " + scene + " --measured " + quoted(dir / "areas.csv") + " -o " +
                                quoted(dir / "out") + " --set " + set);
    EXPECT_EQ(r.exit_code, 2) << set << ": " << r.output;
    EXPECT_NE(r.output.find("no wear rate on the command line of calibrate"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("stage 0 at"), std::string::npos) << "a history ran: " << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << set;
  }
}

// The calibrated copy is checked for its rate before the histories, but without the --set
// overrides, which it does not hold: a relative lifters.profile among them resolves from the
// scene's folder, and from the copy's folder (-o elsewhere) it named a file that is not there.
TEST(HostileSurveys, CalibrateTakesARelativeProfileOverrideWithTheCopyElsewhere) {
  const TempDir dir("millwear-hostile-calibrate-relative");
  fs::create_directories(dir / "sc" / "prof");
  write(dir / "sc" / "prof" / "lab-2x30.toml", read_text(kSource + "/profiles/lab-2x30.toml"));
  std::string scene = read_text(kSource + "/tests/data/lab-quick.toml");
  const std::string profile = "\"../../profiles/lab-2x30.toml\"";
  ASSERT_NE(scene.find(profile), std::string::npos);
  scene.replace(scene.find(profile), profile.size(), "\"" + kSource + "/profiles/lab-2x30.toml\"");
  write(dir / "sc" / "lab-quick.toml", scene);
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,385\n100,355\n");
  const auto r = run_millwear("calibrate " + quoted(dir / "sc" / "lab-quick.toml") + " --measured " +
                              quoted(dir / "areas.csv") + " -o " + quoted(dir / "cal") +
                              " --max-runs 1 --set lifters.profile=prof/lab-2x30.toml");
  EXPECT_NE(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output.find("expected an existing profile file"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "cal" / "lab-quick-calibrated.toml")) << r.output;
}

// A run of --replicates 2 holds two histories of the design; validate --from compares the
// first (the scene's seed), while the run's summary.csv gives their mean: it says which
// history it compared, on the screen and in its manifest.
TEST(HostileSurveys, ValidateFromAReplicatedRunSaysWhichHistoryItCompared) {
  const TempDir dir("millwear-hostile-from-replicates");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  const auto run = run_millwear("run " + scene + " -o " + quoted(dir / "run") + " --replicates 2 -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,385\n100,355\n");
  const auto r = run_millwear("validate " + scene + " --measured " + quoted(dir / "areas.csv") + " -o " +
                              quoted(dir / "out") + " --from " + quoted(dir / "run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the run holds 2 histories of lab-quick (--replicates); compared: the first, seed 1"),
            std::string::npos)
      << r.output;
  const std::string manifest = millwear::io::read_file((dir / "out" / "manifest.json").string());
  EXPECT_NE(manifest.find("1 of 2 (seed 1)"), std::string::npos) << manifest;
}

// A survey that lost more area than the lifter has is refused at its line before any history
// is run (the histories could never reach it: they would run to --max-runs and not converge).
TEST(HostileSurveys, CalibrateRefusesALossOfTheWholeLifter) {
  const TempDir dir("millwear-hostile-whole-lifter");
  write(dir / "losses.csv", "hours,area_loss_mm2\n50,100\n100,6000\n");
  const auto r = run_millwear("calibrate " + quoted(fs::path(kSource + "/tests/data/lab-quick.toml")) + " --measured " +
                              quoted(dir / "losses.csv") + " -o " + quoted(dir / "out"));
  expect_refused(r, (dir / "losses.csv").string(), "line 3", dir / "out");
  EXPECT_NE(r.output.find("smaller than the lifter's area"), std::string::npos) << r.output;
}

// ---- a folder where a file goes --------------------------------------------------------------

namespace {

// A folder (not empty) put where a command writes a file.
void folder_in_place_of(const fs::path& file) {
  fs::remove(file);
  fs::create_directories(file);
  write(file / "note.txt", "a user's folder\n");
}

}  // namespace

// A folder named summary.csv in a run's folder: the same run again is refused before anything
// is deleted or run (exit 2, naming the path and what was expected there), where it deleted
// the earlier results and ran, then failed to write its table (exit 1).
// More ParaView frames than the window has steps: a frame a step, each at its own time, where
// a thousand frames repeated 16 states (each time in the index a hundred times over).
TEST(HostileOutputs, FramesPastTheWindowsStepsAreOneAStep) {
  const TempDir dir("millwear-hostile-vtk-frames");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_mill_with("", ""));
  const auto r = run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "out") +
                              " --revolutions 0.01 -q --vtk --set outputs.vtk_frames=1000");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // A run's stage window likewise (a window of 0.02 revolutions).
  write(dir / "quick.toml", lab_quick());
  const auto history = run_millwear("run " + quoted(dir / "quick.toml") + " -o " + quoted(dir / "run") +
                                    " -q --vtk --set outputs.vtk_frames=1000 --set wear.window_revolutions=0.02");
  ASSERT_EQ(history.exit_code, 0) << history.output;
  for (const fs::path& index : {dir / "out" / "vtk" / "lab-mill.pvd", dir / "run" / "vtk" / "lab-quick_stage0.pvd"}) {
    const std::string pvd = read_text(index);
    std::vector<double> particle_times;
    for (std::size_t at = pvd.find("<DataSet"); at != std::string::npos; at = pvd.find("<DataSet", at + 1)) {
      const std::string tag = pvd.substr(at, pvd.find('>', at) - at);
      if (tag.find("part=\"0\"") == std::string::npos) continue;
      const auto t = tag.find("timestep=\"") + 10;
      particle_times.push_back(std::stod(tag.substr(t, tag.find('"', t) - t)));
    }
    ASSERT_GT(particle_times.size(), 1u) << index << pvd;
    EXPECT_LT(particle_times.size(), 1000u) << index;
    for (std::size_t k = 1; k < particle_times.size(); ++k)
      EXPECT_LT(particle_times[k - 1], particle_times[k]) << index << " frame " << k;
  }
}

TEST(HostileOutputs, ARunRefusesAFolderWhereItWritesAFile) {
  const TempDir dir("millwear-hostile-run-folder-file");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  const fs::path out = dir / "out";
  const auto first = run_millwear("run " + scene + " -o " + quoted(out) + " --quiet");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  folder_in_place_of(out / "summary.csv");
  const auto before = millwear::testing::files_under(out);
  ASSERT_EQ(before.count("profiles/lab-quick_stage2.csv"), 1u);
  for (const std::string extra : {" --check", ""}) {
    const auto r = run_millwear("run " + scene + " -o " + quoted(out) + " --quiet" + extra);
    EXPECT_EQ(r.exit_code, 2) << extra << "\n" << r.output;
    EXPECT_NE(r.output.find((out / "summary.csv").string() + ": -o: a file, which `millwear run` writes there, but a "
                            "folder of that name is there"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(millwear::testing::changed_files(before, millwear::testing::files_under(out)), "") << extra;
  }
}

// validate into its earlier folder where one of its tables is now a folder: refused before the
// history runs, the earlier results kept, where it deleted them, ran the history and failed.
TEST(HostileOutputs, ValidateRefusesAFolderWhereItWritesAFile) {
  const TempDir dir("millwear-hostile-validate-folder-file");
  const std::string scene = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,385\n100,355\n");
  const fs::path out = dir / "out";
  const std::string args = "validate " + scene + " --measured " + quoted(dir / "areas.csv") + " -o " + quoted(out);
  const auto first = run_millwear(args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  folder_in_place_of(out / "simulated_areas.csv");
  const auto before = millwear::testing::files_under(out);
  const auto r = run_millwear(args);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((out / "simulated_areas.csv").string() + ": -o: a file, which `millwear validate` writes"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("stage 1"), std::string::npos) << "the history ran:\n" << r.output;
  EXPECT_EQ(millwear::testing::changed_files(before, millwear::testing::files_under(out)), "");
}

// calibrate without -o writes its copy beside the scene: a folder of that name is refused
// before any history, where the histories ran and the copy then failed (exit 1).
TEST(HostileOutputs, CalibrateRefusesAFolderWhereTheCalibratedCopyGoes) {
  const TempDir dir("millwear-hostile-calibrate-folder-file");
  write(dir / "quick.toml", lab_quick());
  write(dir / "areas.csv", "hours,area_mm2\n0,419\n50,385\n100,355\n");
  folder_in_place_of(dir / "quick-calibrated.toml");
  const auto r = run_millwear("calibrate " + quoted(dir / "quick.toml") + " --measured " + quoted(dir / "areas.csv") +
                              " --max-runs 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((dir / "quick-calibrated.toml").string() + ": -o: a file, which `millwear calibrate` writes"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("run 1:"), std::string::npos) << "a history ran:\n" << r.output;
}

// A sweep whose point folder is a file: refused before any point runs, naming that path.
TEST(HostileOutputs, ASweepRefusesAFileWhereAPointsFolderGoes) {
  const TempDir dir("millwear-hostile-sweep-file-folder");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  const fs::path out = dir / "out";
  const std::string args = "sweep " + lab + " -o " + quoted(out) + " --vary mill.speed=0.7,0.8 --revolutions 1 " +
                           "--fidelity draft -j 1 --no-plot -q";
  const auto first = run_millwear(args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  fs::remove_all(out / "points" / "01");
  write(out / "points" / "01", "a user's file\n");
  const auto before = millwear::testing::files_under(out);
  const auto r = run_millwear(args);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((out / "points" / "01").string() + ": -o: a folder, where `millwear sweep` writes"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(millwear::testing::changed_files(before, millwear::testing::files_under(out)), "");
}

// ---- a full disk -----------------------------------------------------------------------------

// A disk that fills while the figures are drawn: the run fails (exit 1) and says the file
// system is full, where it said only "pclose returned error". A 700 kB file system holds the
// results of the lab run (430 kB) but not all of its figures (1.2 MB). Mounting one needs
// root (CI runs as root); elsewhere the test cannot arrange a full disk and says so.
TEST(HostileDisk, AFullDiskWhileDrawingFiguresIsNamed) {
  const TempDir dir("millwear-hostile-full");
  const std::string mnt = (dir / "fs").string();
  fs::create_directories(mnt);
  if (millwear::testing::run_shell("mount -t tmpfs -o size=700k tmpfs " + quoted(fs::path(mnt))).exit_code != 0)
    GTEST_SKIP() << "cannot mount a small file system here (not root)";
  const auto r = run_millwear("run " + quoted(fs::path(kSource + "/tests/data/lab-quick.toml")) + " -o " +
                              quoted(fs::path(mnt) / "out") + " --quiet");
  millwear::testing::run_shell("umount " + quoted(fs::path(mnt)));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const bool named = r.output.find("is full") != std::string::npos ||
                     r.output.find("No space left on device") != std::string::npos;
  EXPECT_TRUE(named) << r.output;
  EXPECT_EQ(r.output.find("pclose returned error"), std::string::npos) << r.output;
}

// ---- measured profiles -----------------------------------------------------------------------

// A scan of a fin 0.2 mm wide is all but gone once re-smoothed: refused by the commands that
// wear and those that only turn the charge, naming the file and its columns.
TEST(HostileMeasured, AScanThinnerThanTheParticlesIsRefusedByEveryCommand) {
  const TempDir dir("millwear-hostile-measured-fin");
  write(dir / "fin.csv", "x_mm,y_mm\n-20,-1\n-0.1,0\n0,20\n0.1,0\n20,-1\n");
  const fs::path scene = lab_mill_with_profile(dir, "fin.csv");
  for (const char* cmd : {"charge", "run"}) {
    const auto r = run_millwear(std::string(cmd) + " " + quoted(scene) + " -o " + quoted(dir / "out"));
    expect_refused(r, (dir / "fin.csv").string(), "x_mm,y_mm", dir / "out");
    EXPECT_NE(r.output.find("thinner than the particles"), std::string::npos) << r.output;
  }
}

// Gauge noise makes loops of a fraction of a square millimetre, which are cut out; points out
// of order that cross over a real part of the lifter are refused, not reshaped.
TEST(HostileMeasured, ASurfaceCrossingOverItsLifterIsRefusedNotReshaped) {
  const TempDir dir("millwear-hostile-measured-crossing");
  const fs::path crossing = dir / "crossing.csv";
  write(crossing, "x_mm,y_mm\n-20,-1\n-16.55,0\n5,20\n-5,20\n16.55,0\n20,-1\n");
  const auto r = run_millwear("profile " + quoted(crossing));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("crossing.csv"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("x_mm,y_mm"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("crosses itself"), std::string::npos) << r.output;
  // The same lifter with a small noise loop on its leading face (a point stepping back over
  // the edge before it) reads, the loop cut out.
  const fs::path noisy = dir / "noisy.csv";
  write(noisy, "x_mm,y_mm\n-20,-1\n-16.55,0\n-5,20\n5,20\n10.8,10\n10.2,10.6\n10.9,10.9\n11.5,9\n16.55,0\n20,-1\n");
  const auto ok = run_millwear("profile " + quoted(noisy));
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("(1 repeated or looping dropped)"), std::string::npos) << ok.output;
  // Its extent is the points' leftmost and rightmost x, not the first and last point's.
  const fs::path back = dir / "back.csv";
  write(back, "x_mm,y_mm\n-20,-1\n-16.55,0\n-5,20\n5,20\n16.55,0\n20,-1\n19.9,-1\n");
  const auto extent = run_millwear("profile " + quoted(back));
  EXPECT_EQ(extent.exit_code, 0) << extent.output;
  EXPECT_NE(extent.output.find("x from -20.0 to 20.0 mm"), std::string::npos) << extent.output;
}

TEST(HostileMeasured, HexadecimalCellsAreRefused) {
  const TempDir dir("millwear-hostile-measured-hex");
  const fs::path hex = dir / "hex.csv";
  write(hex, "x_mm,y_mm\n-20,0\n-5,0x14\n5,20\n20,0\n");
  const auto r = run_millwear("profile " + quoted(hex));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("line 3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("0x14"), std::string::npos) << r.output;
}

// ---- the command line ------------------------------------------------------------------------

// "nan" passes every comparison: each number option refuses it (and inf) by name, before any
// work, where CLI11's own range check let it through.
TEST(HostileOptions, NotANumberIsRefusedByEveryNumberOption) {
  const TempDir dir("millwear-hostile-options-nan");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  const std::string out = quoted(dir / "out");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"charge " + lab + " -o " + out + " --revolutions nan", "--revolutions"},
      {"sweep " + lab + " -o " + out + " --vary mill.speed=0.7,0.8 --revolutions nan", "--revolutions"},
      {"tradeoff " + lab + " -o " + out + " --stage-hours nan", "--stage-hours"},
      {"rule1 " + lab + " --tolerance nan", "--tolerance"},
      {"rule1 " + lab + " --factors 1e5 nan", "--factors"},
      {"animate " + lab + " -o " + quoted(dir / "a.gif") + " --seconds nan", "--seconds"},
      {"hardness " + quoted(fs::path(kSource + "/validation/hardness-synthetic.csv")) + " -o " + out +
           " --reference-hardness nan",
       "--reference-hardness"},
      {"calibrate " + quoted(fs::path(kSource + "/validation/lab-mill-guess.toml")) + " --measured " +
           quoted(fs::path(kSource + "/validation/lab-mill-areas.csv")) + " -o " + out + " --tolerance inf",
       "--tolerance"},
      {"run " + lab + " -o " + out + " --progress-every -nan", "--progress-every"},
  };
  for (const auto& [args, option] : cases) {
    const auto r = run_millwear(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(option), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << args;
    EXPECT_FALSE(fs::exists(dir / "a.gif")) << args;
  }
}

// Every count of the command line is plain decimal digits: CLI11's integer conversion alone
// would read "0x2" (hexadecimal), "0b10" (binary) and " 2" (a blank before it) as 2. Each is
// refused naming the option (exit 2, nothing written): --threads of run and charge, --jobs of
// run, sweep and rule1, screen's --replicates; "2" is taken.
TEST(HostileOptions, ACountIsPlainDecimalDigits) {
  const TempDir dir("millwear-hostile-counts");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  const std::string screen = quoted(fs::path(kSource + "/scenarios/screen-sag-face-angle.toml"));
  const std::string out = quoted(dir / "out");
  const std::vector<std::string> threads = {"0x2", "0b10", " 2", "2 ", "+2", "2.0", "0", "257"};
  const std::vector<std::string> others = {"0x2", " 2", "+2", "0"};
  struct Case {
    std::string command, option;
    const std::vector<std::string>* counts;
  };
  const std::vector<Case> cases = {
      {"run " + lab + " -o " + out + " --check", "--threads", &threads},
      {"charge " + lab + " -o " + out, "--threads", &threads},
      {"run " + lab + " -o " + out + " --check", "--jobs", &others},
      {"sweep " + lab + " -o " + out + " --vary mill.speed=0.7,0.8", "--jobs", &others},
      {"rule1 " + lab + " -o " + out, "--jobs", &others},
      {"screen " + screen + " -o " + out + " --emit parallel", "--replicates", &others}};
  for (const Case& c : cases) {
    for (const std::string& count : *c.counts) {
      const std::string args = c.command + " " + c.option + " '" + count + "'";
      const auto r = run_millwear(args);
      EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
      EXPECT_NE(r.output.find(c.option), std::string::npos) << args << "\n" << r.output;
      EXPECT_NE(r.output.find("plain decimal digits, got '" + count + "'"), std::string::npos) << args << "\n"
                                                                                                << r.output;
      EXPECT_FALSE(fs::exists(dir / "out")) << args;
    }
  }
  for (const std::string option : {"--threads", "--jobs"}) {
    const auto ok = run_millwear("run " + lab + " -o " + out + " --check " + option + " 2");
    EXPECT_EQ(ok.exit_code, 0) << option << "\n" << ok.output;
  }
}

// `--stop-after-stage K` names a stage a design runs before its last: past the last it
// would stop nothing and exit as interrupted never, and at a stage `--continue` copies it
// would stop before running anything. Both are refused before the run (exit 2).
TEST(HostileOptions, AStopAfterAStageNoDesignRunsIsRefused) {
  const TempDir dir("millwear-hostile-stop-stage");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));  // stages 0 to 2
  const std::string out = quoted(dir / "out");
  for (const std::string k : {"2", "7"}) {
    const auto r = run_millwear("run " + lab + " -o " + out + " --check --stop-after-stage " + k);
    EXPECT_EQ(r.exit_code, 2) << k << "\n" << r.output;
    EXPECT_NE(r.output.find("--stop-after-stage: a stage from 0 to 1 that a design runs before its last, got " + k),
              std::string::npos)
        << r.output;
  }
  EXPECT_EQ(run_millwear("run " + lab + " -o " + out + " --check --stop-after-stage 1").exit_code, 0);

  const std::string first = quoted(dir / "first");
  const auto made = run_millwear("run " + lab + " -o " + first + " --fidelity draft -q --set wear.stages=1");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const std::string go_on = "run " + lab + " -o " + out + " --continue " + first +
                            " --stage 1 --set wear.stages=3 --fidelity draft -q --check --stop-after-stage ";
  const auto copied = run_millwear(go_on + "1");
  EXPECT_EQ(copied.exit_code, 2) << copied.output;
  EXPECT_NE(copied.output.find("a stage from 2 to 2 that a design runs before its last, got 1"), std::string::npos)
      << copied.output;
  EXPECT_EQ(run_millwear(go_on + "2").exit_code, 0);
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// Lifters so tall that the charge has no room inside their tips: every command refuses the
// scene up front (exit 2, naming charge.filling and the largest filling that fits), before
// any design's thread would meet it in the fill. A filling under that bound runs.
TEST(HostileScenes, AChargeWithNoRoomInsideTheLifterTipsIsRefusedByEveryCommand) {
  const TempDir dir("millwear-hostile-no-room");
  write(dir / "tall.toml",
        "name = \"tall\"\nform = \"trapezoid\"\nheight = 145.0\ntop_width = 30.0\n"
        "leading_face_angle = 0.0\ntrailing_face_angle = 0.0\n");
  std::string s = lab_quick();
  const std::string prof = "\"" + kSource + "/profiles/lab-2x30.toml\"";
  s.replace(s.find(prof), prof.size(), quoted(dir / "tall.toml"));
  s.replace(s.find("rows = 12"), 9, "rows = 8");
  const fs::path scene = dir / "scene.toml";
  write(scene, s);
  const std::string sc = quoted(scene);
  for (const std::string& cmd : {"run " + sc + " --check -o ", "run " + sc + " -q -o ", "charge " + sc + " -o ",
                                "rule1 " + sc + " --factors 1e5 2e5 -o ", "tradeoff " + sc + " --quick -o "}) {
    const auto r = run_millwear(cmd + quoted(dir / "out"));
    expect_refused(r, scene.string(), "charge.filling", dir / "out");
    EXPECT_NE(r.output.find("a filling of at most 0.19"), std::string::npos) << r.output;
  }
  std::string fits = s;
  fits.replace(fits.find("filling = 0.3"), 13, "filling = 0.18");
  fits.replace(fits.find("ball_filling = 0.3"), 18, "ball_filling = 0.18");
  write(scene, fits);
  const auto r = run_millwear("charge " + sc + " --revolutions 0.2 -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// Contacts of 1 Hz cannot hold the charge: disks sink out of the mill from the settling on,
// before the measured window as well as in it. charge fails (exit 1), and its summary and
// printout count every disk lost since the fill, apart from those lost in the window.
TEST(HostileScenes, DisksLostBeforeTheWindowAreCountedInTheChargeSummary) {
  const TempDir dir("millwear-hostile-lost-early");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const auto r = run_millwear("charge " + quoted(scene) + " --set solver.contact_hertz=1 -o " + quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("disks were lost"), std::string::npos) << r.output;
  const millwear::io::CsvData sum = millwear::io::read_csv((dir / "out" / "charge_summary.csv").string());
  double lost = -1, escaped = -1;
  for (std::size_t i = 0; i < sum.row_count(); ++i) {
    const std::string q = sum.text(i, sum.column("quantity"));
    if (q == "lost_disks") lost = sum.number(i, sum.column("value"));
    if (q == "escaped_disks") escaped = sum.number(i, sum.column("value"));
  }
  EXPECT_GT(lost, escaped) << "no disk was lost before the window: the case is not tested";
  EXPECT_NE(r.output.find("lost disks " + std::to_string(static_cast<int>(lost)) + " since the fill"), std::string::npos)
      << r.output;
}

// A charge of balls alone has no Austin estimate (a SAG model), and a mill at critical speed
// no Morrell estimate either: their rows are left out of charge_summary.csv, which holds no
// non-finite figure.
TEST(HostileScenes, APowerModelWithoutAnEstimateLeavesNoRowInTheChargeSummary) {
  const TempDir dir("millwear-hostile-power-models");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  for (const char* speed : {"0.75", "1.0"}) {
    const fs::path out = dir / (std::string("out-") + speed);
    const auto r = run_millwear("charge " + quoted(scene) + " --revolutions 0.2 --set mill.speed=" + speed + " -o " +
                                quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const millwear::io::CsvData sum = millwear::io::read_csv((out / "charge_summary.csv").string());
    bool morrell = false, austin = false;
    for (std::size_t i = 0; i < sum.row_count(); ++i) {
      const std::string q = sum.text(i, sum.column("quantity"));
      morrell |= q == "morrell_power_per_m";
      austin |= q == "austin_power_per_m";
      const std::string v = sum.text(i, sum.column("value"));
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (end != v.c_str() && *end == '\0') {
        EXPECT_TRUE(std::isfinite(x)) << speed << ": " << q << " = " << v;
      }
    }
    EXPECT_EQ(morrell, std::string(speed) == "0.75") << speed;
    EXPECT_FALSE(austin) << speed;
    EXPECT_NE(r.output.find("Austin       none"), std::string::npos) << r.output;
    if (std::string(speed) == "1.0") {
      EXPECT_NE(r.output.find("Morrell      none at or above critical speed"), std::string::npos) << r.output;
    }
  }
  // Far below working speeds the C-model has no estimate either, and says why: not "at or
  // above critical speed".
  const auto slow = run_millwear("charge " + quoted(scene) + " --revolutions 0.01 --set mill.speed=0.03" +
                                 " --set solver.spinup_revolutions=0.01 -o " + quoted(dir / "out-slow"));
  ASSERT_EQ(slow.exit_code, 0) << slow.output;
  EXPECT_NE(slow.output.find("Morrell      none at 3% of critical speed"), std::string::npos) << slow.output;
}

// A wear rate that wears the lifter to the shell within the first stage: the history ends
// with the worn-out geometry, whose charge figures were never measured. summary.csv leaves
// them unknown (nan, as their errors): no stage's figures stand in for them.
TEST(HostileScenes, TheWornOutStageReportsNoChargeFigures) {
  const TempDir dir("millwear-hostile-worn-out");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const auto r = run_millwear("run " + quoted(scene) + " -q --set wear.wear_rate=1e-6 -o " + quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("worn to the shell"), std::string::npos) << r.output;
  const millwear::io::CsvData sum = millwear::io::read_csv((dir / "out" / "summary.csv").string());
  ASSERT_GE(sum.row_count(), 2u);
  const std::size_t last = sum.row_count() - 1;
  EXPECT_TRUE(std::isfinite(sum.number(0, "power_kw")));
  EXPECT_TRUE(std::isfinite(sum.number(last, "area_mm2")));
  EXPECT_LT(sum.number(last, "height_mm"), 0.1 * sum.number(0, "height_mm"));
  for (const char* c : {"power_kw", "collision_kw", "utilization", "liner_shear_kw", "toe_deg", "liner_wear_g_per_kwh"})
    EXPECT_TRUE(std::isnan(sum.number(last, c))) << c << " = " << sum.number(last, c);
}

// A window that lost disks ends its history, and its stage is kept for a look at what
// happened; but its charge is not the scene's: summary.csv and the comparison gave its power
// and collision energy as the design's, and one verdict called a difference resolved. Its
// charge figures are unknown now, as a worn-out stage's are, its liner's geometry stands, and
// a `charge` that lost disks says in its manifest that it failed.
TEST(HostileScenes, AWindowThatLostDisksGivesNoChargeFiguresToCompare) {
  const TempDir dir("millwear-hostile-lost-window");
  write(dir / "good.toml", lab_quick());
  std::string bad = lab_quick();
  bad.replace(bad.find("name = \"lab-quick\""), 18, "name = \"bad\"");
  bad.replace(bad.find("[solver]"), 8, "[solver]\ncontact_hertz = 5.0");
  write(dir / "bad.toml", bad);
  const auto r = run_millwear("run " + quoted(dir / "good.toml") + " " + quoted(dir / "bad.toml") +
                              " -q -j 1 --set mill.speed=1.2 -o " + quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 1) << r.output;
  ASSERT_NE(r.output.find("bad: stage 0: disk"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("resolved:"), std::string::npos) << r.output;
  const millwear::io::CsvData sum = millwear::io::read_csv((dir / "out" / "summary.csv").string());
  bool seen = false;
  for (std::size_t i = 0; i < sum.row_count(); ++i) {
    if (sum.text(i, sum.column("design")) != "bad") continue;
    seen = true;
    EXPECT_TRUE(std::isfinite(sum.number(i, "area_mm2")));
    for (const char* c : {"power_kw", "collision_kw", "utilization", "liner_shear_kw", "charge_t", "liner_wear_g_per_kwh"})
      EXPECT_TRUE(std::isnan(sum.number(i, c))) << c << " = " << sum.number(i, c);
  }
  EXPECT_TRUE(seen) << read_text(dir / "out" / "summary.csv");
  EXPECT_NE(read_text(dir / "out" / "summary.md").find("power_kw at stage 0: bad against lab-quick: not compared"),
            std::string::npos);
  const auto c = run_millwear("charge " + quoted(dir / "bad.toml") + " -q --revolutions 1 --set mill.speed=1.2 -o " +
                              quoted(dir / "charge"));
  ASSERT_EQ(c.exit_code, 1) << c.output;
  const std::string manifest = read_text(dir / "charge" / "manifest.json");
  EXPECT_NE(manifest.find("\"status\": \"failed\""), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("disks were lost"), std::string::npos) << manifest;
}

// contacts.csv keeps at most 200,000 records, the window's first: six revolutions of the lab
// mill log more, and the file stopped at three quarters of the window without a word. The
// summary says how far it reaches, and charge warns.
TEST(HostileScenes, AContactLogCutAtItsLimitSaysWhereItStops) {
  const TempDir dir("millwear-hostile-contact-log");
  write(dir / "scene.toml", lab_quick());
  const auto r = run_millwear("charge " + quoted(dir / "scene.toml") + " -q --revolutions 6 --set outputs.contact_log=true -o " +
                              quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: contacts.csv holds the window's first 200000 liner contacts"), std::string::npos)
      << r.output;
  const millwear::io::CsvData sum = millwear::io::read_csv((dir / "out" / "charge_summary.csv").string());
  double until = std::nan(""), window = std::nan("");
  for (std::size_t i = 0; i < sum.row_count(); ++i) {
    if (sum.text(i, 0) == "contact_log_until") until = sum.number(i, "value");
    if (sum.text(i, 0) == "simulated_time") window = sum.number(i, "value");
  }
  ASSERT_TRUE(std::isfinite(until) && std::isfinite(window));
  EXPECT_LT(until, 0.9 * window);
  EXPECT_EQ(millwear::io::read_csv((dir / "out" / "contacts.csv").string()).row_count(), 200000u);
  // A window the log holds whole: no warning, and the log reaches its end.
  const auto whole = run_millwear("charge " + quoted(dir / "scene.toml") + " -q --revolutions 1 --set outputs.contact_log=true -o " +
                                  quoted(dir / "one"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_EQ(whole.output.find("contacts.csv holds"), std::string::npos) << whole.output;
  const std::string one = read_text(dir / "one" / "charge_summary.csv");
  EXPECT_NE(one.find("contact_log_until,"), std::string::npos) << one;
}

// rule 1 and the tradeoff measure one lifter's worn profile: on a hi-lo pattern they judged
// the high kind alone (rule1 recommended a factor from it; tradeoff's profile error was the high
// kind's and its life the low kind's). Refused before any history, naming the pattern.
TEST(HostileScenes, RuleOneAndTheTradeoffRefuseAPatternOfShapes) {
  const TempDir dir("millwear-hostile-pattern-rule1");
  const std::string scene = quoted(fs::path(kSource + "/scenarios/lab-hi-lo.toml"));
  for (const std::string& cmd : {"rule1 " + scene + " --factors 5e4 1e5", "tradeoff " + scene + " --quick --stages 1"}) {
    const auto r = run_millwear(cmd + " -o " + quoted(dir / "out"));
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.output;
    EXPECT_NE(r.output.find("lab-hi-lo.toml: lifters.pattern: one lifter shape"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << cmd;
  }
}

// Figure scripts that are not there: the results stand, the command exits 1 (0 on a machine
// without gnuplot, where figures are not expected), and the warning lists each figure that
// failed once, under one heading.
TEST(HostileScenes, ChargeFiguresThatFailAreListedOnce) {
  const TempDir dir("millwear-hostile-no-scripts");
  fs::create_directories(dir / "scripts");
  const auto r = millwear::testing::run_shell("MILLWEAR_PLOTS_DIR=" + quoted(dir / "scripts") + " \"" + MILLWEAR_BINARY +
                                              "\" charge " + quoted(fs::path(kSource + "/scenarios/lab-mill.toml")) +
                                              " --revolutions 0.3 -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, millwear::plots::gnuplot_available() ? 1 : 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "charge_summary.csv"));
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (auto at = r.output.find(what); at != std::string::npos; at = r.output.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("some figures failed"), 1u) << r.output;
  for (const char* fig : {"spectrum:", "snapshot_lab-mill:", "impacts_lab-mill:"}) EXPECT_EQ(count(fig), 1u) << fig << r.output;
}

// hardness again into its folder with figure scripts that fail: the new tables are written
// and the command exits 1, and the earlier data's figure is not left beside them.
TEST(HostileScenes, HardnessWhoseFigureFailsLeavesNoEarlierFigure) {
  if (!millwear::plots::gnuplot_available()) GTEST_SKIP() << "no gnuplot: no figure is drawn at all";
  const TempDir dir("millwear-hostile-hardness-figure");
  const std::string data = quoted(fs::path(kSource + "/validation/hardness-synthetic.csv"));
  ASSERT_EQ(run_millwear("hardness " + data + " -o " + quoted(dir / "out")).exit_code, 0);
  ASSERT_TRUE(fs::exists(dir / "out" / "hardness.png"));
  fs::create_directories(dir / "scripts");
  const auto r = millwear::testing::run_shell("MILLWEAR_PLOTS_DIR=" + quoted(dir / "scripts") + " \"" + MILLWEAR_BINARY +
                                              "\" hardness " + data + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "hardness_fit.csv"));
  EXPECT_FALSE(fs::exists(dir / "out" / "hardness.png"));
  EXPECT_FALSE(fs::exists(dir / "out" / "hardness.svg"));
}

// The figures `charge` says it drew are the ones in OUT/plots: with the snapshot or the
// spectrum turned off in the scene their figures are not drawn, and not named.
TEST(HostileScenes, ChargeNamesOnlyTheFiguresItDrew) {
  const TempDir dir("millwear-hostile-charge-figures");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  for (const char* off : {"outputs.snapshot=false", "outputs.collision_spectrum=false"}) {
    const fs::path out = dir / off;
    const auto r = run_millwear("charge " + lab + " --revolutions 0.3 -q --set " + off + " -o " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto at = r.output.find("figures in ");
    if (!millwear::plots::gnuplot_available()) {
      EXPECT_EQ(at, std::string::npos) << r.output;
      continue;
    }
    ASSERT_NE(at, std::string::npos) << r.output;
    const auto open = r.output.find('(', at), close = r.output.find(')', at);
    ASSERT_LT(open, close) << r.output;
    const std::string list = r.output.substr(open + 1, close - open - 1) + ",";
    int named = 0;
    for (std::size_t from = 0, comma; (comma = list.find(',', from)) != std::string::npos; from = comma + 2, ++named) {
      const std::string fig = list.substr(from, comma - from);
      EXPECT_TRUE(fs::exists(out / "plots" / (fig + ".png"))) << off << ": named " << fig << " but did not draw it\n"
                                                             << r.output;
    }
    EXPECT_GE(named, 1) << r.output;
  }
}

// The same for a sweep: the table stands and the command exits 1 (it exited 0 with a warning).
TEST(HostileScenes, SweepFiguresThatFailExitOneWithTheTableWritten) {
  const TempDir dir("millwear-hostile-sweep-no-scripts");
  fs::create_directories(dir / "scripts");
  const auto r = millwear::testing::run_shell("MILLWEAR_PLOTS_DIR=" + quoted(dir / "scripts") + " \"" + MILLWEAR_BINARY +
                                              "\" sweep " + quoted(fs::path(kSource + "/scenarios/lab-mill.toml")) +
                                              " --vary mill.speed=0.6,0.7 --revolutions 0.2 -j 1 -q -o " +
                                              quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, millwear::plots::gnuplot_available() ? 1 : 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "sweep.csv"));
  EXPECT_NE(r.output.find("figures"), std::string::npos) << r.output;
}

// A point whose charge the fill cannot place (disks of one size at a filling under the 60%
// limit, past what random placement reaches) is that point's error: the other points are
// kept, sweep.csv written, exit 1. It stopped the sweep part-way, exit 2, no table.
// The lab scene with balls and rocks of one size, 20 mm: at a filling of 0.59 (ball filling
// 0.1), under the 60% limit, past what random placement reaches.
std::string lab_of_one_size() {
  std::string s = lab_quick();
  const std::string range = "size_range = [15.0, 25.0]";
  s.replace(s.find(range), range.size(), "sizes = [20.0]");
  s += "\n[[charge.species]]\nname = \"rock\"\ndensity = 2700.0\nsizes = [20.0]\n";
  return s;
}

TEST(HostileScenes, ASweepPointTheFillCannotPlaceIsThatPointsError) {
  const TempDir dir("millwear-hostile-sweep-unplaceable");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_of_one_size());
  const auto r = run_millwear("sweep " + quoted(scene) + " --vary charge.filling=0.3,0.59 --set charge.ball_filling=0.1 " +
                              "--revolutions 0.2 -j 1 -q --no-plot -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("charge.filling = 0.59"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("random placement put"), std::string::npos) << r.output;
  const millwear::io::CsvData t = millwear::io::read_csv((dir / "out" / "sweep.csv").string());
  ASSERT_EQ(t.row_count(), 2u);
  EXPECT_EQ(t.text(0, t.column("error")), "");
  EXPECT_NE(t.text(1, t.column("error")).find("charge.filling"), std::string::npos);
}

// A run of two designs whose second one's charge the fill cannot place: refused as a wrong
// input naming that scene and charge.filling, before the first design runs and before
// anything is written, and by --check too. It ran the first design and failed the second
// (exit 1).
TEST(HostileScenes, ARunRefusesAFillingTheFillCannotPlaceBeforeAnyDesignRuns) {
  const TempDir dir("millwear-hostile-run-unplaceable");
  const fs::path good = dir / "good.toml", jam = dir / "jam.toml";
  write(good, lab_quick());
  std::string s = lab_of_one_size();
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"name = \"lab-quick\"", "name = \"jam\""},
                                 {"filling = 0.3", "filling = 0.59"}, {"ball_filling = 0.3", "ball_filling = 0.1"}})
    s.replace(s.find(from), from.size(), to);
  write(jam, s);
  const std::string designs = "run " + quoted(good) + " " + quoted(jam) + " -q -o " + quoted(dir / "out");
  expect_refused(run_millwear(designs + " --check"), jam.string(), "charge.filling", dir / "out");
  const auto r = run_millwear(designs);
  expect_refused(r, jam.string(), "charge.filling", dir / "out");
  EXPECT_NE(r.output.find("random placement put"), std::string::npos) << r.output;
}

// No friction between charge and liner: no shear work, no wear, so no life. The run's table
// says why the life column is empty.
TEST(HostileScenes, ALinerThatDoesNotWearSaysThereIsNoLife) {
  const TempDir dir("millwear-hostile-no-wear");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const auto r = run_millwear("run " + quoted(scene) + " --set \"charge.species[0].friction_liner=0\" -o " +
                              quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no life: the lifter's height does not fall over the last stages"), std::string::npos) << r.output;
  const millwear::io::CsvData sum = millwear::io::read_csv((dir / "out" / "summary.csv").string());
  EXPECT_FALSE(std::isfinite(sum.number(sum.row_count() - 1, "life_h")));
  const auto worn = run_millwear("run " + quoted(scene) + " -o " + quoted(dir / "worn"));
  ASSERT_EQ(worn.exit_code, 0) << worn.output;
  EXPECT_EQ(worn.output.find("no life"), std::string::npos) << worn.output;
}

// Twice the critical speed with one revolution of spin-up: the charge is still being flung to
// the shell in the window, and much of the drive's power goes into its energy, not into
// dissipation. charge says the window was not steady; at the scene's own speed it does not.
TEST(HostileScenes, AChargeStillSpinningUpIsSaidNotToBeSteady) {
  const TempDir dir("millwear-hostile-not-steady");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const auto fast = run_millwear("charge " + quoted(scene) + " --set mill.speed=2.0 -o " + quoted(dir / "fast"));
  ASSERT_EQ(fast.exit_code, 0) << fast.output;
  EXPECT_NE(fast.output.find("was not steady in the window"), std::string::npos) << fast.output;
  const auto steady = run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "steady"));
  ASSERT_EQ(steady.exit_code, 0) << steady.output;
  EXPECT_EQ(steady.output.find("not steady"), std::string::npos) << steady.output;
}

// A --set of a key one of the command's own options sets (--stages: wear.stages, --fidelity:
// fidelity, --revolutions: run.revolutions, --factors: wear.factor) was overridden by the option
// without a word, and the manifest still listed it. Refused before any work, naming the --set
// and the option; without the option the --set is taken.
TEST(HostileOptions, ASetOfAKeyAnOptionSetsIsRefused) {
  const TempDir dir("millwear-hostile-set-option");
  const std::string quick = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  const std::string out = " -o " + quoted(dir / "out");
  for (const auto& [command, says] : std::vector<std::pair<std::string, std::string>>{
           {"tradeoff " + quick + out + " --only draft --stages 1 --set wear.stages=3", "which --stages sets"},
           {"tradeoff " + quick + out + " --only draft --stage-hours 5 --set wear.stage_hours=7", "which --stage-hours sets"},
           {"sweep " + quick + out + " --vary mill.speed=0.6,0.7 --fidelity draft --set fidelity=reference",
            "which --fidelity sets"},
           {"sweep " + quick + out + " --vary mill.speed=0.6,0.7 --revolutions 0.3 --set run.revolutions=2",
            "which --revolutions sets"},
           {"charge " + quick + out + " --revolutions 0.3 --set run.revolutions=2", "which --revolutions sets"},
           {"run " + quick + out + " --fidelity draft --set fidelity=reference", "which --fidelity sets"},
           {"rule1 " + quick + out + " --factors 1e5 2e5 --set wear.factor=3e5", "which --factors sets"},
           {"rule1 " + quick + out + " --set wear.stages=2", "which --stages sets"}}) {
    const auto r = run_millwear(command);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << command << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << command;
  }
  const auto taken = run_millwear("charge " + quick + out + " --check --set run.revolutions=2");
  EXPECT_EQ(taken.exit_code, 0) << taken.output;
}

TEST(HostileOptions, OptionsThatContradictEachOtherAreRefused) {
  const TempDir dir("millwear-hostile-options-conflict");
  // --max-runs 1 alone is no contradiction: the default minimum (2) yields to it.
  const auto one = run_millwear("calibrate " + quoted(fs::path(kSource + "/validation/lab-mill-guess.toml")) +
                                " --measured " + quoted(fs::path(kSource + "/validation/lab-mill-areas.csv")) + " -o " +
                                quoted(dir / "one") + " --max-runs 1 --set wear.stages=1");
  EXPECT_NE(one.exit_code, 2) << one.output;
  EXPECT_EQ(one.output.find("--min-runs"), std::string::npos) << one.output;
  // One run cannot converge (exit 1): the scene it leaves says so in its calibration note.
  EXPECT_EQ(one.exit_code, 1) << one.output;
  EXPECT_NE(read_text(dir / "one" / "lab-mill-guess-calibrated.toml").find("NOT CONVERGED"), std::string::npos);
  const auto cal = run_millwear("calibrate " + quoted(fs::path(kSource + "/validation/lab-mill-guess.toml")) + " --measured " +
                                quoted(fs::path(kSource + "/validation/lab-mill-areas.csv")) + " -o " + quoted(dir / "out") +
                                " --min-runs 5 --max-runs 2");
  EXPECT_EQ(cal.exit_code, 2) << cal.output;
  EXPECT_NE(cal.output.find("--min-runs"), std::string::npos) << cal.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  const auto sc = run_millwear("screen " + quoted(fs::path(kSource + "/scenarios/screen-sag-face-angle.toml")) + " -o " +
                               quoted(dir / "out") + " --chunk 2");
  EXPECT_EQ(sc.exit_code, 2) << sc.output;
  EXPECT_NE(sc.output.find("--emit"), std::string::npos) << sc.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // --resume goes on, --force starts over: run obeyed --force and deleted the run.
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const auto rf = run_millwear("run " + quoted(scene) + " -q --resume --force -o " + quoted(dir / "out"));
  EXPECT_EQ(rf.exit_code, 2) << rf.output;
  EXPECT_NE(rf.output.find("--resume excludes --force"), std::string::npos) << rf.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // --collect of one folder, named twice as two: the positional one was ignored.
  fs::create_directories(dir / "a");
  fs::create_directories(dir / "b");
  const auto co = run_millwear("screen --collect " + quoted(dir / "a") + " -o " + quoted(dir / "b"));
  EXPECT_EQ(co.exit_code, 2) << co.output;
  EXPECT_NE(co.output.find("one output folder"), std::string::npos) << co.output;
  // One scene named twice is the same design twice, not two designs of one name.
  const auto twice = run_millwear("run " + quoted(scene) + " " + quoted(dir / "." / "scene.toml") + " --check -o " +
                                  quoted(dir / "out"));
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  EXPECT_NE(twice.output.find("each scene once"), std::string::npos) << twice.output;
}

// A charge's own earlier folder is its to rewrite, but a user's file put there under a name a
// charge of another scene writes (its snapshot, a figure) is refused naming it (exit 2, by
// --check too), not overwritten; the user's other files stay beside the charges that do run.
TEST(HostileOptions, AChargeRefusesAUsersFileInItsFolderUnderAnOutputsName) {
  const TempDir dir("millwear-hostile-options-charge-user");
  const fs::path out = dir / "out", other = dir / "other.toml";
  std::string s = lab_mill_with("name = \"lab-mill\"", "name = \"other\"");
  write(other, s);
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  const auto first = run_millwear("charge " + lab + " --revolutions 0.3 -q -o " + quoted(out));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  write(out / "notes.txt", "mine\n");
  for (const char* mine : {"snapshot_other.csv", "plots/impacts_other.png"}) {
    write(out / mine, "the user's own\n");
    for (const char* check : {" --check", ""}) {
      const auto r = run_millwear("charge " + quoted(other) + " --revolutions 0.3 -q -o " + quoted(out) + check);
      EXPECT_EQ(r.exit_code, 2) << mine << check << "\n" << r.output;
      EXPECT_NE(r.output.find(mine), std::string::npos) << r.output;
      EXPECT_EQ(read_text(out / mine), "the user's own\n") << mine << check;
      EXPECT_TRUE(fs::exists(out / "snapshot_lab-mill.csv")) << "the refusal deleted the earlier charge";
    }
    fs::remove(out / mine);
  }
  const auto again = run_millwear("charge " + quoted(other) + " --revolutions 0.3 -q -o " + quoted(out));
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(read_text(out / "notes.txt"), "mine\n");
}

// `screen --collect` ranks what is in the folder: an option of a screen that runs or emits
// designs (--emit, --replicates, --resume, --force, --jobs) is refused naming it (exit 2), not
// ignored as though it had been applied, and the folder is left as it was.
TEST(HostileOptions, CollectRefusesTheOptionsOfAScreenThatRuns) {
  const TempDir dir("millwear-hostile-options-collect");
  const fs::path out = dir / "screen";
  const auto emitted = run_millwear("screen " + quoted(fs::path(kSource + "/tests/data/screen-lab.toml")) + " -o " +
                                    quoted(out) + " --emit parallel");
  ASSERT_EQ(emitted.exit_code, 0) << emitted.output;
  for (const char* option : {"--emit", "--replicates", "--resume", "--force", "--jobs"}) {
    const std::string value = option == std::string("--emit") ? " slurm" : option == std::string("--replicates") ||
                                                                            option == std::string("--jobs") ? " 3" : "";
    const auto r = run_millwear("screen --collect " + quoted(out) + " " + option + value);
    EXPECT_EQ(r.exit_code, 2) << option << "\n" << r.output;
    EXPECT_NE(r.output.find(option), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out / "ranking.csv")) << option << ": collected";
    EXPECT_FALSE(fs::exists(out / "screen.sbatch")) << option << ": emitted";
  }
}

// An input that lies in the output folder under a name the command writes or deletes would be
// gone before it is read: run --force deleted a lifter given as an earlier stage's profile
// and then failed on it, charge wrote its impacts table over a scan named impacts.csv, and
// animate its GIF over a profile named x.gif (both exit 0). Refused before any work, the
// input kept; an input elsewhere in the folder runs.
TEST(HostileOptions, AnInputAmongTheFilesACommandWritesIsRefusedAndKept) {
  const TempDir dir("millwear-hostile-input-output");
  const std::string quick = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  const std::string sets = " -q --set wear.stages=1 --set wear.stage_hours=10";
  const fs::path out = dir / "run";
  ASSERT_EQ(run_millwear("run " + quick + " -o " + quoted(out) + sets).exit_code, 0);
  const fs::path stage1 = out / "profiles" / "lab-quick_stage1.csv";
  const std::string scan = read_text(stage1);
  const auto expect_input_refused = [](const millwear::testing::CliResult& r, const fs::path& input,
                                       const std::string& text) {
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(input.string() + ": -o: an input outside the files"), std::string::npos) << r.output;
    EXPECT_EQ(read_text(input), text) << input;
  };
  expect_input_refused(run_millwear("run " + quick + " -o " + quoted(out) + sets + " --force --set lifters.profile=" +
                                    quoted(stage1)),
                       stage1, scan);
  // The same scan beside the results or among the stage profiles, under a name the run neither
  // writes nor deletes, runs.
  for (const fs::path& kept : {out / "scan.csv", out / "profiles" / "myscan.csv"}) {
    write(kept, scan);
    const auto beside = run_millwear("run " + quick + " -o " + quoted(out) + sets + " --force --set lifters.profile=" +
                                     quoted(kept));
    EXPECT_EQ(beside.exit_code, 0) << beside.output;
    EXPECT_EQ(read_text(kept), scan);
  }

  // An earlier charge's folder, which a charge rewrites.
  ASSERT_EQ(run_millwear("charge " + quick + " -o " + quoted(dir / "charge") + " -q --revolutions 0.05").exit_code, 0);
  write(dir / "charge" / "impacts.csv", scan);
  expect_input_refused(run_millwear("charge " + quick + " -o " + quoted(dir / "charge") +
                                    " -q --revolutions 0.05 --set lifters.profile=" + quoted(dir / "charge" / "impacts.csv")),
                       dir / "charge" / "impacts.csv", scan);
  // A TOML profile under a name ending in .gif.
  const std::string toml_profile = read_text(kSource + "/profiles/lab-2x30.toml");
  write(dir / "scan.gif", toml_profile);
  expect_input_refused(run_millwear("animate " + quick + " -o " + quoted(dir / "scan.gif") +
                                    " --seconds 0.1 --set lifters.profile=" + quoted(dir / "scan.gif")),
                       dir / "scan.gif", toml_profile);
}

// An output folder that cannot be made is bad input (exit 2) found before any work, and a
// command refused after its folder was made does not leave it behind empty.
TEST(HostileOptions, AnOutputFolderThatCannotBeMadeIsRefusedAndNoEmptyFolderIsLeft) {
  const TempDir dir("millwear-hostile-options-folder");
  write(dir / "afile", "x");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  for (const char* cmd : {"run", "charge"}) {
    const auto r = run_millwear(std::string(cmd) + " " + lab + " -o " + quoted(dir / "afile" / "sub"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("afile"), std::string::npos) << r.output;
  }
  // An output file (animate's GIF) is written after the simulation: its path is checked first.
  fs::create_directories(dir / "folder.gif");
  for (const fs::path& gif : {dir / "afile" / "a.gif", dir / "folder.gif"}) {
    const auto r = run_millwear("animate " + lab + " -o " + quoted(gif));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
  }
  // The message blames the file on the way, not the GIF.
  const auto in_file = run_millwear("animate " + lab + " -o " + quoted(dir / "afile" / "a.gif"));
  EXPECT_NE(in_file.output.find((dir / "afile").string() + " is a file"), std::string::npos) << in_file.output;
  EXPECT_EQ(in_file.output.find("a file of that name exists"), std::string::npos) << in_file.output;
  // A folder that takes no files whoever asks (a virtual file system; access() passes root
  // there) is refused by trying it, not blamed on a full disk after the simulation.
  for (const std::string& cmd : {"animate " + lab + " -o /proc/millwear-test.gif", "charge " + lab + " -o /proc/millwear-test"}) {
    const auto r = run_millwear(cmd);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    const bool said = r.output.find("no file can be made in /proc") != std::string::npos ||
                      r.output.find("/proc is not writable") != std::string::npos;  // not root
    EXPECT_TRUE(said) << r.output;
    EXPECT_EQ(r.output.find("is full"), std::string::npos) << r.output;
  }
  // validate finds that --from holds no run only once it holds its output folder, which must
  // not outlive the refusal.
  const fs::path surveys = dir / "areas.csv";
  write(surveys, "hours,area_mm2\n0,414.6\n100,400\n");
  fs::create_directories(dir / "no-run");
  const auto v = run_millwear("validate " + lab + " --measured " + quoted(surveys) + " -o " +
                              quoted(dir / "new" / "out") + " --from " + quoted(dir / "no-run"));
  EXPECT_EQ(v.exit_code, 2) << v.output;
  EXPECT_NE(v.output.find("no-run"), std::string::npos) << v.output;
  EXPECT_FALSE(fs::exists(dir / "new" / "out")) << v.output;
}

// --force takes over another run's folder by deleting that run's files only: a user's own
// file there under a name the new design writes (its liner, a stage's profile) was not that
// run's, and is refused naming it (exit 2, the folder left as it was), not overwritten.
TEST(HostileOptions, ForceRefusesAUsersFileUnderANameTheNewDesignWrites) {
  const TempDir dir("millwear-hostile-options-force-user");
  const fs::path first = dir / "first.toml", second = dir / "second.toml", out = dir / "out";
  write(first, lab_quick());
  std::string t = lab_quick();
  const std::string name = "name = \"lab-quick\"";
  t.replace(t.find(name), name.size(), "name = \"lab-other\"");
  write(second, t);
  const auto r0 = run_millwear("run " + quoted(first) + " -o " + quoted(out) + " -q --stop-after-stage 0");
  ASSERT_EQ(r0.exit_code, 130) << r0.output;
  for (const char* mine : {"liner_lab-other.csv", "profiles/lab-other_stage0.csv"}) {
    write(out / mine, "the user's own\n");
    for (const char* check : {" --check", ""}) {
      const auto r = run_millwear("run " + quoted(second) + " -o " + quoted(out) + " -q --force" + check);
      EXPECT_EQ(r.exit_code, 2) << mine << check << "\n" << r.output;
      EXPECT_NE(r.output.find(mine), std::string::npos) << r.output;
      EXPECT_EQ(read_text(out / mine), "the user's own\n") << mine << check;
      EXPECT_TRUE(fs::exists(out / "stages" / "lab-quick_stage0.done")) << "the refusal deleted the earlier run";
    }
    fs::remove(out / mine);
  }
}

// A run that starts over in its own folder (the same inputs without --resume, or another
// run's folder with --force) deletes that run's stage files and profiles: a user's other
// files beside them, even under names that start like a stage's, stay.
TEST(HostileOptions, StartingOverLeavesAUsersOtherFilesBesideTheStages) {
  const TempDir dir("millwear-hostile-options-start-over");
  const fs::path first = dir / "first.toml", second = dir / "second.toml", out = dir / "out";
  write(first, lab_quick());
  std::string t = lab_quick();
  const std::string name = "name = \"lab-quick\"";
  t.replace(t.find(name), name.size(), "name = \"lab-other\"");
  write(second, t);
  const std::vector<std::string> mine = {"stages/lab-quick_stage0.notes.txt", "stages/lab-quick_stage7.csv",
                                         "profiles/lab-quick_stage0.marked.csv", "profiles/lab-quick_stage0.txt"};
  for (const char* extra : {"", " --force"}) {
    const fs::path scene = *extra ? second : first;
    const auto r0 = run_millwear("run " + quoted(first) + " -o " + quoted(out) + " -q --stop-after-stage 0");
    ASSERT_EQ(r0.exit_code, 130) << r0.output;
    for (const std::string& m : mine) write(out / m, "the user's own\n");
    const auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " -q --stop-after-stage 0" + extra);
    ASSERT_EQ(r.exit_code, 130) << extra << "\n" << r.output;
    for (const std::string& m : mine) {
      ASSERT_TRUE(fs::exists(out / m)) << m << extra;
      EXPECT_EQ(read_text(out / m), "the user's own\n") << m << extra;
    }
    // The earlier run's own stage files went (with --force: the other design's were written).
    EXPECT_EQ(fs::exists(out / "stages" / "lab-quick_stage0.done"), !*extra) << extra;
    EXPECT_TRUE(fs::exists(out / "stages" / (*extra ? "lab-other_stage0.done" : "lab-quick_stage0.done")));
    fs::remove_all(out);
  }
}

// A command other than `run` that writes into a folder holding another command's results
// (a run's manifest or run key, a sweep's manifest) would overwrite part of them: refused
// before any work, and the folder's files left as they were. The same command's own folder
// is its to rewrite.
TEST(HostileOptions, AFolderHoldingAnotherCommandsResultsIsRefused) {
  const TempDir dir("millwear-hostile-options-taken");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  const std::string run_manifest = "{\"program\": \"millwear\", \"files\": [\"manifest.json\"]}\n";
  for (const char* sub : {"run", "key/stages", "sweep", "charge"}) fs::create_directories(dir / sub);
  write(dir / "charge" / "charge_summary.csv", "quantity,value,unit\nscene,lab-mill,\n");
  write(dir / "run" / "manifest.json", run_manifest);
  write(dir / "key" / "stages" / "run.key", "design.lab-mill=0123\n");
  write(dir / "sweep" / "manifest.json", "{\"program\": \"millwear\", \"command\": \"sweep\"}\n");
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"charge " + lab + " -o " + quoted(dir / "run"), "millwear run"},
      {"charge " + lab + " -o " + quoted(dir / "key"), "millwear run"},
      {"sweep " + lab + " -o " + quoted(dir / "run") + " --vary mill.speed=0.5 --no-plot -q", "millwear run"},
      {"charge " + lab + " -o " + quoted(dir / "sweep"), "millwear sweep"},
      {"hardness " + quoted(fs::path(kSource + "/validation/hardness-synthetic.csv")) + " -o " + quoted(dir / "run"),
       "millwear run"},
      // run itself refuses another command's folder, --force or not: it deletes only a run's files.
      {"run " + lab + " -o " + quoted(dir / "charge") + " -q", "millwear charge"},
      {"run " + lab + " -o " + quoted(dir / "sweep") + " -q --force", "millwear sweep"},
  };
  for (const auto& [cmd, holder] : refused) {
    const auto r = run_millwear(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.output;
    const bool named = r.output.find("holds those of `" + holder + "`") != std::string::npos ||
                       r.output.find("holds the results of `" + holder + "`") != std::string::npos;
    EXPECT_TRUE(named) << r.output;
  }
  EXPECT_TRUE(fs::exists(dir / "sweep" / "manifest.json"));
  EXPECT_FALSE(fs::exists(dir / "charge" / "summary.csv"));
  EXPECT_EQ(read_text(dir / "run" / "manifest.json"), run_manifest);
  EXPECT_FALSE(fs::exists(dir / "run" / "liner_lab-mill.csv"));
  EXPECT_FALSE(fs::exists(dir / "run" / "hardness_fit.csv"));
  EXPECT_FALSE(fs::exists(dir / "run" / "sweep.csv"));
  EXPECT_FALSE(fs::exists(dir / "run" / ".millwear.lock"));
  // hardness into its own earlier folder rewrites it; its folder is marked as its own, and
  // every other command, run with --force included, is refused it.
  const std::string hard = "hardness " + quoted(fs::path(kSource + "/validation/hardness-synthetic.csv")) + " -o " +
                           quoted(dir / "hard");
  ASSERT_EQ(run_millwear(hard).exit_code, 0);
  const auto again = run_millwear(hard);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  const std::string hard_fit = read_text(dir / "hard" / "hardness_fit.csv");
  for (const std::string& cmd :
       {"charge " + lab + " -o " + quoted(dir / "hard"), "run " + lab + " -o " + quoted(dir / "hard") + " -q --force",
        "rule1 " + lab + " -o " + quoted(dir / "hard") + " --factors 1 2",
        "sweep " + lab + " -o " + quoted(dir / "hard") + " --vary mill.speed=0.5 --no-plot -q"}) {
    const auto r = run_millwear(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.output;
    EXPECT_NE(r.output.find("`millwear hardness`"), std::string::npos) << r.output;
  }
  EXPECT_EQ(read_text(dir / "hard" / "hardness_fit.csv"), hard_fit);
  EXPECT_FALSE(fs::exists(dir / "hard" / "manifest.json"));
  EXPECT_FALSE(fs::exists(dir / "hard" / "charge_summary.csv"));
}

// An output path the file system refuses (a name over 255 bytes) or that would break the
// figures' scripts (a newline) is refused before the work, not found when the first file is
// written after it.
TEST(HostileOptions, AnOutputPathWithAnOverlongNameOrANewlineIsRefusedBeforeTheWork) {
  const TempDir dir("millwear-hostile-options-names");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  const std::string longname(300, 'a');
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"charge " + lab + " -o " + quoted(dir / longname), "at most 255 bytes"},
      {"charge " + lab + " -o " + quoted(dir / "a\nb"), "control characters"},
      {"animate " + lab + " -o " + quoted(dir / (longname + ".gif")), "at most 255 bytes"},
      {"animate " + lab + " -o " + quoted(dir / "a\nb.gif"), "control characters"},
  };
  for (const auto& [cmd, said] : cases) {
    const auto r = run_millwear(cmd);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(said), std::string::npos) << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

// A refusal names what the user gave: rule 1's factor from the command line (not the
// scene's wear.factor), and a run key that names no design as such (not "design(s) ?").
TEST(HostileOptions, RefusalsNameTheOptionOrTheDamagedFile) {
  const TempDir dir("millwear-hostile-options-named");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  const auto r = run_millwear("rule1 " + lab + " --factors 1e5 1e-300");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--factors, --stages: factors within the run's limits over 1 stage; factor 1e-300 gives"),
            std::string::npos)
      << r.output;
  // A factor out of range is written as given, not as a 309-digit number.
  const auto big = run_millwear("rule1 " + lab + " --factors 1e5 1e308");
  EXPECT_EQ(big.exit_code, 2) << big.output;
  EXPECT_NE(big.output.find("got 1e+308"), std::string::npos) << big.output;
  // One factor is compared with nothing: no recommendation can come of it.
  const auto one = run_millwear("rule1 " + lab + " --factors 1e5 -o " + quoted(dir / "one"));
  EXPECT_EQ(one.exit_code, 2) << one.output;
  EXPECT_NE(one.output.find("--factors: at least two factors, each compared with the smallest; got 1"),
            std::string::npos)
      << one.output;
  EXPECT_FALSE(fs::exists(dir / "one"));
  // tradeoff's --stages and --stage-hours make the history too long: they are named, not the
  // scene key whose limit they broke.
  const auto t = run_millwear("tradeoff " + lab + " -o " + quoted(dir / "ladder") +
                              " --quick --stages 10000 --stage-hours 1e6");
  EXPECT_EQ(t.exit_code, 2) << t.output;
  EXPECT_NE(t.output.find("--stages, --stage-hours: a history within the run's limits"), std::string::npos)
      << t.output;
  EXPECT_FALSE(fs::exists(dir / "ladder"));
  fs::create_directories(dir / "out" / "stages");
  write(dir / "out" / "stages" / "run.key", "");
  const auto k = run_millwear("run " + lab + " -o " + quoted(dir / "out") + " -q");
  EXPECT_EQ(k.exit_code, 2) << k.output;
  EXPECT_NE(k.output.find("names no design"), std::string::npos) << k.output;
}

// A screen whose base is not a scene (here the comparison file) is refused with the base
// file's own error and the screen file whose screen.base names it.
TEST(HostileScreen, ABaseThatIsNotASceneNamesTheScreensBase) {
  const TempDir dir("millwear-hostile-screen-base");
  std::string text = read_text(kSource + "/scenarios/screen-sag-face-angle.toml");
  text.replace(text.find("base = \"sag-2x30.toml\""), 22,
               "base = \"" + kSource + "/scenarios/sag-2x30-vs-1x30.toml\"");
  const std::string profile = "equal_area = \"../profiles/2x30.toml\"";
  text.replace(text.find(profile), profile.size(), "equal_area = \"" + kSource + "/profiles/2x30.toml\"");
  write(dir / "screen.toml", text);
  const auto r = run_millwear("screen " + quoted(dir / "screen.toml") + " -o " + quoted(dir / "out"));
  expect_refused(r, "sag-2x30-vs-1x30.toml", "comparison", dir / "out");
  EXPECT_NE(r.output.find("screen.toml's screen.base names"), std::string::npos) << r.output;
}

// A FIFO or a device given as an input file is refused at once, naming it, rather than read
// until it ends (never, for /dev/zero) or waited on (a FIFO nobody writes).
TEST(HostileFiles, AFifoOrADeviceIsRefusedNotWaitedOn) {
  const TempDir dir("millwear-hostile-files-fifo");
  const fs::path fifo = dir / "surveys.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  for (const std::string& input : {quoted(fifo), std::string("/dev/zero")}) {
    for (const std::string& cmd : {"hardness " + input + " -o " + quoted(dir / "h"),
                                   "validate " + lab + " --measured " + input + " -o " + quoted(dir / "v")}) {
      // timeout: a command that waits on the FIFO ends with 124, not 2.
      const auto r = millwear::testing::run_shell("timeout 60 \"" + std::string(MILLWEAR_BINARY) + "\" " + cmd);
      EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.output;
      EXPECT_NE(r.output.find("not a regular file"), std::string::npos) << r.output;
    }
  }
  EXPECT_FALSE(fs::exists(dir / "h"));
  EXPECT_FALSE(fs::exists(dir / "v"));
}

// A reference hardness far outside the data's would make a = H0^-b zero or infinite and the
// corrected rates inf or NaN: refused naming the option and the range that holds.
TEST(HostileOptions, AReferenceHardnessFarFromTheDataIsRefused) {
  const TempDir dir("millwear-hostile-options-hardness");
  const std::string file = quoted(fs::path(kSource + "/validation/hardness-synthetic.csv"));
  for (const char* h0 : {"1e300", "1e-300"}) {
    const auto r = run_millwear("hardness " + file + " -o " + quoted(dir / "out") + " --reference-hardness " + h0);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--reference-hardness"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("within a factor of 1000"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  const auto ok = run_millwear("hardness " + file + " -o " + quoted(dir / "ok") + " --reference-hardness 14");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  const std::string fit = read_text(dir / "ok" / "hardness_fit.csv");
  EXPECT_EQ(fit.find("nan"), std::string::npos) << fit;
  EXPECT_EQ(fit.find("inf"), std::string::npos) << fit;
}

// A folder the command may not write (here one holding a user's file) is refused before any
// result is shown: exit 2, the fit not printed, the user's file untouched.
TEST(HostileFiles, HardnessRefusesItsFolderBeforePrintingAFit) {
  const TempDir dir("millwear-hostile-hardness-folder");
  const std::string file = quoted(fs::path(kSource + "/validation/hardness-synthetic.csv"));
  fs::create_directories(dir / "out");
  std::ofstream(dir / "out" / "user.txt") << "mine\n";
  const auto r = run_millwear("hardness " + file + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output.find("a = "), std::string::npos) << r.output;
  EXPECT_EQ(read_text(dir / "out" / "user.txt"), "mine\n");
  EXPECT_FALSE(fs::exists(dir / "out" / "hardness_fit.csv"));
}

// A frame of the animation is a whole number of time steps. 200 frames of 0.1 s on the lab's
// 1 ms step were a step each, 0.2 s, said to be "0.10 s of the charge" with exit 0: refused
// before any work, with the frames that fit. Frames of 10/3 steps are 4 steps each: the
// seconds said are those shown, 30 x 4 ms.
TEST(HostileOptions, AnimateFramesAreWholeTimeStepsAndTheSecondsSaidAreThoseShown) {
  const TempDir dir("millwear-hostile-animate-frames");
  const std::string lab = quoted(fs::path(kSource + "/tests/data/lab-quick.toml"));
  const auto r = run_millwear("animate " + lab + " -o " + quoted(dir / "a.gif") + " --seconds 0.1 --frames 200");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--frames"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("at most 100 frames for 0.1 s"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "a.gif"));
  // (Without gnuplot, which draws the GIF, animate stops before simulating: exit 1.)
  const auto ok = run_millwear("animate " + lab + " -o " + quoted(dir / "b.gif") + " --seconds 0.1 --frames 30");
  ASSERT_EQ(ok.exit_code, millwear::plots::gnuplot_available() ? 0 : 1) << ok.output;
  if (ok.exit_code == 0) {
    EXPECT_NE(ok.output.find("30 frames, 0.12 s of the charge"), std::string::npos) << ok.output;
  }
}

// An empty --fidelity or --reference is a mistake on the command line, not "the default".
TEST(HostileOptions, AnEmptyFidelityOrReferenceIsRefused) {
  const TempDir dir("millwear-hostile-options-empty");
  const std::string lab = quoted(fs::path(kSource + "/scenarios/lab-mill.toml"));
  for (const std::string& cmd : {"run " + lab + " -o " + quoted(dir / "r") + " --fidelity \"\"",
                                 "charge " + lab + " -o " + quoted(dir / "c") + " --fidelity \"\"",
                                 "sweep " + lab + " -o " + quoted(dir / "s") + " --vary mill.speed=0.5 --fidelity \"\"",
                                 "run " + lab + " -o " + quoted(dir / "r") + " --reference \"\""}) {
    const auto r = run_millwear(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.output;
    const bool named = r.output.find("--fidelity") != std::string::npos || r.output.find("--reference") != std::string::npos;
    EXPECT_TRUE(named) << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

// ---- files read back -------------------------------------------------------------------------

// A stage file that says "nan" is a damaged file: refused on --resume naming file and key,
// not carried into summary.csv as a figure. The marker's content hashes are taken out (a
// marker without hashes is taken as it is): the numbers themselves are checked too.
// Stage 1's record of a finished run of the lab scene with each key set to its value, its
// marker's content hashes dropped (as a run written before the hashes): what a resume then
// reads. Returns the record.
fs::path edit_stage_one_record(const fs::path& out, const std::vector<std::pair<std::string, std::string>>& edits) {
  fs::path record;
  for (const auto& e : fs::directory_iterator(out / "stages"))
    if (e.path().extension() == ".record" && e.path().string().find("stage1") != std::string::npos) record = e.path();
  EXPECT_FALSE(record.empty());
  std::string text = read_text(record);
  for (const auto& [key, value] : edits) {
    const auto at = text.find(key + "=");
    EXPECT_NE(at, std::string::npos) << text;
    if (at == std::string::npos) return record;
    text.replace(at, text.find('\n', at) - at, key + "=" + value);
  }
  write(record, text);
  const fs::path marker = out / "stages" / (record.stem().string() + ".done");
  std::string kv = read_text(marker);
  EXPECT_NE(kv.find("hash.record="), std::string::npos) << kv;
  for (auto hash = kv.find("hash."); hash != std::string::npos; hash = kv.find("hash."))
    kv.erase(hash, kv.find('\n', hash) + 1 - hash);
  write(marker, kv);
  return record;
}

TEST(HostileStageFiles, ANotANumberInAFinishedStageIsRefusedOnResume) {
  const TempDir dir("millwear-hostile-stage-nan");
  std::string s = lab_quick();
  const fs::path scene = dir / "scene.toml";
  write(scene, s);
  const fs::path out = dir / "out";
  const auto first = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const fs::path record = edit_stage_one_record(out, {{"lifter.area_m2", "nan"}});
  const auto again = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find(record.filename().string()), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("lifter.area_m2"), std::string::npos) << again.output;
}

// A window in which no disk reached the shell band has no toe or shoulder (NaN): such a
// stage resumes, and the run's summary says `nan` for them.
TEST(HostileStageFiles, AStageWithoutAToeOrShoulderResumes) {
  const TempDir dir("millwear-hostile-stage-no-toe");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const fs::path out = dir / "out";
  const auto first = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  edit_stage_one_record(out, {{"summary.toe_deg", "nan"}, {"summary.shoulder_deg", "nan"}});
  const auto again = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  const millwear::io::CsvData sum = millwear::io::read_csv((out / "summary.csv").string());
  ASSERT_EQ(sum.row_count(), 3u);  // stages 0, 1 and 2
  for (const char* c : {"toe_deg", "shoulder_deg"}) {
    EXPECT_TRUE(std::isfinite(sum.number(0, sum.column(c)))) << c;
    EXPECT_TRUE(std::isnan(sum.number(1, sum.column(c)))) << c;
  }
}

// A state file cut at a line end still parses (fewer disks, fewer liner points) and would
// resume from other numbers: its marker's content hash refuses it, naming the file, for
// every command that reads a finished run's stages. A file left as written resumes.
TEST(HostileStageFiles, AStateFileCutAtALineEndIsRefused) {
  const TempDir dir("millwear-hostile-stage-cut");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const fs::path out = dir / "out";
  ASSERT_EQ(run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet").exit_code, 0);
  for (const std::string ext : {".charge.csv", ".units.csv"}) {
    const fs::path file = out / "stages" / ("lab-quick_stage1" + ext);
    ASSERT_TRUE(fs::exists(file)) << file;
    const std::string whole = read_text(file);
    // The last three lines gone: what is left ends at a line end.
    std::size_t cut = whole.size() - 1;
    for (int k = 0; k < 3; ++k) cut = whole.rfind('\n', cut - 1);
    write(file, whole.substr(0, cut + 1));
    const auto again = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
    EXPECT_EQ(again.exit_code, 2) << again.output;
    EXPECT_NE(again.output.find(file.filename().string()), std::string::npos) << again.output;
    EXPECT_NE(again.output.find("changed or cut"), std::string::npos) << again.output;
    const auto cont = run_millwear("run " + quoted(scene) + " -o " + quoted(dir / "next") + " --quiet --continue " +
                                   quoted(out) + " --stage 1");
    EXPECT_EQ(cont.exit_code, 2) << cont.output;
    EXPECT_NE(cont.output.find(file.filename().string()), std::string::npos) << cont.output;
    write(file, whole);
  }
  // The charge the stage started from, gone: not a fresh fill, a damaged stage.
  const fs::path start = out / "stages" / "lab-quick_stage1.start.csv";
  const std::string start_text = read_text(start);
  fs::remove(start);
  const auto gone = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
  EXPECT_EQ(gone.exit_code, 2) << gone.output;
  EXPECT_NE(gone.output.find(start.filename().string()), std::string::npos) << gone.output;
  write(start, start_text);
  // A marker that lost one file's hash: refused naming the marker and the key.
  const fs::path marker = out / "stages" / "lab-quick_stage1.done";
  const std::string marker_text = read_text(marker);
  std::string edited = marker_text;
  const auto at = edited.find("hash.edges.csv=");
  ASSERT_NE(at, std::string::npos) << edited;
  edited.erase(at, edited.find('\n', at) + 1 - at);
  write(marker, edited);
  const auto unhashed = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
  EXPECT_EQ(unhashed.exit_code, 2) << unhashed.output;
  EXPECT_NE(unhashed.output.find("hash.edges.csv"), std::string::npos) << unhashed.output;
  write(marker, marker_text);
  const auto intact = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
  EXPECT_EQ(intact.exit_code, 0) << intact.output;
}

// A stage marker that does not read (garbled on disk) marks no finished stage, as a marker
// deleted does: --resume measures that stage again and the run ends as an uninterrupted one,
// not failed when it comes to write the stage over the garbled marker.
TEST(HostileStageFiles, AGarbledStageMarkerIsAStageToRunAgain) {
  const TempDir dir("millwear-hostile-stage-garbled-marker");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const fs::path out = dir / "out";
  ASSERT_EQ(run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet").exit_code, 0);
  const std::string summary = read_text(out / "summary.csv");
  const fs::path marker = out / "stages" / "lab-quick_stage1.done";
  ASSERT_TRUE(fs::exists(marker));
  write(marker, "garbage\n");
  const auto again = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(read_text(out / "summary.csv"), summary);
  EXPECT_NE(read_text(marker).find("hash.record="), std::string::npos);
}

// --continue reads a finished run: one another process is still writing is refused, naming it.
TEST(HostileStageFiles, ARunStillBeingWrittenIsNotContinued) {
  const TempDir dir("millwear-hostile-continue-locked");
  std::string s = lab_quick();
  const fs::path scene = dir / "scene.toml";
  write(scene, s);
  const fs::path run = dir / "run";
  ASSERT_EQ(run_millwear("run " + quoted(scene) + " -o " + quoted(run) + " --quiet --set wear.stages=1").exit_code, 0);
  const std::string cont = "run " + quoted(scene) + " -o " + quoted(dir / "next") + " --quiet --continue " + quoted(run);
  {
    const millwear::io::FolderLock writer(run.string());  // as a run still writing into it
    const auto r = run_millwear(cont);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("holds its lock"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "next"));
  }
  const auto r = run_millwear(cont);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// A run of another mill under the same design name (here 10 rows, the scene 12) is refused by
// the commands that draw on a finished run, naming it; the scene's own run is taken.
TEST(HostileStageFiles, ARunOfAnotherMillIsNotDrawnOn) {
  const TempDir dir("millwear-hostile-other-mill");
  const fs::path scene = lab_mill_with_profile(dir, kSource + "/profiles/lab-2x30.toml");
  std::string ten = read_text(scene);
  ten.replace(ten.find("rows = 12"), 9, "rows = 10");
  write(dir / "ten.toml", ten);
  const fs::path run = dir / "run10";
  ASSERT_EQ(run_millwear("run " + quoted(dir / "ten.toml") + " -o " + quoted(run) + " --quiet --fidelity draft --set wear.stages=1")
                .exit_code,
            0);
  const auto a = run_millwear("animate " + quoted(scene) + " --history " + quoted(run) + " -o " + quoted(dir / "a.gif"));
  expect_refused(a, run.string(), "--history", dir / "a.gif");
  const auto v = run_millwear("validate " + quoted(scene) + " --measured " +
                              quoted(fs::path(kSource + "/validation/lab-mill-areas.csv")) + " --from " + quoted(run) +
                              " -o " + quoted(dir / "v"));
  expect_refused(v, run.string(), "--from", dir / "v");
  // Nor is its liner continued in the scene's mill: it would not fit its lifter rows.
  const auto c = run_millwear("run " + quoted(scene) + " -o " + quoted(dir / "c") + " --continue " + quoted(run) +
                              " --fidelity draft");
  expect_refused(c, scene.string(), "lifters.rows", dir / "c");
  EXPECT_NE(c.output.find("10 -> 12"), std::string::npos) << c.output;
  // The run's own scene draws on it; at another speed it is refused, naming the setting.
  const auto own = run_millwear("animate " + quoted(dir / "ten.toml") + " --fidelity draft --set wear.stages=1 --history " + quoted(run) +
                                " --seconds 0.5 --frames 10 -o " + quoted(dir / "own.gif"));
  EXPECT_EQ(own.exit_code, 0) << own.output;
  const auto faster = run_millwear("animate " + quoted(dir / "ten.toml") +
                                   " --fidelity draft --set wear.stages=1 --set mill.speed=0.6 --history " + quoted(run) +
                                   " -o " + quoted(dir / "b.gif"));
  expect_refused(faster, run.string(), "--history", dir / "b.gif");
  EXPECT_NE(faster.output.find("mill.speed"), std::string::npos) << faster.output;
}

// Collisions only take energy out of a charge. At 1.6 times the critical speed the lab bed
// rides the shell under 2.6 g, and the solver's error (in proportion to the time step) makes
// its disk-disk contacts give energy: `charge` says the split of the power is not sound, and
// `run` names the event for each stage, a resumed run too. At the scene's own speed the
// collisions dissipate and nothing is said.
TEST(HostileScenes, ContactsThatGiveTheChargeEnergyAreSaidToBeUnsound) {
  const TempDir dir("millwear-hostile-unsound-split");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const std::string fast = " --set mill.speed=1.6 --set solver.spinup_revolutions=3";
  const auto charge = run_millwear("charge " + quoted(scene) + fast + " -o " + quoted(dir / "fast"));
  ASSERT_EQ(charge.exit_code, 0) << charge.output;
  const auto collision = [&](const char* out) {
    const millwear::io::CsvData t = millwear::io::read_csv((dir / out / "charge_summary.csv").string());
    for (std::size_t r = 0; r < t.row_count(); ++r)
      if (t.text(r, 0) == "collision_power_per_m") return t.number(r, 1);
    return std::nan("");
  };
  ASSERT_LT(collision("fast"), 0.0) << "the contacts did not give energy: the case is not tested";
  EXPECT_NE(charge.output.find("the contacts between disks gave the charge energy"), std::string::npos)
      << charge.output;
  const auto steady = run_millwear("charge " + quoted(scene) + " -o " + quoted(dir / "steady"));
  ASSERT_EQ(steady.exit_code, 0) << steady.output;
  EXPECT_GT(collision("steady"), 0.0);
  EXPECT_EQ(steady.output.find("gave the charge energy"), std::string::npos) << steady.output;

  const std::string run = "run " + quoted(scene) + fast + " --set wear.stages=1 -o " + quoted(dir / "run");
  const auto stopped = run_millwear(run + " --stop-after-stage 0");
  ASSERT_EQ(stopped.exit_code, 130) << stopped.output;
  const auto resumed = run_millwear(run + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  for (const char* stage : {"event: stage 0: the contacts between disks", "event: stage 1: the contacts between disks"})
    EXPECT_NE(resumed.output.find(stage), std::string::npos) << resumed.output;
}

// A stage whose window finds the charge still settling (at 1.9 times the critical speed the
// lab bed takes over a revolution of spin-up to ride the shell) is a run event naming the
// stage, as `charge` warns of that window, a resumed run too; at the scene's own speed the
// windows are steady and nothing is said.
TEST(HostileScenes, AStageWindowNotSteadyIsARunEvent) {
  const TempDir dir("millwear-hostile-unsteady-window");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const std::string run = "run " + quoted(scene) + " --set mill.speed=1.9 --set wear.stages=1 -o " + quoted(dir / "run");
  const auto stopped = run_millwear(run + " --stop-after-stage 0");
  ASSERT_EQ(stopped.exit_code, 130) << stopped.output;
  const auto resumed = run_millwear(run + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("event: stage 0: the charge was not steady in the window"), std::string::npos)
      << resumed.output;
  const auto steady = run_millwear("run " + quoted(scene) + " --set wear.stages=1 -o " + quoted(dir / "steady"));
  ASSERT_EQ(steady.exit_code, 0) << steady.output;
  EXPECT_EQ(steady.output.find("not steady"), std::string::npos) << steady.output;
}

// One disk never collides: its spectrum is empty, and no spectrum figure is drawn (on log
// axes it has no point, and gnuplot's refusal failed the command). The rest are drawn and
// the commands succeed.
TEST(HostileScenes, AChargeWithoutACollisionDrawsNoSpectrumAndSucceeds) {
  const TempDir dir("millwear-hostile-one-disk");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  // A share of half the largest ball's area: one ball whatever size it draws.
  const std::string one = " --set charge.filling=0.0011 --set charge.ball_filling=0.0011";
  const auto charge = run_millwear("charge " + quoted(scene) + one + " -o " + quoted(dir / "charge"));
  ASSERT_EQ(charge.exit_code, 0) << charge.output;
  EXPECT_FALSE(fs::exists(dir / "charge" / "plots" / "spectrum.png"));
  EXPECT_EQ(charge.output.find("spectrum,"), std::string::npos) << charge.output;
  const auto run = run_millwear("run " + quoted(scene) + one + " --set wear.stages=1 -o " + quoted(dir / "run"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(fs::exists(dir / "run" / "plots" / "fig7_area.png"));
  EXPECT_FALSE(fs::exists(dir / "run" / "plots" / "spectrum.png"));
}

// Soft contacts let the settled bed sink into itself under its weight, about 2 n g / w^2 at
// the bottom of n layers. The estimate against the engine: the deepest overlap of two disks
// in the lab mill's bed after two revolutions, at 40 and 80 Hz, within a third of it. At 40
// Hz --check notes the contacts as soft for the bed and names a frequency that is not; at
// that frequency, and at the scene's own, nothing is noted.
TEST(HostileScenes, ContactsTooSoftForTheBedAreNotedAndTheEstimateHolds) {
  const TempDir dir("millwear-hostile-soft-bed");
  const std::string lab = kSource + "/scenarios/lab-mill.toml";
  for (const int hertz : {40, 80}) {
    const millwear::Scene s = millwear::load_scene(lab, {"solver.contact_hertz=" + std::to_string(hertz)});
    const double estimate = millwear::bed_overlap_radii(s);
    const fs::path out = dir / ("hz" + std::to_string(hertz));
    const auto r = run_millwear("charge " + quoted(fs::path(lab)) + " --revolutions 2 -q --set solver.contact_hertz=" +
                                std::to_string(hertz) + " -o " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const millwear::io::CsvData snap = millwear::io::read_csv((out / "snapshot_lab-mill.csv").string());
    const auto x = snap.numbers("x_m"), y = snap.numbers("y_m"), rad = snap.numbers("radius_m");
    double deepest = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t j = i + 1; j < x.size(); ++j) {
        const double overlap = rad[i] + rad[j] - std::hypot(x[i] - x[j], y[i] - y[j]);
        deepest = std::max(deepest, overlap / s.smallest_particle_radius_m());
      }
    EXPECT_GT(deepest, estimate / 1.33) << hertz << " Hz";
    EXPECT_LT(deepest, estimate * 1.33) << hertz << " Hz";
  }
  const auto noted = run_millwear("charge " + quoted(fs::path(lab)) + " --check --set solver.contact_hertz=40 -o " +
                                  quoted(dir / "check"));
  ASSERT_EQ(noted.exit_code, 0) << noted.output;
  const std::string lead = "solver.contact_hertz ";
  const auto at = noted.output.find(lead, noted.output.find("are soft for this bed"));
  ASSERT_NE(at, std::string::npos) << noted.output;
  const std::string enough = noted.output.substr(at + lead.size(), noted.output.find(' ', at + lead.size()) - at - lead.size());
  EXPECT_LE(millwear::bed_overlap_radii(millwear::load_scene(lab, {"solver.contact_hertz=" + enough})), millwear::kSoundBedOverlapRadii) << enough;
  for (const std::string& set : {" --set solver.contact_hertz=" + enough, std::string()}) {
    const auto quiet = run_millwear("charge " + quoted(fs::path(lab)) + " --check" + set + " -o " + quoted(dir / "check"));
    ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
    EXPECT_EQ(quiet.output.find("soft for this bed"), std::string::npos) << set << "\n" << quiet.output;
  }
}

// The same history under two names gives every figure to the same bit: the verdicts say the
// two are equal, not that one is higher by 0.
TEST(HostileScenes, TwoNamesOfOneHistoryAreSaidToBeEqual) {
  const TempDir dir("millwear-hostile-equal");
  std::string s = lab_quick();
  s.replace(s.find("\"lab-quick\""), 11, "\"copy-a\"");
  write(dir / "a.toml", s);
  s.replace(s.find("\"copy-a\""), 8, "\"copy-b\"");
  write(dir / "b.toml", s);
  const auto r = run_millwear("run " + quoted(dir / "a.toml") + " " + quoted(dir / "b.toml") +
                              " --set wear.stages=1 --quiet -o " + quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(read_text(dir / "out" / "profiles" / "copy-a_stage1.csv"), read_text(dir / "out" / "profiles" / "copy-b_stage1.csv"));
  const std::string md = read_text(dir / "out" / "summary.md");
  EXPECT_NE(md.find("copy-b and copy-a are equal"), std::string::npos) << md;
  EXPECT_EQ(md.find("higher than"), std::string::npos) << md;
  EXPECT_EQ(md.find("lower than"), std::string::npos) << md;
}

// outputs.snapshot = false: a run writes no snapshot of the charge and draws none, as charge
// does not; the liner file and the other figures are written.
TEST(HostileScenes, ARunWithoutTheSnapshotOutputWritesNone) {
  const TempDir dir("millwear-hostile-no-snapshot");
  const fs::path scene = dir / "scene.toml";
  write(scene, lab_quick());
  const auto r = run_millwear("run " + quoted(scene) + " --set outputs.snapshot=false --set wear.stages=1 -o " +
                              quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "snapshot_lab-quick.csv"));
  EXPECT_FALSE(fs::exists(dir / "out" / "plots" / "snapshot_lab-quick.png"));
  EXPECT_TRUE(fs::exists(dir / "out" / "liner_lab-quick.csv"));
  EXPECT_TRUE(fs::exists(dir / "out" / "plots" / "fig7_area.png"));
  EXPECT_EQ(read_text(dir / "out" / "manifest.json").find("snapshot_lab-quick"), std::string::npos);
}

// A charge that centrifuges has no toe or shoulder: their standard errors are NaN in the stage
// file, which is what the file means, and the run resumes from it.
TEST(HostileStageFiles, ACentrifugedRunResumesFromItsStages) {
  const TempDir dir("millwear-hostile-stage-centrifuged");
  std::string s = lab_quick();
  s.replace(s.find("speed = 0.75"), 12, "speed = 1.60");
  const fs::path scene = dir / "scene.toml";
  write(scene, s);
  const fs::path out = dir / "out";
  const auto first = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  bool undefined = false;
  for (const auto& e : fs::directory_iterator(out / "stages"))
    if (e.path().extension() == ".record") undefined |= read_text(e.path()).find("charge_se.toe_deg=nan") != std::string::npos;
  ASSERT_TRUE(undefined) << "the charge did not centrifuge: the case is not tested";
  const auto again = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --quiet --resume");
  EXPECT_EQ(again.exit_code, 0) << again.output;
}

// Surveys in metres or of another mill: refused naming the file and the survey's line.
TEST(HostileSurveys, SurveyPointsOutsideTheLinerUnitAreRefused) {
  const TempDir dir("millwear-hostile-survey-far");
  const fs::path surveys = dir / "far.csv";
  write(surveys, "hours,x_mm,y_mm\n0,-16,0\n0,0,20\n0,16,0\n100,-16000,0\n100,0,18000\n100,16000,0\n");
  const auto r = run_millwear("validate " + quoted(fs::path(kSource + "/scenarios/lab-mill.toml")) + " --measured " +
                              quoted(surveys) + " -o " + quoted(dir / "out"));
  expect_refused(r, surveys.string(), "line 5", dir / "out");
}

// A rectangular scan whose shell plates lie a whole number of mesh edges below the shell line:
// the re-meshed surface has a vertex a rounding error above the line, which is a foot, not a
// lifter point on the line. So is a file point 0.5 nm above it.
TEST(HostileMeasured, APointARoundingErrorAboveTheShellLineIsAFoot) {
  const TempDir dir("millwear-hostile-measured-rounding");
  write(dir / "rect.csv", "x_mm,y_mm\n-30,-2\n-10,-2\n-10,20\n10,20\n10,-2\n30,-2\n");
  const auto r = run_millwear("run " + quoted(lab_mill_with_profile(dir, "rect.csv")) + " -o " + quoted(dir / "out") +
                              " --check");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  write(dir / "tiny.csv", "x_mm,y_mm\n-60,-5\n-50,-5\n-50,0.0000005\n-50,100\n50,100\n50,-5\n60,-5\n");
  const auto p = run_millwear("profile " + quoted(dir / "tiny.csv"));
  EXPECT_EQ(p.exit_code, 0) << p.output;
  EXPECT_NE(p.output.find("10000.0"), std::string::npos) << p.output;  // 100 x 100 mm
}

// A scan whose shell plate goes 246 mm below the line in a 300 mm mill (a typed -246 for
// -2.46) is refused by the scene, naming the scan, not run as a crevasse in the shell.
TEST(HostileMeasured, AScanFarBelowTheShellLineIsRefused) {
  const TempDir dir("millwear-hostile-measured-deep");
  write(dir / "deep.csv", "x_mm,y_mm\n-30,-2\n-16.5,0\n-5,20\n5,20\n16.5,0\n25,-246\n30,-2\n");
  const fs::path scene = lab_mill_with_profile(dir, "deep.csv");
  for (const char* cmd : {"charge", "run"}) {
    const auto r = run_millwear(std::string(cmd) + " " + quoted(scene) + " -o " + quoted(dir / "out"));
    expect_refused(r, (dir / "deep.csv").string(), "x_mm,y_mm", dir / "out");
    EXPECT_NE(r.output.find("a tenth of the mill radius"), std::string::npos) << r.output;
  }
}

// calibrate without -o writes its copy beside the scene: a file of the user's under that name
// is refused before any run, and stays as it was.
TEST(HostileFiles, CalibrateDoesNotReplaceAUsersFileUnderTheCopysName) {
  const TempDir dir("millwear-hostile-calibrated-copy");
  fs::create_directories(dir / "scenarios");
  fs::create_directory_symlink(kSource + "/profiles", dir / "profiles");
  fs::copy_file(kSource + "/scenarios/lab-mill.toml", dir / "scenarios/lab-mill.toml");
  const fs::path mine = dir / "scenarios/lab-mill-calibrated.toml";
  write(mine, "# my own edit of the lab mill\n");
  const auto r = run_millwear("calibrate " + quoted(dir / "scenarios/lab-mill.toml") + " --measured " +
                              quoted(fs::path(kSource + "/validation/lab-mill-surveys.csv")) + " --max-runs 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("lab-mill-calibrated.toml: no file, or one `millwear calibrate` wrote"), std::string::npos)
      << r.output;
  EXPECT_EQ(read_text(mine), "# my own edit of the lab mill\n");
}
