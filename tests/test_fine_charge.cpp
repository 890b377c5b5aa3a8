// Fine charges: a rock size distribution down to 25 mm fills the SAG mill to its filling
// and mass fractions, and the charge turns without losing a disk.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <string>
#include <vector>

#include "common/units.hpp"
#include "engine/engine.hpp"
#include "engine_fixtures.hpp"
#include "scene/filling.hpp"
#include "scene/fidelity.hpp"

using namespace millwear;

namespace {

Scene fine_sag() {
  Scene scene = load_scene(millwear::testing::source_path("scenarios/sag-2x30-fine.toml"));
  apply_fidelity(scene, "draft");
  scene.solver.backend = Backend::Soft;
  return scene;
}

}  // namespace

// Each size class gets its share of the rock area (mass fraction x species area / disk
// area) within one disk (the counts are whole disks: filling.hpp), the filling places exactly
// those counts, and the fractions follow the passing curve the scene names.
TEST(FineCharge, TwentyFiveMillimetreSagChargeFillsToItsFillingAndMassFractions) {
  const Scene scene = fine_sag();
  const auto species = scene.species_as_placed();
  ASSERT_EQ(species.size(), 2u);
  const SpeciesDef& rock = species[1];
  ASSERT_EQ(rock.diameters_m.size(), 8u);
  EXPECT_DOUBLE_EQ(scene.smallest_particle_radius_m(), 0.0125);
  // Gates-Gaudin-Schuhmann, top 250 mm, modulus 0.8: class 25 mm spans 25 - sqrt(25 x 37.5).
  const double p_lo = std::pow(25.0 / 250.0, 0.8), p_hi = std::pow(std::sqrt(25.0 * 37.5) / 250.0, 0.8);
  const double p_min = p_lo;  // finer than the smallest class: left out, fractions renormalised
  EXPECT_NEAR(rock.mass_fractions[7], (p_hi - p_lo) / (1.0 - p_min), 1e-12);
  // The classes hold 1 - P(25 mm) of the distribution, and --check says so.
  EXPECT_NEAR(scene.charge.species[1].distribution_held, 1.0 - p_min, 1e-12);
  const std::vector<std::string> notes = distribution_notes(scene);
  ASSERT_EQ(notes.size(), 1u);
  char held[64];
  std::snprintf(held, sizeof held, "hold %.1f%%", 100.0 * (1.0 - p_min));
  EXPECT_NE(notes[0].find(held), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("finer than 25 mm"), std::string::npos) << notes[0];

  const MillGeometry mill = build_scene_mill(scene);
  const ChargeState charge = fill_charge(scene, mill);
  const std::vector<std::int64_t> want = disks_per_size(scene, 1);
  const double area = species_area_m2(scene, 1);
  std::vector<std::int64_t> got(rock.diameters_m.size(), 0);
  for (std::size_t i = 0; i < charge.size(); ++i) {
    if (charge.species[i] != 1 || !charge.active[i]) continue;
    for (std::size_t c = 0; c < rock.diameters_m.size(); ++c)
      if (std::fabs(2.0 * charge.radius_m[i] - rock.diameters_m[c]) < 1e-9) got[c] += 1;
  }
  for (std::size_t c = 0; c < rock.diameters_m.size(); ++c) {
    const double d = rock.diameters_m[c];
    const double share = area * rock.mass_fractions[c] / (kPi * d * d / 4.0);
    EXPECT_EQ(got[c], want[c]) << "class " << d * 1e3 << " mm";
    EXPECT_LT(std::fabs(static_cast<double>(got[c]) - share), 1.0) << "class " << d * 1e3 << " mm";
  }
  // The finest class holds the most disks: the fine tail is there.
  EXPECT_GT(got[7], got[0]);
  // The count `run --check` reports is the charge the filling places (discrete sizes: exact).
  EXPECT_EQ(expected_charge_disks(scene), static_cast<double>(charge.size()));
}

// The fine charge (about 3,100 disks) settles and turns on the soft engine (two threads)
// without a lost disk: 0.5 s at rest, then half a revolution at the scene's speed (the
// charge lifts to its shoulder and cascades onto the toe; a whole revolution, 6,000 steps
// of 1 ms, costs twice the test's time for the same events again).
// With a size cut-off that leaves classes out, --check's note gives what the classes it
// keeps hold (of the distribution, or of a list of sizes), down to shares far below 0.1%.
TEST(FineCharge, TheNoteOnASpeciesMassCountsTheClassesTheCutOffKeeps) {
  Scene scene = fine_sag();
  scene.solver.size_cutoff_m = 0.1;
  const SpeciesDef& rock = scene.charge.species[1];
  double kept = 0.0, listed = 0.0;
  for (std::size_t i = 0; i < rock.diameters_m.size(); ++i) {
    listed += rock.mass_fractions[i];
    if (rock.diameters_m[i] >= 0.1) kept += rock.mass_fractions[i];
  }
  ASSERT_LT(kept, listed);
  std::vector<std::string> notes = distribution_notes(scene);
  ASSERT_EQ(notes.size(), 1u);
  char held[96];
  std::snprintf(held, sizeof held, "from 112.5 mm (the size cut-off, 100 mm) hold %.1f%% of its distribution's mass",
                100.0 * rock.distribution_held * kept / listed);
  EXPECT_NE(notes[0].find(held), std::string::npos) << notes[0];
  // What is left out lies below the 112.5 mm class's lower edge, the geometric mean with the
  // 87.5 mm class, 99.22 mm.
  std::snprintf(held, sizeof held, "the %.1f%% finer than 99.22 mm (the 112.5 mm class's lower edge) goes to them",
                100.0 * (1.0 - rock.distribution_held * kept / listed));
  EXPECT_NE(notes[0].find(held), std::string::npos) << notes[0];
  // Listed sizes: the cut-off keeps a class holding a billionth of the mass.
  Scene listed_sizes = fine_sag();
  SpeciesDef& listed_rock = listed_sizes.charge.species[1];
  listed_rock.diameters_m = {0.022, 0.007};
  listed_rock.mass_fractions = {1e-9, 1.0 - 1e-9};
  listed_rock.distribution_held = 0.0;
  listed_sizes.solver.size_cutoff_m = 0.01;
  notes = distribution_notes(listed_sizes);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("from 22 mm (the size cut-off, 10 mm) hold 1e-07% of its listed mass"), std::string::npos)
      << notes[0];
  // Without a cut-off a list says nothing.
  listed_sizes.solver.size_cutoff_m = 0.0;
  EXPECT_TRUE(distribution_notes(listed_sizes).empty());
}

TEST(FineCharge, TwentyFiveMillimetreSagChargeTurnsWithoutLosingADisk) {
  Scene scene = fine_sag();
  scene.solver.threads = 2;
  const MillGeometry mill = build_scene_mill(scene);
  auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
  const double dt = engine->time_step_s();
  engine->set_mill_speed(0.0);
  engine->step(steps_for(0.5, dt));
  const double omega = scene.angular_speed_rad_s();
  engine->set_mill_speed(omega);
  engine->reset_window();
  engine->step(steps_for(kPi / omega, dt));
  EXPECT_EQ(engine->accounting().escaped, 0);
  EXPECT_EQ(engine->accounting().non_finite, 0);
  EXPECT_TRUE(engine->events().empty()) << engine->events().front().what;
  EXPECT_GT(engine->accounting().drive_work_J, 0.0);
}
