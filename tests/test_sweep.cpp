// `millwear sweep`: the values of --vary, every point checked before any work, and the
// classic power curve of a tumbling mill: power rises with speed to a peak below critical
// and falls as the charge centrifuges (lab mill, draft fidelity, short windows).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <csignal>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_support.hpp"
#include "common/errors.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "io/staging.hpp"
#include "scene/scene.hpp"
#include "study/charge_run.hpp"
#include "study/sweep.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;
using namespace millwear;

namespace {

std::string shipped(const std::string& rel) { return std::string(MILLWEAR_SOURCE_DIR) + "/" + rel; }

}  // namespace

TEST(SweepVary, ARangeIncludesItsLastValueWrittenWithoutRoundingNoise) {
  const study::SweepAxis a = study::parse_vary("mill.speed=0.5:1.6:0.1");
  EXPECT_EQ(a.key, "mill.speed");
  ASSERT_EQ(a.values.size(), 12u);
  EXPECT_EQ(a.texts[2], "0.7");
  EXPECT_EQ(a.texts.back(), "1.6");
  EXPECT_DOUBLE_EQ(a.values.back(), 1.6);
}

// A range's values are those typed, to every digit: FIRST and STEP written to 13 digits, or
// seeds of 13 digits, are swept as written, not rounded to 12 significant digits (a seed of
// 1000000000001 as 1e+12, which solver.seed then refuses as no integer).
TEST(SweepVary, ARangeKeepsEveryDigitOfItsValues) {
  const study::SweepAxis seeds = study::parse_vary("solver.seed=1000000000000:1000000000003:1");
  EXPECT_EQ(seeds.texts, (std::vector<std::string>{"1000000000000", "1000000000001", "1000000000002", "1000000000003"}));
  const study::SweepAxis fine = study::parse_vary("mill.speed=0.1234567890123:0.2234567890123:0.05");
  ASSERT_EQ(fine.texts.size(), 3u);
  EXPECT_EQ(fine.texts.front(), "0.1234567890123");
  EXPECT_EQ(fine.texts[1], "0.1734567890123");
  EXPECT_EQ(fine.texts.back(), "0.2234567890123");
  EXPECT_EQ(fine.values.back(), 0.2234567890123);
  // Written with an exponent, the values are rounded to 12 significant digits.
  EXPECT_EQ(study::parse_vary("mill.speed=5e-1:7e-1:1e-1").texts, (std::vector<std::string>{"0.5", "0.6", "0.7"}));
}

namespace {

// A --vary of mill.speed parse_vary refuses, naming the --vary and saying `says`.
void expect_speed_vary_refused(const std::string& vary, const std::string& says) {
  try {
    study::parse_vary(vary);
    ADD_FAILURE() << "accepted: " << vary;
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--vary mill.speed");
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

}  // namespace

// LAST is one of the values: steps that pass it are refused, naming the two values around it.
TEST(SweepVary, ARangeWhoseStepsPassItsLastValueIsRefused) {
  expect_speed_vary_refused("mill.speed=0.5:1.0:0.3", "the values go 0.8, then 1.1");
  EXPECT_EQ(study::parse_vary("mill.speed=0.5:1.1:0.3").texts.back(), "1.1");
}

TEST(SweepVary, AListKeepsItsValuesAsWritten) {
  const study::SweepAxis a = study::parse_vary("lifters.rows=10, 12,16");
  ASSERT_EQ(a.texts.size(), 3u);
  EXPECT_EQ(a.texts[1], "12");
  EXPECT_DOUBLE_EQ(a.values[2], 16.0);
}

// A sweep is a curve: a list typed out of order is swept, tabled and drawn in ascending
// order, each value kept as typed, so the figures' lines do not double back.
TEST(SweepVary, AListIsSweptInAscendingOrder) {
  const study::SweepAxis a = study::parse_vary("mill.speed=0.8, 0.50,0.65,-0");
  ASSERT_EQ(a.texts.size(), 4u);
  EXPECT_EQ(a.texts, (std::vector<std::string>{"-0", "0.50", "0.65", "0.8"}));
  for (std::size_t k = 0; k + 1 < a.values.size(); ++k) EXPECT_LT(a.values[k], a.values[k + 1]) << k;
}

// Seeds run to 2^63 - 1; past 2^53 two seeds one apart are one double: a list of them was
// refused as a value listed twice, and a range of them ran other seeds than it said.
TEST(SweepVary, SeedsPastWhatADoubleHoldsAreToldApartAndOrdered) {
  const study::SweepAxis a = study::parse_vary("solver.seed=9007199254740993,9007199254740994,9007199254740992");
  EXPECT_EQ(a.texts, (std::vector<std::string>{"9007199254740992", "9007199254740993", "9007199254740994"}));
  // A range of them steps exactly (in doubles 9007199254740993 + 3 ran 9007199254740992 + 3).
  EXPECT_EQ(study::parse_vary("solver.seed=9007199254740993:9007199254741002:3").texts,
            (std::vector<std::string>{"9007199254740993", "9007199254740996", "9007199254740999", "9007199254741002"}));
  EXPECT_EQ(study::parse_vary("solver.seed=9223372036854775805:9223372036854775807:1").texts.back(), "9223372036854775807");
  EXPECT_EQ(study::parse_vary("solver.substeps=-2:2:2").texts, (std::vector<std::string>{"-2", "0", "2"}));
  expect_speed_vary_refused("mill.speed=9007199254740993:9007199254740996:2",
                            "the values go 9007199254740995, then 9007199254740997");
  try {
    study::parse_vary("solver.seed=9223372036854775806,9223372036854775806");
    ADD_FAILURE() << "a seed listed twice was swept";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("each value once"), std::string::npos) << e.what();
  }
}

// sweep.csv names each point by the seed it ran, where a double cannot hold the seed: two seeds
// one apart past 2^53 read as one (the second's), so one seed had two results.
TEST(SweepCharge, TheTableNamesSeedsPastWhatADoubleHoldsAsTheyRan) {
  const TempDir out("millwear-sweep-big-seeds");
  const auto r = millwear::testing::run_millwear(
      "sweep " + millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " +
      millwear::testing::quoted(out) + " --vary solver.seed=12345678901234567,12345678901234568 " +
      "--revolutions 0.2 --fidelity draft -j 2 --no-plot -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData t = io::read_csv((out / "sweep.csv").string());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.text(0, t.column("value")), "12345678901234567");
  EXPECT_EQ(t.text(1, t.column("value")), "12345678901234568");
}

// The same value twice would run the same charge twice: refused, naming both as written.
TEST(SweepVary, AValueListedTwiceIsRefused) {
  expect_speed_vary_refused("mill.speed=0.6, 0.7,0.60", "each value once, got 0.6 and 0.60");
  // Two texts the scene reads as one double are one value; seeds past 2^53 stay apart.
  expect_speed_vary_refused("mill.speed=0.6,0.60000000000000001",
                            "each value once, got 0.6 and 0.60000000000000001");
  EXPECT_EQ(study::parse_vary("solver.seed=9007199254740992,9007199254740993").values.size(), 2u);
}

// A sweep runs the charge alone: a key of [wear] would give the same point at every value.
TEST(SweepVary, AWearKeyIsRefusedAsOneTheChargeDoesNotRead) {
  try {
    study::parse_vary("wear.stage_hours=10,20");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--vary wear.stage_hours");
    EXPECT_NE(std::string(e.what()).find("a sweep runs the charge alone"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(study::parse_vary("charge.filling=0.2,0.3"));
}

// Nor do the keys of a wear history outside [wear], what is written, the other backend's
// solver settings, or the revolutions --revolutions sets for every point: each is refused
// before any point runs, naming the --vary and why.
TEST(SweepVary, AKeyTheSweepsChargeDoesNotReadIsRefused) {
  for (const char* vary : {"outputs.vtk_frames=5,10", "lifters.start_hours=0,100", "mill.reverse_every=10,50"})
    try {
      study::parse_vary(vary);
      ADD_FAILURE() << "accepted: " << vary;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where, "--vary " + std::string(vary).substr(0, std::string(vary).find('='))) << e.what();
      EXPECT_NE(std::string(e.what()).find("every value gives the same point"), std::string::npos) << e.what();
    }
  const auto refused = [](const std::string& vary, double revolutions, const std::vector<std::string>& sets) {
    study::SweepRequest q;
    q.scene_file = shipped("scenarios/lab-mill.toml");
    q.vary = vary;
    q.revolutions = revolutions;
    q.overrides = sets;
    try {
      study::sweep_scenes(q, study::parse_vary(q.vary));
    } catch (const InputError& e) {
      EXPECT_EQ(e.where, "--vary " + vary.substr(0, vary.find('='))) << e.what();
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused("solver.velocity_iterations=4,8", 0.0, {}).find("backend (soft) does not read"), std::string::npos);
  EXPECT_NE(refused("solver.substeps=2,8", 0.0, {"solver.backend=\"box2d\"", "solver.time_step=0.0005"})
                .find("backend (box2d) does not read"),
            std::string::npos);
  EXPECT_NE(refused("run.revolutions=1,2", 0.5, {}).find("--revolutions 0.5 sets every point's"), std::string::npos);
  // What each backend reads, and the revolutions without --revolutions, are swept.
  EXPECT_EQ(refused("solver.substeps=2,8", 0.0, {}), "");
  EXPECT_EQ(refused("solver.velocity_iterations=4,8", 0.0, {"solver.backend=\"box2d\"", "solver.time_step=0.0005"}), "");
  EXPECT_EQ(refused("run.revolutions=1,2", 0.0, {}), "");
}

// The varied value goes in after the --set overrides, so one of the same key, or of a key the
// value replaces, would be dropped at every point while the manifest still lists it: refused
// before any point runs, naming the --set.
TEST(SweepVary, ASetTheVariedValueReplacesIsRefused) {
  const auto refused = [](const std::string& vary, const std::vector<std::string>& sets) {
    study::SweepRequest q;
    q.scene_file = shipped("scenarios/lab-mill.toml");
    q.vary = vary;
    q.overrides = sets;
    try {
      study::sweep_scenes(q, study::parse_vary(q.vary));
    } catch (const InputError& e) {
      return e.where + ": " + e.expected;
    }
    return std::string();
  };
  EXPECT_EQ(refused("mill.speed=0.6,0.7", {"mill.speed=0.9"}),
            "--set mill.speed=0.9: a key --vary mill.speed leaves in place: the varied value replaces it at every point");
  EXPECT_EQ(refused("mill.speed=0.6,0.7", {"mill.diameter=0.5", "mill.speed_rpm=40"}).substr(0, 23),
            "--set mill.speed_rpm=40");
  EXPECT_EQ(refused("solver.steps_per_second=2000,4000", {"solver.time_step=abc"}).substr(0, 25),
            "--set solver.time_step=ab");
  EXPECT_EQ(refused("charge.species[0].density=7000,7800", {"charge.species[0].density=7500"}).substr(0, 36),
            "--set charge.species[0].density=7500");
  // Other keys are kept, whatever their order.
  EXPECT_EQ(refused("mill.speed=0.6,0.7", {"charge.species[0].density=7500", "mill.diameter=0.5"}), "");
}

// Replicate K of a point runs seed + K - 1: seeds swept closer than the replicates would run
// one charge in two points, and are refused naming the pair; seeds that far apart are swept.
TEST(SweepVary, SeedsCloserThanTheReplicatesAreRefused) {
  const auto refused = [](const std::string& vary, int replicates) {
    study::SweepRequest q;
    q.scene_file = shipped("scenarios/lab-mill.toml");
    q.vary = vary;
    q.replicates = replicates;
    try {
      study::sweep_scenes(q, study::parse_vary(q.vary));
    } catch (const InputError& e) {
      EXPECT_EQ(e.where, "--vary solver.seed") << e.what();
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused("solver.seed=1,2", 2).find("got 1 and 2"), std::string::npos);
  EXPECT_NE(refused("solver.seed=1:9:4", 5).find("got 1 and 5"), std::string::npos);
  EXPECT_NE(refused("solver.seed=10,1,3", 3).find("got 1 and 3, which would run the same charges"), std::string::npos)
      << refused("solver.seed=10,1,3", 3);
  EXPECT_EQ(refused("solver.seed=10,1,4", 3), "");
  EXPECT_EQ(refused("solver.seed=1,3", 2), "");
  EXPECT_EQ(refused("solver.seed=1,2", 1), "");
  EXPECT_EQ(refused("mill.speed=0.6,0.7", 4), "");
}

TEST(SweepVary, MalformedVariesAreRefused) {
  for (const char* bad : {"mill.speed", "=0.5:1:0.1", "mill.speed=0.5:1", "mill.speed=1:0.5:0.1",
                          "mill.speed=0.5:1:0", "mill.speed=0.5,fast", "mill.speed=0:1000:0.001"})
    EXPECT_THROW(study::parse_vary(bad), InputError) << bad;
}

TEST(SweepVary, AValueOutsideTheKeysRangeIsRefusedNamingTheVary) {
  study::SweepRequest q;
  q.scene_file = shipped("scenarios/lab-mill.toml");
  q.vary = "mill.speed=0.5,2.5";
  try {
    study::sweep_scenes(q, study::parse_vary(q.vary));
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--vary mill.speed=2.5: mill.speed") << e.what();
    EXPECT_NE(e.expected.find("in [0.01, 2]"), std::string::npos) << e.what();
  }
}

// A value inside the key's range that breaks a limit of the scene as a whole: the refusal
// names the limit's key and the point.
TEST(SweepVary, APointPastAScenesLimitIsRefusedNamingThePoint) {
  study::SweepRequest q;
  q.scene_file = shipped("scenarios/lab-mill.toml");
  q.vary = "solver.time_step=0.001,0.02";  // in the key's range, past the lab mill's step limit
  try {
    study::sweep_scenes(q, study::parse_vary(q.vary));
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "solver.time_step (at --vary solver.time_step=0.02)") << e.what();
  }
}

// The window stepped in pieces (batches, ParaView frames) takes the same steps as in one.
TEST(SweepCharge, FramesAndBatchesDoNotChangeTheFigures) {
  Scene s = load_scene(shipped("scenarios/lab-mill.toml"), {"run.revolutions=0.5"});
  const ChargeRunResult plain = run_charge_only(s);
  s.outputs.vtk = true;
  s.outputs.vtk_frames = 7;
  const ChargeRunResult framed = run_charge_only(s);
  EXPECT_EQ(plain.figures.power_kW_per_m, framed.figures.power_kW_per_m);
  EXPECT_EQ(plain.figures.collision_kW_per_m, framed.figures.collision_kW_per_m);
  EXPECT_EQ(plain.final_state.position_m[0].x, framed.final_state.position_m[0].x);
  EXPECT_TRUE(plain.frames.empty());
  EXPECT_EQ(framed.frames.size(), 8u);  // 7 rounded up to whole frames per batch (4 x 2)
  ASSERT_EQ(framed.batches.size(), 4u);
  // The batches add up to the window: mean of equal batches = the window's power.
  double mean = 0;
  for (const auto& b : framed.batches) mean += b.power_kW_per_m / 4.0;
  EXPECT_NEAR(mean, framed.figures.power_kW_per_m, 0.02 * std::abs(framed.figures.power_kW_per_m));
}

// Power against speed on the lab mill: at half critical the charge cascades; near 0.85 it
// cataracts and draws the most; at 1.6 of critical it rides round with the shell and the
// drive does almost no work. The margins are three standard errors of the difference. (Three
// revolutions of spin-up: at 1.6 of critical the charge takes over one to settle on the shell.)
TEST(SweepCharge, PowerRisesToAPeakBelowCriticalAndFallsAsTheChargeCentrifuges) {
  const TempDir out("millwear-sweep-speed");
  const auto r = millwear::testing::run_millwear(
      "sweep " + millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " +
      millwear::testing::quoted(out) + " --vary mill.speed=0.5,0.85,1.6 --revolutions 2 --fidelity draft " +
      "--set solver.seed=2 --set solver.spinup_revolutions=3 -j 2 --no-plot -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData t = io::read_csv((out / "sweep.csv").string());
  ASSERT_EQ(t.rows.size(), 3u);
  const auto col = [&](const char* name, std::size_t row) { return t.number(row, name); };
  const double p_low = col("power_kW", 0), p_mid = col("power_kW", 1), p_high = col("power_kW", 2);
  const auto margin = [&](std::size_t a, std::size_t b) {
    return 3.0 * std::hypot(col("power_kW_sem", a), col("power_kW_sem", b));
  };
  EXPECT_GT(p_mid - p_low, margin(0, 1)) << r.output;
  EXPECT_GT(p_mid - p_high, margin(1, 2)) << r.output;
  // Past critical the charge covers the whole shell: no toe or shoulder, and the table says so.
  EXPECT_EQ(t.text(2, t.column("toe_deg")), "centrifuged");
  EXPECT_EQ(t.text(2, t.column("shoulder_deg")), "centrifuged");
  EXPECT_EQ(t.text(2, t.column("centrifuged")), "1");
  EXPECT_EQ(t.text(2, t.column("liner_impact_share")), "centrifuged");
  for (std::size_t row : {0u, 1u}) {
    EXPECT_EQ(t.text(row, t.column("centrifuged")), "0");
    EXPECT_GE(col("liner_impact_share", row), 0.0);  // a share of the impact energy
    EXPECT_LE(col("liner_impact_share", row), 1.0);
    EXPECT_LT(col("toe_deg", row), 0.0);        // the toe on the falling side of 6 o'clock
    EXPECT_GT(col("shoulder_deg", row), 90.0);  // the shoulder above 3 o'clock on the rising side
  }
  // Specific power is power over the same charge mass at every speed.
  EXPECT_NEAR(col("charge_t", 0), col("charge_t", 2), 0.01 * col("charge_t", 0));
  EXPECT_NEAR(col("specific_power_kW_per_t", 1) * col("charge_t", 1), p_mid, 1e-6 * p_mid);
  // The manifest records the override and the values; each point keeps its charge files.
  const std::string manifest = millwear::testing::read_text(out / "manifest.json");
  EXPECT_NE(manifest.find("\"solver.seed=2\""), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"0.85\""), std::string::npos) << manifest;
  EXPECT_TRUE(fs::exists(out / "points" / "02" / "charge_summary.csv"));
  // A point whose disk-disk contacts gave the charge energy is warned of, and only such a point
  // (the centrifuged bed's, docs/stability.md).
  for (std::size_t row = 0; row < t.rows.size(); ++row) {
    const std::string said = "mill.speed = " + t.text(row, t.column("value")) + ": the contacts between disks gave";
    EXPECT_EQ(r.output.find(said) != std::string::npos, col("collision_power_kW", row) < 0.0) << said << "\n" << r.output;
  }
}

// A point whose charge was still settling in its window is warned of, naming the point, as
// `millwear charge` of its scene warns (lab mill at 1.9 of critical, three revolutions of
// spin-up, one measured: most of the drive's power goes into the charge's energy); the
// steady point is not.
TEST(SweepCharge, APointWhoseChargeWasNotSteadyIsWarnedOf) {
  const TempDir out("millwear-sweep-unsteady");
  const std::string args = millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " +
                           millwear::testing::quoted(out) +
                           " --set solver.spinup_revolutions=3 --revolutions 1 --fidelity draft -q";
  const auto charge = millwear::testing::run_millwear("charge " + args + " --set mill.speed=1.9");
  ASSERT_EQ(charge.exit_code, 0) << charge.output;
  ASSERT_NE(charge.output.find("the charge was not steady in the window"), std::string::npos) << charge.output;
  fs::remove_all(out.path());
  const auto r = millwear::testing::run_millwear("sweep " + args + " --vary mill.speed=0.75,1.9 -j 2 --no-plot");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: mill.speed = 1.9: the charge was not steady in the window"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("mill.speed = 0.75: the charge was not steady"), std::string::npos) << r.output;
}

TEST(SweepReplicates, FoldedIntoTheMeanAndTheStandardErrorOfTheMean) {
  std::vector<study::SweepPoint> reps(4);
  const double power[] = {10.0, 12.0, 14.0, 16.0};
  for (int k = 0; k < 4; ++k) {
    reps[k].power_kW = power[k];
    reps[k].power_kW_sem = 0.1;  // each charge's own batch-means error is not the spread
    reps[k].charge_t = 2.0;
    reps[k].lost_disks = k == 2 ? 1 : 0;
  }
  reps[3].centrifuged = true;
  reps[1].error = "a lost disk";
  const study::SweepPoint p = study::fold_replicates(reps);
  EXPECT_EQ(p.replicates, 4);
  EXPECT_DOUBLE_EQ(p.power_kW, 13.0);
  // Sample sd of 10, 12, 14, 16 is sqrt(20/3); over sqrt(4).
  EXPECT_NEAR(p.power_kW_sem, std::sqrt(20.0 / 3.0) / 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.charge_t, 2.0);
  EXPECT_EQ(p.lost_disks, 1u);
  EXPECT_TRUE(p.centrifuged);
  EXPECT_EQ(p.error, "a lost disk");
}

// Replicates of a point run its scene with seeds s, s+1, ...: each replicate's charge files in
// its own folder, the table's errors from their spread.
TEST(SweepReplicates, EachValueRunsItsReplicatesAndTheTableSaysWhereItsErrorsComeFrom) {
  const TempDir out("millwear-sweep-replicates");
  const auto r = millwear::testing::run_millwear(
      "sweep " + millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " +
      millwear::testing::quoted(out) + " --vary mill.speed=0.7 --revolutions 0.5 --fidelity draft " +
      "--replicates 3 -j 2 --no-plot -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData t = io::read_csv((out / "sweep.csv").string());
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.text(0, t.column("replicates")), "3");
  EXPECT_EQ(t.text(0, t.column("error_source")), "replicates");
  std::vector<double> power;
  for (const char* dir : {"00", "00.r2", "00.r3"}) {
    const io::CsvData s = io::read_csv((out / "points" / dir / "charge_summary.csv").string());
    bool value_recorded = false;  // a point's folder says which point it is
    for (std::size_t i = 0; i < s.rows.size(); ++i) {
      if (s.text(i, 0) == "power_per_mill") power.push_back(s.number(i, 1));
      value_recorded = value_recorded || (s.text(i, 0) == "set" && s.text(i, 1) == "mill.speed=0.7");
    }
    EXPECT_TRUE(value_recorded) << dir;
  }
  ASSERT_EQ(power.size(), 3u);
  EXPECT_NE(power[0], power[1]);  // another seed, another charge
  const double mean = (power[0] + power[1] + power[2]) / 3.0;
  double var = 0.0;
  for (double x : power) var += (x - mean) * (x - mean) / 2.0;
  // The point's figure is the replicates' mean, its error the standard error of that mean.
  EXPECT_NEAR(t.number(0, "power_kW"), mean, 1e-6 * std::abs(mean));
  EXPECT_NEAR(t.number(0, "power_kW_sem"), std::sqrt(var / 3.0), 1e-6 * std::abs(mean));
}

// A sweep again into its folder: the earlier sweep's points (a value it no longer has) and
// files go first; a user's own file in a point's folder stays, and the manifest lists only
// what this sweep wrote.
TEST(SweepFolder, ASweepAgainRemovesTheEarlierSweepsPointsAndKeepsTheUsersFiles) {
  const TempDir out("millwear-sweep-again");
  const std::string base = "sweep " + millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " +
                           millwear::testing::quoted(out) + " --revolutions 0.5 --fidelity draft --no-plot -q";
  auto r = millwear::testing::run_millwear(base + " --vary mill.speed=0.6,0.7,0.8");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "points/02/charge_summary.csv"));
  std::ofstream(out / "points/01/my-notes.txt") << "the user's\n";
  r = millwear::testing::run_millwear(base + " --vary mill.speed=0.6,0.7");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "points/02")) << "the earlier sweep's third point";
  std::ifstream notes(out / "points/01/my-notes.txt");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(notes), {}), "the user's\n");
  const std::string manifest = millwear::testing::read_text(out / "manifest.json");
  EXPECT_EQ(manifest.find("my-notes.txt"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("points/01/charge_summary.csv"), std::string::npos) << manifest;
}

// A sweep with figures lists gnuplot's log in its manifest, so a sweep without figures into the
// folder removes it with the earlier figures (it stayed, unlisted).
TEST(SweepFolder, ASweepWithoutFiguresRemovesTheEarlierSweepsGnuplotLog) {
  const TempDir out("millwear-sweep-log");
  const std::string base = "sweep " + millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " +
                           millwear::testing::quoted(out) + " --revolutions 0.1 --fidelity draft -q --vary mill.speed=0.6,0.7";
  auto r = millwear::testing::run_millwear(base);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "plots/gnuplot.log"));
  EXPECT_NE(millwear::testing::read_text(out / "manifest.json").find("plots/gnuplot.log"), std::string::npos);
  r = millwear::testing::run_millwear(base + " --no-plot");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "plots/sweep_power.png"));
  EXPECT_FALSE(fs::exists(out / "plots/gnuplot.log"));
}

// A sweep killed part-way (SIGKILL: no chance to clean up) writes nothing into OUT: the points
// it finished are in its staging folder, which the next sweep into the folder clears, so none
// of them stays beside the new results.
TEST(SweepFolder, ThePointsOfASweepKilledPartWayDoNotOutliveIt) {
  const TempDir dir("millwear-sweep-killed");
  const fs::path out = dir / "out";
  const fs::path staging = out / io::kStagingName;
  const std::string lab = millwear::testing::quoted(shipped("scenarios/lab-mill.toml"));
  const std::string cmd = "exec \"" + std::string(MILLWEAR_BINARY) + "\" sweep " + lab + " -o " +
                          millwear::testing::quoted(out) + " --vary mill.speed=0.5:1.0:0.1 -j 1 --revolutions 2 -q "
                          "--no-plot > /dev/null 2>&1";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Killed once two points (of six) are written.
  bool written = false;
  for (int i = 0; i < 1200 && !written; ++i) {
    written = fs::exists(staging / "points/01/charge_summary.csv");
    if (!written) ::usleep(20000);
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(written) << "two points were not written within 24 s";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the sweep finished before it was killed";
  EXPECT_EQ(io::visible_entries(out.string()), std::vector<std::string>{}) << "nothing in OUT";

  const auto r = millwear::testing::run_millwear("sweep " + lab + " -o " + millwear::testing::quoted(out) +
                                                 " --vary mill.speed=0.8 -j 1 --revolutions 2 -q --no-plot");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "points" / "00" / "charge_summary.csv"));
  for (const char* stale : {"01", "02", "03", "04", "05"}) EXPECT_FALSE(fs::exists(out / "points" / stale)) << stale;
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_EQ(io::read_csv((out / "sweep.csv").string()).row_count(), 1u);
}

// Two values one rounding apart are two points: sweep.csv writes each as the fewest digits
// that read back as it, so they do not print alike, and a value as typed stays as typed.
TEST(SweepFolder, ValuesOneRoundingApartAreWrittenApart) {
  const TempDir out("millwear-sweep-close");
  const auto r = millwear::testing::run_millwear(
      "sweep " + millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " +
      millwear::testing::quoted(out) + " --vary mill.speed=0.7,0.7000000000000001 --revolutions 2 --fidelity draft " +
      "-j 2 --no-plot -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData t = io::read_csv((out / "sweep.csv").string());
  ASSERT_EQ(t.row_count(), 2u);
  EXPECT_EQ(t.text(0, t.column("value")), "0.7");
  EXPECT_EQ(t.text(1, t.column("value")), "0.7000000000000001");
}

// Ctrl-C (here `timeout`'s SIGINT) stops a sweep as the signal does (exit 130), saying first
// what it leaves: nothing of its own in OUT.
TEST(SweepFolder, AnInterruptedSweepSaysWhatItLeaves) {
  const TempDir dir("millwear-sweep-interrupted");
  const auto r = millwear::testing::run_shell(
      "timeout --preserve-status -s INT 2 \"" + std::string(MILLWEAR_BINARY) + "\" sweep " +
      millwear::testing::quoted(shipped("scenarios/lab-mill.toml")) + " -o " + millwear::testing::quoted(dir / "out") +
      " --vary mill.speed=0.5:1.6:0.1 -j 1 --revolutions 2 -q --no-plot");
  EXPECT_EQ(r.exit_code, 128 + SIGINT) << r.output;
  EXPECT_NE(r.output.find("millwear sweep: interrupted; nothing of this sweep is kept, " + (dir / "out").string() +
                          " is as it was"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "sweep.csv"));
}
