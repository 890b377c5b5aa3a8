// Stability: operating point. Mill speed from rest to 160% of critical (cascading,
// cataracting, centrifuging) and filling from an empty mill to 50% of the mill area.
// Every run must be sound: finite, no escaped disk, speeds under the bound of
// stability_run.hpp (bench/stability_sweep prints the figures, docs/stability.md).
#include "metrics/charge_summary.hpp"
#include "stability_common.hpp"

namespace millwear::stability {

TEST(StabilityOperating, MillSpeedFromRestToCentrifugingIsSound) {
  for (double f : {0.0, 0.3, 0.75, 1.0, 1.3, 1.6}) {
    Scene s = tiny_mill();
    s.mill.speed_fraction_critical = f;
    expect_sound_or_clear_stop(run_briefly(s, 1.0), "mill.speed", "speed " + std::to_string(f) + " of critical");
  }
}

// Above critical the charge rides the shell: the centre of mass moves to the mill centre
// and the torque arm vanishes. Checked as the bed's mean radius: over 80% of the
// radius at 160% critical (the disks sit within two diameters of the shell).
TEST(StabilityOperating, AboveCriticalTheChargeCentrifuges) {
  Scene s = tiny_mill();
  s.mill.speed_fraction_critical = 1.6;
  const MillGeometry mill = build_scene_mill(s);
  auto engine = make_engine(s, mill, fill_charge(s, mill), accounting_options_for(s));
  settle_and_spin_up(*engine, s, 1.0);
  engine->step(steps_for(2.0 * s.revolution_time_s(), engine->time_step_s()));
  const ChargeState& st = engine->state();
  double mean_r = 0.0, n = 0.0;
  for (std::size_t i = 0; i < st.size(); ++i)
    if (st.active[i]) mean_r += length(st.position_m[i]), n += 1.0;
  ASSERT_GT(n, 0.0);
  EXPECT_GT(mean_r / n, 0.8 * s.radius_m());
  // The charge summary says so: the shell band is full all round, no toe or shoulder.
  engine->reset_window();
  engine->step(steps_for(s.revolution_time_s(), engine->time_step_s()));
  EXPECT_TRUE(summarize(engine->accounting(), s.angular_speed_rad_s(), kGravity).centrifuged);
}

// The same mill at 75% of critical cascades: a bed with its toe on the falling side and its
// shoulder on the rising side, the centre of mass between them.
TEST(StabilityOperating, BelowCriticalTheChargeHasAToeAndAShoulder) {
  Scene s = tiny_mill();
  const MillGeometry mill = build_scene_mill(s);
  auto engine = make_engine(s, mill, fill_charge(s, mill), accounting_options_for(s));
  settle_and_spin_up(*engine, s, 1.0);
  engine->step(steps_for(s.revolution_time_s(), engine->time_step_s()));
  const ChargeSummary sum = summarize(engine->accounting(), s.angular_speed_rad_s(), kGravity);
  EXPECT_FALSE(sum.centrifuged);
  EXPECT_LT(sum.toe_deg, 0.0);
  EXPECT_GT(sum.shoulder_deg, 0.0);
  EXPECT_GT(sum.centre_of_mass_deg, sum.toe_deg);
  EXPECT_LT(sum.centre_of_mass_deg, sum.shoulder_deg);
}

// A filling too small for one disk is refused before anything is placed, naming the filling
// (the tiny mill's charge is all balls: ball_filling = filling).
TEST(StabilityOperating, FillingOfNoDiskIsRefused) {
  Scene s = tiny_mill(15.0, 1.67, 1e-4);  // less than one disk's area
  const Outcome o = run_briefly(s, 1.0);
  EXPECT_FALSE(o.completed);
  EXPECT_NE(o.error.find("charge.ball_filling"), std::string::npos) << o.error;
  EXPECT_NE(o.error.find("at least one disk"), std::string::npos) << o.error;
  EXPECT_EQ(o.disks, 0u);
}

TEST(StabilityOperating, OneParticleIsSound) {
  // One 15-25 mm ball: 0.8 x filling x 0.283 m^2 = one disk's area at filling 1.1e-3.
  Scene s = tiny_mill(20.0, 1.0, 1.3e-3);
  const Outcome o = run_briefly(s, 2.0);
  expect_sound_or_clear_stop(o, "charge.filling", "one particle");
  EXPECT_EQ(o.disks, 1u);
}

TEST(StabilityOperating, FillingUpToHalfTheMillIsSound) {
  for (double f : {0.01, 0.1, 0.3, 0.5}) {
    Scene s = tiny_mill(15.0, 1.67, f);
    expect_sound_or_clear_stop(run_briefly(s, 0.5), "charge.filling", "filling " + std::to_string(f));
  }
}

// Past what fits inside the lifter tips the fill stops and names charge.filling.
TEST(StabilityOperating, OverfilledMillStopsNamingTheFilling) {
  Scene s = tiny_mill(15.0, 1.67, 0.9);
  const Outcome o = run_briefly(s, 0.5);
  EXPECT_FALSE(o.completed);
  expect_sound_or_clear_stop(o, "charge.filling", "filling 0.9");
}

// Random placement fills at most about 55% of a circle with disks of one size, less than the
// 60% the up-front check allows: a filling between the two stops in the fill, naming
// charge.filling and a filling below the share it placed.
TEST(StabilityOperating, AFillingRandomPlacementCannotReachStopsNamingTheFilling) {
  Scene s = tiny_mill(20.0, 1.0, 0.59);
  const MillGeometry mill = build_scene_mill(s);
  EXPECT_NO_THROW(check_charge_fits(s, mill, s.source_file));
  try {
    fill_charge(s, mill);
    ADD_FAILURE() << "placed disks of one size at filling 0.59";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, s.source_file);
    EXPECT_EQ(e.where, "charge.filling");
    const auto at = e.expected.find("a filling below ");
    ASSERT_NE(at, std::string::npos) << e.expected;
    const double below = std::stod(e.expected.substr(at + 16));
    EXPECT_GT(below, 0.4) << e.expected;
    EXPECT_LT(below, 0.59) << e.expected;
  }
}

}  // namespace millwear::stability
