// Scene files: the shipped scenes load with the values they state; every class of bad input
// is an InputError naming the file and the dotted key; fidelity presets fill what a scene
// leaves out and never override what it sets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "scene/fidelity.hpp"
#include "scene/filling.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"
#include "temp_dir.hpp"
#include "tiny_scene.hpp"

namespace fs = std::filesystem;
using namespace millwear;
using millwear::testing::TempDir;

namespace {


std::string shipped(const std::string& rel) { return std::string(MILLWEAR_SOURCE_DIR) + "/" + rel; }

// Each bad-input test changes one thing in the tiny scene.
const char* const kBaseScene = millwear::testing::kTinyScene;
const char* const kLifter = millwear::testing::kTinyLifter;

// One temporary folder per test (ctest runs tests in parallel processes).
class SceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    write("lifter.toml", kLifter);
  }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  // The base scene with `from` replaced by `to` (from must occur, so a test cannot pass by
  // editing nothing).
  std::string scene_with(const std::string& from, const std::string& to) {
    std::string text = kBaseScene;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the base scene";
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return write("scene.toml", text);
  }
  // Load a scene that must fail; returns the error.
  static InputError load_error(const std::string& path) {
    try {
      load_scene(path);
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no InputError for " << path;
    return InputError("", "", "");
  }
  static void expect_names(const InputError& e, const std::string& file, const std::string& key) {
    EXPECT_EQ(e.file, file);
    EXPECT_EQ(e.where, key);
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file), std::string::npos) << msg;
    EXPECT_NE(msg.find(key), std::string::npos) << msg;
  }

  TempDir dir_{"millwear-scene"};
};

using SceneErrors = SceneTest;
using SceneUnits = SceneTest;
using SceneFidelity = SceneTest;

}  // namespace

// ---------------------------------------------------------------------------------------
// The shipped scenes
// ---------------------------------------------------------------------------------------

TEST(SceneFiles, Sag2x30HasTheStatedMillAndCharge) {
  const Scene s = load_scene(shipped("scenarios/sag-2x30.toml"));
  EXPECT_EQ(s.name, "sag-2x30");
  EXPECT_DOUBLE_EQ(s.mill.diameter_m, 10.0);
  EXPECT_DOUBLE_EQ(s.mill.length_m, 5.0);
  EXPECT_DOUBLE_EQ(s.mill.speed_fraction_critical, 0.75);
  EXPECT_EQ(s.mill.direction, Direction::Bidirectional);
  EXPECT_DOUBLE_EQ(s.mill.reverse_every_hours, 750.0);
  EXPECT_EQ(s.mill.rows, 48);
  EXPECT_DOUBLE_EQ(s.charge.filling, 0.28);
  EXPECT_DOUBLE_EQ(s.charge.ball_filling, 0.12);
  ASSERT_EQ(s.charge.species.size(), 2u);
  EXPECT_TRUE(s.charge.species[0].is_ball);
  EXPECT_DOUBLE_EQ(s.charge.species[0].largest_diameter_m(), 0.125);
  EXPECT_DOUBLE_EQ(s.charge.species[1].d_min_m, 0.100);
  EXPECT_DOUBLE_EQ(s.charge.species[1].d_max_m, 0.250);
  EXPECT_EQ(s.wear.stages * s.wear.stage_hours, 3000.0);
  EXPECT_EQ(s.fidelity, "standard");
}

TEST(SceneFiles, Sag1x30DiffersFromSag2x30OnlyInLiftersAndDirection) {
  const Scene a = load_scene(shipped("scenarios/sag-2x30.toml"));
  const Scene b = load_scene(shipped("scenarios/sag-1x30.toml"));
  EXPECT_EQ(b.name, "sag-1x30");
  EXPECT_EQ(b.mill.direction, Direction::Forward);
  EXPECT_NE(a.mill.lifter.source_file, b.mill.lifter.source_file);
  EXPECT_DOUBLE_EQ(a.mill.diameter_m, b.mill.diameter_m);
  EXPECT_DOUBLE_EQ(a.mill.speed_fraction_critical, b.mill.speed_fraction_critical);
  EXPECT_EQ(a.mill.rows, b.mill.rows);
  EXPECT_DOUBLE_EQ(a.charge.filling, b.charge.filling);
  EXPECT_DOUBLE_EQ(a.charge.ball_filling, b.charge.ball_filling);
  EXPECT_DOUBLE_EQ(a.wear.wear_rate_m3_per_J, b.wear.wear_rate_m3_per_J);
  EXPECT_DOUBLE_EQ(a.solver.time_step_s, b.solver.time_step_s);
}

TEST(SceneFiles, LabMillHasTheStatedMillAndCharge) {
  const Scene s = load_scene(shipped("scenarios/lab-mill.toml"));
  EXPECT_EQ(s.name, "lab-mill");
  EXPECT_DOUBLE_EQ(s.mill.diameter_m, 0.6);
  EXPECT_DOUBLE_EQ(s.mill.length_m, 0.3);
  EXPECT_EQ(s.mill.rows, 12);
  EXPECT_DOUBLE_EQ(s.charge.filling, 0.3);
  EXPECT_DOUBLE_EQ(s.charge.ball_filling, 0.3);
  ASSERT_EQ(s.charge.species.size(), 1u);
  EXPECT_TRUE(s.charge.species[0].is_ball);
  EXPECT_DOUBLE_EQ(s.solver.time_step_s, 0.001);
  EXPECT_DOUBLE_EQ(s.solver.settle_time_s, 0.5);
  EXPECT_EQ(s.wear.stages, 2);
  EXPECT_DOUBLE_EQ(s.wear.stage_hours, 100.0);
  // The lab lifter is the 2x30 scaled to 20 mm high.
  double height = 0.0;
  for (const Vec2& p : s.mill.lifter.points) height = std::max(height, p.y);
  EXPECT_NEAR(height, 0.020, 1e-12);
}

TEST(SceneFiles, LabMillChargeIsAFewHundredDisks) {
  // Disk count from areas: filling * mill area * packing / mean disk area; for diameters
  // uniform in [a, b], E[d^2] = (a^2 + ab + b^2) / 3. The scene is meant to hold 200-400 disks.
  const Scene s = load_scene(shipped("scenarios/lab-mill.toml"));
  const SpeciesDef& b = s.charge.species[0];
  const double mean_d2 = (b.d_min_m * b.d_min_m + b.d_min_m * b.d_max_m + b.d_max_m * b.d_max_m) / 3.0;
  const double solid = s.charge.filling * kPi * s.radius_m() * s.radius_m() * s.charge.bulk_packing;
  const double disks = solid / (0.25 * kPi * mean_d2);
  EXPECT_GT(disks, 200.0);
  EXPECT_LT(disks, 400.0);
}

TEST(SceneFiles, LabMillBuildsItsMill) {
  const Scene s = load_scene(shipped("scenarios/lab-mill.toml"));
  const MillGeometry m = build_scene_mill(s);
  EXPECT_EQ(m.rows, 12);
  EXPECT_DOUBLE_EQ(m.radius_m, 0.3);
  EXPECT_EQ(m.edges.size(), m.boundary.size());
}

// ---------------------------------------------------------------------------------------
// Bad input: each names the file and the dotted key
// ---------------------------------------------------------------------------------------

TEST_F(SceneErrors, BaseSceneOfTheseTestsLoads) {
  const Scene s = load_scene(write("scene.toml", kBaseScene));
  EXPECT_EQ(s.name, "tiny");
  EXPECT_EQ(s.charge.species.size(), 2u);
}

TEST_F(SceneErrors, UnknownKeyInASpeciesNamesItsDottedKey) {
  const std::string f = scene_with("name = \"rock\"\n", "name = \"rock\"\ndensty = 2.0\n");
  const InputError e = load_error(f);
  expect_names(e, f, "charge.species[1].densty");
  EXPECT_NE(e.expected.find("density"), std::string::npos) << e.expected;  // the near miss
}

TEST_F(SceneErrors, UnknownSectionIsRejected) {
  const std::string f = scene_with("[solver]", "[solvers]\nseed = 1\n[solver]");
  expect_names(load_error(f), f, "solvers");
}

TEST_F(SceneErrors, WrongTypeNamesKey) {
  const std::string f = scene_with("diameter = 0.6", "diameter = \"0.6\"");
  const InputError e = load_error(f);
  expect_names(e, f, "mill.diameter");
  EXPECT_NE(e.expected.find("a number"), std::string::npos) << e.expected;
}

TEST_F(SceneErrors, FloatForAnIntegerKeyIsRejected) {
  const std::string f = scene_with("rows = 12", "rows = 12.5");
  expect_names(load_error(f), f, "lifters.rows");
}

TEST_F(SceneErrors, OutOfRangeSpeedNamesKeyAndRange) {
  const std::string f = scene_with("speed = 0.75", "speed = 2.5");
  const InputError e = load_error(f);
  expect_names(e, f, "mill.speed");
  EXPECT_NE(e.expected.find("[0.01, 2]"), std::string::npos) << e.expected;
}

TEST_F(SceneErrors, NegativeDensityIsOutOfRange) {
  const std::string f = scene_with("density = 2700.0", "density = -2700.0");
  expect_names(load_error(f), f, "charge.species[1].density");
}

TEST_F(SceneErrors, BallFillingAboveFillingIsOutOfRange) {
  const std::string f = scene_with("ball_filling = 0.1", "ball_filling = 0.35");
  expect_names(load_error(f), f, "charge.ball_filling");
}

TEST_F(SceneErrors, MissingProfileFileNamesSceneKeyAndPathTried) {
  const std::string f = scene_with("profile = \"lifter.toml\"", "profile = \"nowhere/lifter.toml\"");
  const InputError e = load_error(f);
  expect_names(e, f, "lifters.profile");
  EXPECT_NE(e.expected.find((dir_ / "nowhere/lifter.toml").string()), std::string::npos) << e.expected;
}

TEST_F(SceneErrors, BadProfileErrorNamesTheProfileFile) {
  const std::string profile = write("lifter.toml", std::string(kLifter) + "colour = \"red\"\n");
  const InputError e = load_error(write("scene.toml", kBaseScene));
  EXPECT_EQ(e.file, profile);
}

TEST_F(SceneErrors, SpeedAndSpeedRpmTogetherAreRejected) {
  const std::string f = scene_with("speed = 0.75", "speed = 0.75\nspeed_rpm = 40.0");
  const InputError e = load_error(f);
  EXPECT_EQ(e.file, f);
  EXPECT_NE(std::string(e.what()).find("mill.speed_rpm"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("mill.speed"), std::string::npos) << e.what();
}

TEST_F(SceneErrors, NeitherSpeedNorSpeedRpmIsRejected) {
  const std::string f = scene_with("speed = 0.75", "");
  expect_names(load_error(f), f, "mill.speed");
}

TEST_F(SceneErrors, MassFractionsNotSummingToOneAreRejected) {
  const std::string f = scene_with("[0.4, 0.6]", "[0.4, 0.5]");
  const InputError e = load_error(f);
  expect_names(e, f, "charge.species[1].mass_fractions");
  EXPECT_NE(e.expected.find("sum"), std::string::npos) << e.expected;
}

TEST_F(SceneErrors, SizeRangeWithMinAboveMaxIsRejected) {
  const std::string f =
      scene_with("sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]", "size_range = [20.0, 10.0]");
  expect_names(load_error(f), f, "charge.species[1].size_range");
}

TEST_F(SceneErrors, BallFillingWithoutABallSpeciesIsRejected) {
  const std::string f = scene_with("ball = true", "ball = false");
  expect_names(load_error(f), f, "charge.species");
}

TEST_F(SceneErrors, TwoWearRatesAreRejected) {
  const std::string f = scene_with("wear_rate = 1e-11", "wear_rate = 1e-11\narea_loss_rate = 2500.0");
  expect_names(load_error(f), f, "wear.area_loss_rate");
}

TEST_F(SceneErrors, ReverseEveryNeedsABidirectionalMill) {
  const std::string f = scene_with("direction = \"forward\"", "direction = \"forward\"\nreverse_every = 750.0");
  expect_names(load_error(f), f, "mill.reverse_every");
}

TEST_F(SceneErrors, NotTomlAtAllNamesTheLine) {
  const std::string f = write("scene.toml", "this is not a scene\n");
  const InputError e = load_error(f);
  EXPECT_EQ(e.file, f);
  EXPECT_EQ(e.where, "line 1");
  EXPECT_NE(std::string(e.what()).find("line"), std::string::npos) << e.what();
}

TEST_F(SceneErrors, MissingSceneFileNamesIt) {
  const std::string f = (dir_ / "absent.toml").string();
  EXPECT_EQ(load_error(f).file, f);
}

// ---------------------------------------------------------------------------------------
// Units at the edge
// ---------------------------------------------------------------------------------------

TEST_F(SceneUnits, SpeedRpmBecomesFractionOfCritical) {
  // Critical speed of a 0.6 m mill: sqrt(g / 0.3) rad/s = 54.61 rpm; 27.3 rpm is half of it.
  const double crit_rpm = std::sqrt(kGravity / 0.3) * 60.0 / (2.0 * kPi);
  const Scene s = load_scene(scene_with("speed = 0.75", "speed_rpm = " + std::to_string(0.5 * crit_rpm)));
  EXPECT_NEAR(s.mill.speed_fraction_critical, 0.5, 1e-6);  // 1e-6: std::to_string keeps 6 decimals
}

TEST_F(SceneUnits, MillimetreKeysBecomeMetres) {
  const Scene s = load_scene(scene_with("rows = 12", "rows = 12\nshell_edge = 15.0\nlifter_edge = 3.0"));
  EXPECT_DOUBLE_EQ(s.mill.mesh.shell_edge_m, 0.015);
  EXPECT_DOUBLE_EQ(s.mill.mesh.lifter_edge_m, 0.003);
  EXPECT_DOUBLE_EQ(s.charge.species[0].diameters_m[0], 0.020);
  EXPECT_DOUBLE_EQ(s.wear.replacement_height_m, 0.005);
}

TEST_F(SceneUnits, StepsPerSecondGivesTheTimeStep) {
  const Scene s = load_scene(scene_with("seed = 3", "seed = 3\nsteps_per_second = 800"));
  EXPECT_DOUBLE_EQ(s.solver.time_step_s, 1.0 / 800.0);
}

TEST_F(SceneUnits, SoftSolverKeysAreRead) {
  const Scene s = load_scene(scene_with(
      "seed = 3", "seed = 3\nbackend = \"soft\"\ncontact_hertz = 120.0\ndamping_ratio = 2.0\npush_out = 15.0"));
  EXPECT_EQ(s.solver.backend, Backend::Soft);
  EXPECT_DOUBLE_EQ(s.solver.contact_hertz, 120.0);
  EXPECT_DOUBLE_EQ(s.solver.damping_ratio, 2.0);
  EXPECT_DOUBLE_EQ(s.solver.push_out_radii_per_s, 15.0);
}

// The soft step's frequency is contact_hertz up to an eighth of the substep rate; 0 and
// anything above ask for that bound.
TEST(SolverDef, ContactFrequencyUsedIsBoundedByAnEighthOfTheSubstepRate) {
  SolverDef s;
  s.time_step_s = 1.0 / 500.0;
  s.substeps = 4;  // 2000 substeps per second: the bound is 250 Hz
  s.contact_hertz = 0.0;
  EXPECT_DOUBLE_EQ(s.contact_hertz_used(), 250.0);
  s.contact_hertz = 120.0;
  EXPECT_DOUBLE_EQ(s.contact_hertz_used(), 120.0);
  s.contact_hertz = 1e7;
  EXPECT_DOUBLE_EQ(s.contact_hertz_used(), 250.0);
}

TEST_F(SceneErrors, NonPositiveDampingRatioNamesKey) {
  const std::string f = scene_with("seed = 3", "seed = 3\ndamping_ratio = 0.0");
  expect_names(load_error(f), f, "solver.damping_ratio");
}

TEST_F(SceneErrors, NegativeContactHertzNamesKey) {
  const std::string f = scene_with("seed = 3", "seed = 3\ncontact_hertz = -30.0");
  expect_names(load_error(f), f, "solver.contact_hertz");
}

TEST_F(SceneErrors, NonPositivePushOutNamesKey) {
  const std::string f = scene_with("seed = 3", "seed = 3\npush_out = 0");
  expect_names(load_error(f), f, "solver.push_out");
}

TEST_F(SceneUnits, AreaLossRateSetsTheCalibrationSource) {
  const Scene s = load_scene(scene_with("wear_rate = 1e-11", "area_loss_rate = 2500.0"));
  EXPECT_EQ(s.wear.rate_source, WearRateSource::AreaLossRate);
  EXPECT_DOUBLE_EQ(s.wear.target_loss_rate, 2500.0 * 1e-6 / (1000.0 * kSecondsPerHour));  // m^2/s
}

TEST_F(SceneUnits, SliceThicknessDefaultsToLargestUsedDiameter) {
  const Scene s = load_scene(write("scene.toml", kBaseScene));
  EXPECT_DOUBLE_EQ(s.slice_thickness(), 0.020);
  EXPECT_DOUBLE_EQ(s.smallest_particle_radius_m(), 0.005);
}

TEST_F(SceneUnits, SizeCutoffDropsSmallRockSizesOnly) {
  const Scene s = load_scene(scene_with("seed = 3", "seed = 3\nsize_cutoff = 15.0"));
  const auto placed = s.species_as_placed();
  ASSERT_EQ(placed[1].diameters_m.size(), 1u);
  EXPECT_DOUBLE_EQ(placed[1].diameters_m[0], 0.020);
  EXPECT_DOUBLE_EQ(placed[1].mass_fractions[0], 1.0);  // renormalised
  EXPECT_DOUBLE_EQ(s.smallest_particle_radius_m(), 0.010);
}

TEST_F(SceneUnits, ASizeClassAtTheCutoffStaysWhateverTheRounding) {
  // Classes 20 and 10 mm; a cut-off computed as 0.1 x 0.1 m lands a hair above 10 mm in
  // doubles (as 1.5 x 25 mm does above a 37.5 mm class): the class at the cut-off stays, and
  // a cut-off clearly above it drops it.
  Scene s = load_scene(scene_with("seed = 3", "seed = 3"));
  ASSERT_EQ(s.species_as_placed()[1].diameters_m.size(), 2u);
  s.solver.size_cutoff_m = 0.1 * 0.1;
  ASSERT_GT(s.solver.size_cutoff_m, s.charge.species[1].smallest_diameter_m());
  EXPECT_EQ(s.species_as_placed()[1].diameters_m.size(), 2u);
  s.solver.size_cutoff_m = 0.0101;
  EXPECT_EQ(s.species_as_placed()[1].diameters_m.size(), 1u);
}

TEST_F(SceneUnits, GatesGaudinSchuhmannGivesEachClassItsShareOfThePassingCurve) {
  const Scene s = load_scene(scene_with("sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]",
                                        "sizes = [20.0, 10.0, 5.0]\ndistribution = \"gates-gaudin-schuhmann\"\n"
                                        "top_size = 40.0\nexponent = 0.5"));
  // P(d) = sqrt(d / 40); classes split at sqrt(20 x 10) and sqrt(10 x 5); below 5 mm left out.
  auto p = [](double d) { return std::sqrt(d / 40.0); };
  const double b1 = std::sqrt(200.0), b2 = std::sqrt(50.0);
  const double total = 1.0 - p(5.0);
  const auto& f = s.charge.species[1].mass_fractions;
  ASSERT_EQ(f.size(), 3u);
  EXPECT_NEAR(f[0], (1.0 - p(b1)) / total, 1e-12);
  EXPECT_NEAR(f[1], (p(b1) - p(b2)) / total, 1e-12);
  EXPECT_NEAR(f[2], (p(b2) - p(5.0)) / total, 1e-12);
}

TEST_F(SceneUnits, RosinRammlerGivesEachClassItsShareOfThePassingCurve) {
  const Scene s = load_scene(scene_with("sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]",
                                        "sizes = [5.0, 20.0]\ndistribution = \"rosin-rammler\"\n"
                                        "size_63 = 12.0\nexponent = 1.2"));
  auto p = [](double d) { return 1.0 - std::exp(-std::pow(d / 12.0, 1.2)); };
  const double b = std::sqrt(100.0);
  const double total = 1.0 - p(5.0);
  const auto& f = s.charge.species[1].mass_fractions;
  ASSERT_EQ(f.size(), 2u);
  EXPECT_NEAR(f[0], (p(b) - p(5.0)) / total, 1e-12);  // in the order the sizes are given
  EXPECT_NEAR(f[1], (1.0 - p(b)) / total, 1e-12);
}

TEST_F(SceneUnits, ADistributionNeedsItsScaleAndNoListedFractions) {
  const std::string base = "sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]";
  std::string f = scene_with(base, "sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]\n"
                                   "distribution = \"rosin-rammler\"\nsize_63 = 12.0\nexponent = 1.0");
  expect_names(load_error(f), f, "charge.species[1].mass_fractions");
  f = scene_with(base, "sizes = [10.0, 20.0]\ndistribution = \"gates-gaudin-schuhmann\"\n"
                       "top_size = 15.0\nexponent = 0.8");
  expect_names(load_error(f), f, "charge.species[1].top_size");
  f = scene_with(base, "sizes = [10.0, 20.0]\ndistribution = \"gates-gaudin-schuhmann\"\nexponent = 0.8");
  expect_names(load_error(f), f, "charge.species[1].top_size");
  f = scene_with(base, "sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]\nexponent = 0.8");
  expect_names(load_error(f), f, "charge.species[1].exponent");
}

// Classes that would hold none of a species' mass (every fraction 0 / 0 once normalised) are
// refused naming the key that emptied them, not passed on as NaN disk counts.
TEST_F(SceneUnits, ClassesLeftWithNoMassAreRefusedNamingTheKey) {
  const std::string base = "sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]";
  // One class at the top size: it reaches from there up, where no rock is.
  std::string f =
      scene_with(base, "sizes = [20.0]\ndistribution = \"gates-gaudin-schuhmann\"\ntop_size = 20.0\nexponent = 0.5");
  expect_names(load_error(f), f, "charge.species[1].top_size");
  // Everything finer than the smallest class.
  f = scene_with(base, "sizes = [10.0, 20.0]\ndistribution = \"rosin-rammler\"\nsize_63 = 0.1\nexponent = 5.0");
  expect_names(load_error(f), f, "charge.species[1].size_63");
  // A cut-off that keeps only classes of no mass.
  std::string text = kBaseScene;
  text.replace(text.find(base), base.size(), "sizes = [10.0, 20.0]\nmass_fractions = [1.0, 0.0]");
  text.replace(text.find("seed = 3"), 8, "seed = 3\nsize_cutoff = 15.0");
  f = write("cut.toml", text);
  const InputError e = load_error(f);
  expect_names(e, f, "solver.size_cutoff");
  EXPECT_NE(e.expected.find("keeps some of the mass of charge.species[1] ('rock', largest size with mass 10 mm), got 15 mm"),
            std::string::npos)
      << e.what();
}

// A listed size with no share of the mass gets no disk: it sets neither the smallest radius
// (the time-step limit) nor the largest (the slice thickness).
TEST_F(SceneUnits, ASizeWithNoMassSetsNoLimit) {
  const Scene s = load_scene(scene_with("sizes = [10.0, 20.0]\nmass_fractions = [0.4, 0.6]",
                                        "sizes = [0.5, 10.0, 20.0, 40.0]\nmass_fractions = [0.0, 0.4, 0.6, 0.0]"));
  EXPECT_DOUBLE_EQ(s.smallest_particle_radius_m(), 0.005);
  EXPECT_DOUBLE_EQ(s.largest_particle_radius_m(), 0.010);
  EXPECT_DOUBLE_EQ(s.slice_thickness(), 0.020);
}

// A disk's species is one byte in the engines: 256 species are taken, a 257th is refused
// naming charge.species (it would have become species 0: another density and name).
TEST_F(SceneUnits, MoreSpeciesThanADiskCanNameAreRefused) {
  std::string extra;
  for (int k = 0; k < 254; ++k)
    extra += "[[charge.species]]\nname = \"r" + std::to_string(k) + "\"\ndensity = 2700.0\nsizes = [10.0]\n";
  const std::string at = "[solver]";
  std::string text = kBaseScene;
  text.insert(text.find(at), extra);
  const Scene taken = load_scene(write("scene.toml", text));
  ASSERT_EQ(taken.charge.species.size(), 256u);
  EXPECT_NO_THROW(check_filling(taken, taken.source_file));
  text.insert(text.find(at), "[[charge.species]]\nname = \"one-more\"\ndensity = 2700.0\nsizes = [10.0]\n");
  const std::string f = write("scene.toml", text);
  const Scene refused = load_scene(f);
  try {
    check_filling(refused, f);
    ADD_FAILURE() << "257 species taken";
  } catch (const InputError& e) {
    expect_names(e, f, "charge.species");
    EXPECT_NE(e.expected.find("at most 256 species"), std::string::npos) << e.expected;
  }
}

// A ball species with a size distribution gets --check's note too; and where the scale of
// the distribution lies far above the sizes (a mm / m slip), the note says how much of the
// mass the largest class holds from above its size.
TEST_F(SceneUnits, ANoteSaysWhatTheLargestClassHoldsFromAboveItsSize) {
  const Scene s = load_scene(scene_with(
      "sizes = [20.0]\nmass_fractions = [1.0]",
      "sizes = [15.0, 20.0]\ndistribution = \"rosin-rammler\"\nsize_63 = 20000.0\nexponent = 1.0"));
  const std::vector<std::string> notes = distribution_notes(s);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0].find("charge.species[0] ('ball')"), 0u) << notes[0];
  char coarse[96];
  std::snprintf(coarse, sizeof coarse, "the 20 mm class also holds the %.1f%% coarser than its size",
                100.0 * std::exp(-20.0 / 20000.0));
  EXPECT_NE(notes[0].find(coarse), std::string::npos) << notes[0];
}

// --check notes a charge whose heaviest disk is over a hundred times its lightest (beds of
// many light disks among heavy ones lose an occasional disk), with the time step against the
// limit that check_numerical_limits holds it to; the base scene (11.6 times) gets no note.
TEST_F(SceneUnits, AMassRatioPastTheSoundRangeIsNotedWithTheStepAgainstItsLimit) {
  const Scene base = load_scene(scene_with("seed = 3", "seed = 3"));
  EXPECT_NEAR(particle_mass_ratio(base), 7800.0 * 20.0 * 20.0 / (2700.0 * 10.0 * 10.0), 1e-9);
  EXPECT_TRUE(limit_notes(base).empty());

  Scene s = load_scene(scene_with("sizes = [10.0, 20.0]", "sizes = [1.0, 20.0]"));
  const double ratio = 7800.0 * 20.0 * 20.0 / (2700.0 * 1.0 * 1.0);
  EXPECT_NEAR(particle_mass_ratio(s), ratio, 1e-9 * ratio);
  // Four substeps of at most 1.6 smallest radii each: 6.4 radii a step, under the 8 a step.
  const double limit = 6.4 * 0.0005 / impact_speed_m_s(s);
  EXPECT_NEAR(time_step_limit_s(s), limit, 1e-12 * limit);
  s.solver.time_step_s = 1.01 * limit;
  EXPECT_THROW(check_numerical_limits(s, "scene.toml"), InputError);
  s.solver.time_step_s = 0.5 * limit;
  EXPECT_NO_THROW(check_numerical_limits(s, "scene.toml"));
  const std::vector<std::string> notes = limit_notes(s);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("the heaviest disk is 1156 times the lightest's mass"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("is 0.50 of the limit"), std::string::npos) << notes[0];
}

// A cut-off a hair above the largest rock is refused, and the message tells the two apart.
TEST_F(SceneUnits, ACutoffAboveTheLargestRockNamesBothSizesDistinctly) {
  std::string text = kBaseScene;
  text.replace(text.find("seed = 3"), 8, "seed = 3\nsize_cutoff = 20.00001");
  const std::string f = write("cut.toml", text);
  const InputError e = load_error(f);
  expect_names(e, f, "solver.size_cutoff");
  EXPECT_NE(e.expected.find("largest size with mass 20 mm), got 20.00001 mm"), std::string::npos) << e.what();
}

// ---------------------------------------------------------------------------------------
// Fidelity presets
// ---------------------------------------------------------------------------------------

TEST(SceneFidelityTable, PresetsHaveTheDocumentedValues) {
  const FidelityDef& d = fidelity_preset("draft");
  const FidelityDef& s = fidelity_preset("standard");
  const FidelityDef& r = fidelity_preset("reference");
  EXPECT_DOUBLE_EQ(d.time_step_s, 1.0 / 200.0);
  EXPECT_DOUBLE_EQ(s.time_step_s, 1.0 / 200.0);
  EXPECT_DOUBLE_EQ(r.time_step_s, 1.0 / 1000.0);
  EXPECT_DOUBLE_EQ(d.box2d_time_step_s, 1.0 / 300.0);
  EXPECT_DOUBLE_EQ(s.box2d_time_step_s, 1.0 / 400.0);
  EXPECT_DOUBLE_EQ(r.box2d_time_step_s, 1.0 / 1000.0);
  EXPECT_EQ(d.velocity_iterations, 6);
  EXPECT_EQ(r.position_iterations, 4);
  EXPECT_DOUBLE_EQ(d.window_revolutions, 1.0);
  EXPECT_DOUBLE_EQ(s.window_revolutions, 1.5);
  EXPECT_DOUBLE_EQ(r.window_revolutions, 4.0);
  EXPECT_DOUBLE_EQ(s.max_depth_step_m, 0.006);
  EXPECT_DOUBLE_EQ(r.max_depth_step_m, 0.002);
  for (const FidelityDef* p : {&d, &s, &r}) {
    EXPECT_EQ(p->backend, Backend::Soft) << p->name;
    EXPECT_EQ(p->substeps, 4) << p->name;
  }
  EXPECT_DOUBLE_EQ(d.shell_edge_m, 0.060);
  EXPECT_DOUBLE_EQ(r.lifter_edge_m, 0.010);
  EXPECT_DOUBLE_EQ(s.lifter_edge_m, 0.010);
  EXPECT_DOUBLE_EQ(s.shell_edge_m, 0.020);
}

// The defaults live in the scene's structs; `standard` is made of them, so a scene that
// names nothing gets the same numbers whether or not the preset is applied.
TEST(SceneFidelityTable, StandardIsTheSceneDefaults) {
  const Scene defaults;
  Scene s = defaults;
  apply_fidelity(s, "standard");
  EXPECT_EQ(s.solver.backend, defaults.solver.backend);
  EXPECT_EQ(s.solver.time_step_s, defaults.solver.time_step_s);
  EXPECT_EQ(s.solver.substeps, defaults.solver.substeps);
  EXPECT_EQ(s.solver.velocity_iterations, defaults.solver.velocity_iterations);
  EXPECT_EQ(s.solver.position_iterations, defaults.solver.position_iterations);
  EXPECT_EQ(s.solver.size_cutoff_m, defaults.solver.size_cutoff_m);
  EXPECT_EQ(s.wear.window_revolutions, defaults.wear.window_revolutions);
  EXPECT_EQ(s.wear.max_depth_step_m, defaults.wear.max_depth_step_m);
  EXPECT_EQ(s.wear.factor, defaults.wear.factor);
  EXPECT_EQ(s.mill.mesh.shell_edge_m, defaults.mill.mesh.shell_edge_m);
  EXPECT_EQ(s.mill.mesh.lifter_edge_m, defaults.mill.mesh.lifter_edge_m);
}

TEST(SceneFidelityTable, EachPresetIsFinerThanTheOneBefore) {
  const auto& p = fidelity_presets();
  ASSERT_EQ(p.size(), 3u);
  for (std::size_t i = 1; i < p.size(); ++i) {
    // Draft and standard share the step the ladder found harmless on the soft backend.
    EXPECT_LE(p[i].time_step_s, p[i - 1].time_step_s) << p[i].name;
    EXPECT_GE(p[i].substeps, p[i - 1].substeps) << p[i].name;
    EXPECT_GT(p[i].velocity_iterations, p[i - 1].velocity_iterations) << p[i].name;
    EXPECT_GT(p[i].position_iterations, p[i - 1].position_iterations) << p[i].name;
    EXPECT_GT(p[i].window_revolutions, p[i - 1].window_revolutions) << p[i].name;
    EXPECT_LT(p[i].max_depth_step_m, p[i - 1].max_depth_step_m) << p[i].name;
    EXPECT_LT(p[i].factor, p[i - 1].factor) << p[i].name;
    // Standard shares the reference's mesh (the knob the tradeoff found to matter most).
    EXPECT_LE(p[i].shell_edge_m, p[i - 1].shell_edge_m) << p[i].name;
    EXPECT_LE(p[i].lifter_edge_m, p[i - 1].lifter_edge_m) << p[i].name;
  }
}

TEST(SceneFidelityTable, UnknownPresetIsAnInputError) {
  Scene s;
  EXPECT_THROW(apply_fidelity(s, "sloppy"), InputError);
}

TEST_F(SceneFidelity, FilePresetFillsWhatTheSceneLeavesOut) {
  const Scene s = load_scene(scene_with("name = \"tiny\"", "name = \"tiny\"\nfidelity = \"reference\""));
  const FidelityDef& r = fidelity_preset("reference");
  EXPECT_EQ(s.fidelity, "reference");
  EXPECT_DOUBLE_EQ(s.solver.time_step_s, r.time_step_s);
  EXPECT_EQ(s.solver.velocity_iterations, r.velocity_iterations);
  EXPECT_DOUBLE_EQ(s.wear.window_revolutions, r.window_revolutions);
  EXPECT_DOUBLE_EQ(s.wear.max_depth_step_m, r.max_depth_step_m);
  EXPECT_DOUBLE_EQ(s.wear.factor, r.factor);
  EXPECT_DOUBLE_EQ(s.mill.mesh.shell_edge_m, r.shell_edge_m);
}

TEST_F(SceneFidelity, SceneKeysOverrideThePreset) {
  const std::string f = scene_with("seed = 3", "seed = 3\ntime_step = 0.0025\nvelocity_iterations = 7");
  Scene s = load_scene(f);
  EXPECT_DOUBLE_EQ(s.solver.time_step_s, 0.0025);
  EXPECT_EQ(s.solver.velocity_iterations, 7);
  // Switching preset later (e.g. --fidelity on the command line) keeps the file's choices
  // and changes the rest.
  apply_fidelity(s, "draft");
  EXPECT_EQ(s.fidelity, "draft");
  EXPECT_DOUBLE_EQ(s.solver.time_step_s, 0.0025);
  EXPECT_EQ(s.solver.velocity_iterations, 7);
  EXPECT_EQ(s.solver.position_iterations, fidelity_preset("draft").position_iterations);
}

TEST_F(SceneFidelity, TheBackendComesFromThePresetUnlessTheFileNamesOne) {
  Scene preset_backend = load_scene(write("scene.toml", kBaseScene));
  EXPECT_EQ(preset_backend.solver.backend, fidelity_preset(preset_backend.fidelity).backend);
  EXPECT_EQ(preset_backend.solver.substeps, fidelity_preset(preset_backend.fidelity).substeps);
  Scene library = load_scene(scene_with("seed = 3", "seed = 3\nbackend = \"box2d\"\nsubsteps = 7"));
  for (const char* p : {"draft", "standard", "reference"}) {
    apply_fidelity(library, p);
    EXPECT_EQ(library.solver.backend, Backend::Box2D) << p;
    EXPECT_EQ(library.solver.substeps, 7) << p;
  }
}

TEST_F(SceneFidelity, PresetsChangeTheSameSceneDifferently) {
  Scene s = load_scene(write("scene.toml", kBaseScene));
  apply_fidelity(s, "draft");
  const Scene draft = s;
  apply_fidelity(s, "reference");
  EXPECT_GT(draft.solver.time_step_s, s.solver.time_step_s);
  EXPECT_LT(draft.wear.window_revolutions, s.wear.window_revolutions);
  EXPECT_GT(draft.mill.mesh.lifter_edge_m, s.mill.mesh.lifter_edge_m);
}

// Seeds a command derives (s .. s + count - 1 for replicates) stay within what a scene file's
// solver.seed holds, 2^63 - 1, so that each seed a manifest records can be given back; past
// it the scene's seed is refused, naming the key and what asked for the seeds.
TEST(SceneSeeds, DerivedSeedsStayWithinWhatASceneHolds) {
  Scene s = load_scene(shipped("scenarios/lab-mill.toml"));
  const std::uint64_t max = 9223372036854775807ull;
  s.solver.seed = max - 2;
  EXPECT_NO_THROW(check_derived_seeds(s, 3, "--replicates 3"));
  try {
    check_derived_seeds(s, 4, "--replicates 4");
    FAIL() << "seed " << s.solver.seed << " + 3 was taken";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "solver.seed");
    EXPECT_NE(std::string(e.what()).find("--replicates 4 uses seeds s .. s + 3"), std::string::npos) << e.what();
  }
  s.solver.seed = 0;
  EXPECT_NO_THROW(check_derived_seeds(s, max, "a count up to the largest seed"));
}
