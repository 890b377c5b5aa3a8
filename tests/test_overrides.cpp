// `--set KEY=VALUE`: an override goes through the scene file's own readers, so every key type
// (float, integer, boolean, string, array, enumeration) is typed and range-checked as in the
// file, and every error names the key and the override; the command line exits 2 before
// anything is written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "cli_support.hpp"
#include "common/errors.hpp"
#include "common/units.hpp"
#include "scene/fidelity.hpp"
#include "scene/filling.hpp"
#include "scene/scene.hpp"
#include "temp_dir.hpp"
#include "tiny_scene.hpp"

namespace fs = std::filesystem;
using namespace millwear;
using millwear::testing::TempDir;
using millwear::testing::run_millwear;

namespace {

// The tiny scene turning both ways.
std::string bidirectional_scene() {
  std::string text = millwear::testing::kTinyScene;
  const std::string from = "direction = \"forward\"\n";
  text.replace(text.find(from), from.size(), "direction = \"bidirectional\"\nreverse_every = 100.0\n");
  return text;
}

class Overrides : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_ / "lifter.toml") << millwear::testing::kTinyLifter;
    std::ofstream(dir_ / "scene.toml") << bidirectional_scene();
    scene_ = (dir_ / "scene.toml").string();
  }

  Scene load(const std::vector<std::string>& sets) const { return load_scene(scene_, sets); }
  // The error of a set that must fail.
  InputError error_of(const std::vector<std::string>& sets) const {
    try {
      load(sets);
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no InputError for --set " << sets.back();
    return InputError("", "", "");
  }

  TempDir dir_{"millwear-set"};
  std::string scene_;
};

}  // namespace

TEST_F(Overrides, FloatIntegerBooleanStringArrayAndEnumTakeTheirValues) {
  const Scene s = load({"mill.speed=0.9", "lifters.rows=10", "wear.shell_wear=false", "name=renamed",
                        "charge.species[1].sizes=[12.0, 18.0]", "charge.species[1].mass_fractions=[0.5, 0.5]",
                        "solver.backend=box2d", "mill.direction=\"forward\"", "outputs.vtk=true"});
  EXPECT_DOUBLE_EQ(s.mill.speed_fraction_critical, 0.9);
  EXPECT_EQ(s.mill.rows, 10);
  EXPECT_FALSE(s.wear.shell_wear);
  EXPECT_EQ(s.name, "renamed");
  ASSERT_EQ(s.charge.species[1].diameters_m.size(), 2u);
  EXPECT_DOUBLE_EQ(s.charge.species[1].diameters_m[0], 0.012);
  EXPECT_DOUBLE_EQ(s.charge.species[1].mass_fractions[1], 0.5);
  EXPECT_EQ(s.solver.backend, Backend::Box2D);
  EXPECT_EQ(s.mill.direction, Direction::Forward);  // a one-way mill: reverse_every dropped
  EXPECT_TRUE(s.outputs.vtk);
  EXPECT_EQ(s.overrides.size(), 9u);
  // Unchanged keys keep the file's values.
  EXPECT_DOUBLE_EQ(s.charge.filling, 0.3);
  EXPECT_EQ(s.solver.seed, 3u);
}

TEST_F(Overrides, AMissingTableIsCreatedAndTheLastOfTwoSetsWins) {
  const Scene s = load({"run.revolutions=4", "run.revolutions=5.5"});
  EXPECT_DOUBLE_EQ(s.run.revolutions, 5.5);
}

TEST_F(Overrides, OneOfAPairReplacesTheFilesOther) {
  // The file has mill.speed; speed_rpm replaces it (both would be an error in a file).
  const Scene s = load({"mill.speed_rpm=30"});
  const double crit_rpm = std::sqrt(kGravity / 0.3) * 60.0 / (2.0 * kPi);
  EXPECT_NEAR(s.mill.speed_fraction_critical, 30.0 / crit_rpm, 1e-12);
  const Scene r = load({"charge.species[1].size_range=[10.0, 20.0]"});
  EXPECT_TRUE(r.charge.species[1].diameters_m.empty());
  EXPECT_DOUBLE_EQ(r.charge.species[1].d_max_m, 0.020);
}

TEST_F(Overrides, ASetKeyBeatsTheFidelityPresetAsAFileKeyDoes) {
  Scene s = load({"solver.time_step=0.0004"});
  apply_fidelity(s, "draft");
  EXPECT_DOUBLE_EQ(s.solver.time_step_s, 0.0004);
}

TEST_F(Overrides, UnknownKeyIsRefusedNamingItWithTheNearMiss) {
  const InputError e = error_of({"mill.sped=0.8"});
  EXPECT_EQ(e.file, scene_);
  EXPECT_EQ(e.where, "--set mill.sped=0.8: mill.sped");
  EXPECT_NE(e.expected.find("did you mean 'speed'"), std::string::npos) << e.what();
  // The value never was in the file: no line number.
  EXPECT_EQ(e.expected.find("(line"), std::string::npos) << e.what();
  EXPECT_EQ(error_of({"foo.bar=1"}).where, "--set foo.bar=1: foo");
}

TEST_F(Overrides, BadlyTypedValuesAreRefusedNamingTheKeyAndTheExpectation) {
  struct Case { const char* set; const char* key; const char* expected; };
  const Case cases[] = {
      {"mill.speed=fast", "mill.speed", "a number in [0.01, 2]"},        // float
      {"mill.speed=3", "mill.speed", "a number in [0.01, 2]"},           // float out of range
      {"lifters.rows=10.5", "lifters.rows", "an integer in [1, 1000]"},  // integer
      {"wear.shell_wear=yes", "wear.shell_wear", "true or false"},       // boolean
      {"name=[1]", "name", "a string"},                                   // string
      {"charge.species[1].sizes=[12.0, -1]", "charge.species[1].sizes[1]", "a number in [0.1, 20000]"},  // array
      {"mill.direction=sideways", "mill.direction", "\"forward\", \"reverse\" or \"bidirectional\""},     // enum
      {"outputs.vtk_frames=0", "outputs.vtk_frames", "an integer in [1, 1000]"},
      {"mill.speed=1e400", "mill.speed", "a number within a double's range"},  // not a string
      // Numbers TOML does not write so: not a string either, and not out of a double's range.
      {"mill.speed=.8", "mill.speed", "a number as TOML writes one (0.8 rather than .8"},
      {"wear.stages=99999999999999999999", "wear.stages", "a whole number up to 9.2e18"},
  };
  for (const Case& c : cases) {
    const InputError e = error_of({c.set});
    EXPECT_EQ(e.where, std::string("--set ") + c.set + ": " + c.key) << c.set;
    EXPECT_NE(e.expected.find(c.expected), std::string::npos) << c.set << ": " << e.what();
  }
}

TEST_F(Overrides, MalformedOverridesAreRefused) {
  EXPECT_EQ(error_of({"mill.speed"}).where, "--set mill.speed");
  EXPECT_EQ(error_of({"=0.8"}).where, "--set =0.8");
  EXPECT_NE(error_of({"charge.species[5].density=1000"}).expected.find("index below 2"), std::string::npos);
  EXPECT_NE(error_of({"mill.speed.x=1"}).expected.find("to be a table"), std::string::npos);
  EXPECT_NE(error_of({"mill..speed=1"}).expected.find("dotted scene key"), std::string::npos);
}

// A key the file sets that an override makes wrong (the file's ball filling above a filling
// the command line lowered) is named as the file's, with the overrides that changed the scene.
TEST_F(Overrides, AnotherKeysErrorNamesTheOverridesThatChangedTheScene) {
  const InputError e = error_of({"charge.filling=0.05"});
  EXPECT_EQ(e.where, "charge.ball_filling");
  EXPECT_NE(e.expected.find("(the scene with --set charge.filling=0.05)"), std::string::npos) << e.expected;
  // A sweep names the point whose value did it.
  const auto r = run_millwear("sweep " + millwear::testing::quoted(fs::path(scene_)) + " -o " +
                              millwear::testing::quoted(dir_ / "out") + " --vary charge.filling=0.2,0.05");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("charge.ball_filling (at --vary charge.filling=0.05)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("--set charge.filling"), std::string::npos) << "the point is its --vary: " << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(Overrides, TheCommandLineExitsTwoNamingTheKeyBeforeWritingAnything) {
  const fs::path out = dir_ / "out";
  const auto r = run_millwear("charge " + millwear::testing::quoted(fs::path(scene_)) + " -o " + millwear::testing::quoted(out) + " --set charge.filing=0.3");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--set charge.filing=0.3: charge.filing: unknown key (did you mean 'filling'?)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out));
  // Every command that reads a scene takes --set and checks it before any work.
  for (const std::string cmd : {"run", "sweep", "animate", "rule1", "tradeoff", "validate", "calibrate"}) {
    std::string args = cmd + " " + millwear::testing::quoted(fs::path(scene_)) + " --set mill.speed=fast";
    if (cmd == "animate") args += " -o " + millwear::testing::quoted(dir_ / "a.gif");
    if (cmd == "run" || cmd == "tradeoff" || cmd == "validate" || cmd == "sweep") args += " -o " + millwear::testing::quoted(out);
    if (cmd == "sweep") args += " --vary charge.filling=0.2,0.3";
    if (cmd == "validate" || cmd == "calibrate") args += " --measured " + millwear::testing::quoted(fs::path(scene_));
    const auto c = run_millwear(args);
    EXPECT_EQ(c.exit_code, 2) << cmd << ": " << c.output;
    EXPECT_NE(c.output.find("--set mill.speed=fast: mill.speed: expected a number"), std::string::npos)
        << cmd << ": " << c.output;
  }
  EXPECT_FALSE(fs::exists(out));
}

// A species' size keys switch it between a uniform range, listed fractions and a size
// distribution, and a distribution between its two forms, from the command line: each drops
// the file's keys of the other kind (setting size_range on a distribution was refused as a
// distribution without sizes, and fractions as fractions beside a distribution).
TEST(OverridesSpecies, ASpeciesSwitchesBetweenARangeFractionsAndADistribution) {
  const std::string fine = std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/sag-2x30-fine.toml";
  const std::string sp = "charge.species[1].";
  const Scene range = load_scene(fine, {sp + "size_range=[100.0, 250.0]"});
  EXPECT_TRUE(range.charge.species[1].diameters_m.empty());
  EXPECT_DOUBLE_EQ(range.charge.species[1].d_max_m, 0.25);
  const Scene listed = load_scene(fine, {sp + "mass_fractions=[0.125,0.125,0.125,0.125,0.125,0.125,0.125,0.125]"});
  EXPECT_EQ(listed.charge.species[1].distribution_held, 0.0);
  EXPECT_EQ(listed.charge.species[1].mass_fractions.front(), 0.125);
  const Scene rr = load_scene(fine, {sp + "distribution=rosin-rammler", sp + "size_63=100"});
  const SpeciesDef& rock = rr.charge.species[1];
  const std::vector<double> want =
      distribution_mass_fractions(SizeForm::RosinRammler, rock.diameters_m, 0.1, 0.8);
  ASSERT_EQ(rock.mass_fractions.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_DOUBLE_EQ(rock.mass_fractions[i], want[i]) << i;
  // And back (the form as a TOML literal string): a Rosin-Rammler species given the other
  // form drops its size_63.
  const Scene ggs = load_scene(fine, {sp + "distribution=rosin-rammler", sp + "size_63=100",
                                      sp + "distribution='gates-gaudin-schuhmann'", sp + "top_size=300"});
  EXPECT_DOUBLE_EQ(ggs.charge.species[1].mass_fractions.front(),
                   distribution_mass_fractions(SizeForm::GatesGaudinSchuhmann, rock.diameters_m, 0.3, 0.8).front());
  // A range becomes a distribution.
  const std::string sag = std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/sag-2x30.toml";
  const Scene from_range = load_scene(sag, {sp + "sizes=[200.0, 100.0]", sp + "distribution=gates-gaudin-schuhmann",
                                            sp + "top_size=250", sp + "exponent=0.8"});
  EXPECT_EQ(from_range.charge.species[1].diameters_m.size(), 2u);
  EXPECT_GT(from_range.charge.species[1].distribution_held, 0.0);
}

// A cut-off within a billionth above the largest size keeps that size, as the fill keeps a
// class at the cut-off; one further above is refused, printed so that the two sizes differ
// (nine digits printed 225.0000003 as 225, and refused 225.0000001, whose class the fill keeps).
TEST(OverridesSpecies, ACutOffAHairAboveTheLargestSizeKeepsItAndOneBeyondIsRefusedReadably) {
  const std::string fine = std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/sag-2x30-fine.toml";
  const Scene s = load_scene(fine, {"solver.size_cutoff=225.0000001"});
  EXPECT_EQ(s.species_as_placed()[1].diameters_m, std::vector<double>{0.225});
  try {
    load_scene(fine, {"solver.size_cutoff=225.0000003"});
    ADD_FAILURE() << "a cut-off above the largest size was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.expected.find("largest size with mass 225 mm), got 225.0000003 mm"), std::string::npos) << e.what();
  }
}

// Which of two overrides the later leaves nothing of: the same key (however its index is
// written), a key of its alternatives, a key its value removes, or a key inside the table or
// element it sets; not a neighbouring key, nor the later one's alternative in another table.
TEST(OverridesOrder, ALaterOverrideReplacesTheSameKeyItsAlternativesAndWhatItHolds) {
  EXPECT_TRUE(override_replaces("mill.speed=0.7", "mill.speed=0.6"));
  EXPECT_TRUE(override_replaces("mill.speed=0.7", "mill.speed =abc"));
  EXPECT_TRUE(override_replaces("mill.speed=0.7", "mill.speed_rpm=10"));
  EXPECT_TRUE(override_replaces("solver.steps_per_second=2000", "solver.time_step=0.001"));
  EXPECT_TRUE(override_replaces("wear.area_loss_rate=1", "wear.height_loss_rate=2"));
  EXPECT_TRUE(override_replaces("charge.species[1].density=2800", "charge.species[01].density=2700"));
  EXPECT_TRUE(override_replaces("charge.species[1].size_range=[100.0, 200.0]", "charge.species[1].sizes=[150.0]"));
  EXPECT_TRUE(override_replaces("charge.species[1].distribution=rosin-rammler", "charge.species[1].top_size=300"));
  EXPECT_TRUE(override_replaces("mill.direction=forward", "mill.reverse_every=10"));
  EXPECT_TRUE(override_replaces("charge.species[1]={density=2700}", "charge.species[1].density=2800"));

  EXPECT_FALSE(override_replaces("mill.speed=0.7", "mill.diameter=5"));
  EXPECT_FALSE(override_replaces("charge.species[0].density=2800", "charge.species[1].density=2800"));
  EXPECT_FALSE(override_replaces("charge.species[1].distribution=rosin-rammler", "charge.species[1].size_63=100"));
  EXPECT_FALSE(override_replaces("mill.direction=bidirectional", "mill.reverse_every=10"));
  EXPECT_FALSE(override_replaces("charge.species[1].density=2800", "charge.species[1]={density=2700}"));
  EXPECT_FALSE(override_replaces("solver.speed_rpm=1", "mill.speed=0.7"));
  EXPECT_FALSE(override_replaces("mill.speed=0.7", "no equals sign"));
}
