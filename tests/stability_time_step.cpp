// Stability: time step against particle size. A disk that travels more than
// kMaxStepTravelRadii of the smallest radius per step at the mill's impact speed leaks
// through the liner (bench/stability_sweep, docs/stability.md); the engine refuses such a
// step before anything moves, naming solver.time_step. Inside the limit a run is sound.
#include "stability_common.hpp"

#include "scene/fidelity.hpp"
#include "scene/limits.hpp"

namespace millwear::stability {

// The time-step sweep, 1/5000 s to 1/60 s, at two disk sizes. Every case is either
// sound or stopped naming solver.time_step; the large steps must be the stopped ones.
TEST(StabilityTimeStep, SweepIsSoundOrStopsNamingTheTimeStep) {
  for (double d_mm : {15.0, 40.0})
    for (double hz : {5000.0, 1000.0, 500.0, 240.0, 120.0, 60.0}) {
      if (d_mm < 20.0 && hz > 2000.0) continue;  // 3000 steps a second of 150 disks: slow, far inside
      Scene s = tiny_mill(d_mm);
      s.solver.time_step_s = 1.0 / hz;
      const Outcome o = run_briefly(s, 0.5);
      const std::string label = "d_min " + std::to_string(d_mm) + " mm, dt 1/" + std::to_string(hz);
      expect_sound_or_clear_stop(o, "solver.time_step", label);
      EXPECT_EQ(o.completed, step_travel_radii(s) <= kMaxStepTravelRadii) << label;
    }
}

// The same sweep on the soft backend (the presets' backend), whose limit is per substep:
// with 4 substeps it runs steps four times as long as the library may, and every run it
// does not refuse must be as sound (no disk through the liner, finite, bounded speed).
TEST(StabilityTimeStep, SoftBackendSweepIsSoundOrStopsNamingTheTimeStep) {
  for (double d_mm : {6.0, 15.0, 40.0})
    for (double hz : {1000.0, 500.0, 240.0, 120.0, 60.0}) {
      Scene s = tiny_mill(d_mm);
      s.solver.backend = Backend::Soft;
      s.solver.substeps = 4;
      s.solver.time_step_s = 1.0 / hz;
      const Outcome o = run_briefly(s, 0.5);
      const std::string label = "soft, d_min " + std::to_string(d_mm) + " mm, dt 1/" + std::to_string(hz);
      expect_sound_or_clear_stop(o, "solver.time_step", label);
      EXPECT_EQ(o.completed, step_travel_radii(s) / 4.0 <= kMaxStepTravelRadii) << label;
    }
}

// At the edge (6 mm disks, 1/1000 s: 1.57 radii a step, 870 disks) the run is still clean.
TEST(StabilityTimeStep, SmallDisksJustInsideTheLimitDoNotLeak) {
  Scene s = tiny_mill(6.0);
  s.solver.time_step_s = 1.0 / 1000.0;
  ASSERT_LE(step_travel_radii(s), kMaxStepTravelRadii);
  expect_sound_or_clear_stop(run_briefly(s, 0.5), "solver.time_step", "6 mm at 1/1000");
}

// Beyond the limit the message says what to use: the largest allowed step.
TEST(StabilityTimeStep, StopMessageGivesTheLargestAllowedStep) {
  Scene s = tiny_mill(15.0);
  s.solver.time_step_s = 1.0 / 60.0;
  try {
    check_numerical_limits(s, "scene.toml");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "solver.time_step");
    EXPECT_NE(std::string(e.what()).find("at most"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("leak"), std::string::npos) << e.what();
  }
}

// Every shipped scene at every preset is inside the limit (the presets must never trip it).
// The presets run the soft backend, which is checked per substep (its speculative margins
// cover a step; the soft time-step sweep above is sound far beyond it).
TEST(StabilityTimeStep, ShippedScenesAtEveryPresetAreInsideTheLimit) {
  for (const char* f : {"scenarios/lab-mill.toml", "scenarios/sag-2x30.toml", "scenarios/sag-1x30.toml"})
    for (const char* p : {"draft", "standard", "reference"}) {
      Scene s = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/" + f);
      apply_fidelity(s, p);
      const int substeps = s.solver.backend == Backend::Soft ? s.solver.substeps : 1;
      EXPECT_LE(step_travel_radii(s) / substeps, kMaxStepTravelRadii) << f << " at " << p;
      EXPECT_NO_THROW(check_numerical_limits(s, f)) << f << " at " << p;
      // A scene that names the library backend gets that backend's step from the preset.
      Scene lib = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/" + f);
      lib.solver.backend = Backend::Box2D;
      lib.explicit_keys.insert("solver.backend");
      apply_fidelity(lib, p);
      EXPECT_LE(step_travel_radii(lib), kMaxStepTravelRadii) << f << " at " << p << " on box2d";
      EXPECT_NO_THROW(check_numerical_limits(lib, f)) << f << " at " << p << " on box2d";
    }
}

// The soft backend's substeps do not stretch its step without end: contacts are found once a
// step, so a step that moves a disk past kMaxSoftStepTravelRadii is refused however small
// its substeps (0.05 s in 1000 substeps leaked disks in the lab mill); 0.0125 s in 64 (7.9
// radii) is taken.
TEST(StabilityTimeStep, ASoftStepIsBoundedWhateverItsSubsteps) {
  Scene s = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/tests/data/lab-quick.toml");
  s.solver.backend = Backend::Soft;
  s.solver.substeps = 1000;
  s.solver.time_step_s = 0.05;
  ASSERT_LE(step_travel_radii(s) / s.solver.substeps, kMaxStepTravelRadii);
  try {
    check_numerical_limits(s, "lab-quick.toml");
    ADD_FAILURE() << "a step of " << step_travel_radii(s) << " radii was taken";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "solver.time_step");
    EXPECT_NE(e.expected.find("per step"), std::string::npos) << e.what();
  }
  s.solver.substeps = 64;
  s.solver.time_step_s = 0.0125;
  EXPECT_LE(step_travel_radii(s), kMaxSoftStepTravelRadii);
  EXPECT_NO_THROW(check_numerical_limits(s, "lab-quick.toml"));
}

}  // namespace millwear::stability
