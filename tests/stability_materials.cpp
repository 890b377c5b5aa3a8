// Stability: the charge's materials. Size ratio 1 to 10 (mass ratio 100), fine rock among
// heavy balls (mass ratio 290), restitution 0 to 0.95, friction 0 to 1. Every run must be
// sound (docs/stability.md has the figures).
#include <cstdint>
#include <string>

#include "stability_common.hpp"

namespace millwear::stability {

TEST(StabilityMaterials, SizeRatioOneToTenIsSound) {
  for (double q : {1.0, 2.0, 4.0, 10.0}) {
    // 8 mm smallest: inside the time-step limit at 1/1000 s (1.18 radii a step).
    Scene s = tiny_mill(8.0, q, 0.2);
    expect_sound_or_clear_stop(run_briefly(s, 0.5), "solver.time_step", "size ratio " + std::to_string(q));
  }
}

// Many light disks among heavy ones: 2.5 mm rocks among 15-25 mm steel balls (a ball up to
// 290 times a rock's mass), about 1,000 disks, on the soft backend at half the step limit.
// A rock pressed by a ball onto the liner must not be pushed on through it: its soft
// contacts carry the ball's weight only if the push-out allows (model.cpp, kCarriedWeights).
TEST(StabilityMaterials, FineRockAmongHeavyBallsStaysInTheMill) {
  for (const std::uint64_t seed : {2, 3}) {
    Scene s = tiny_mill(15.0, 25.0 / 15.0, 0.12);
    s.solver.backend = Backend::Soft;
    s.solver.seed = seed;
    s.charge.ball_filling = 0.10;
    SpeciesDef rock = s.charge.species[0];
    rock.name = "rock";
    rock.is_ball = false;
    rock.density_kg_m3 = 2700.0;
    rock.diameters_m = {0.0025};
    rock.mass_fractions = {1.0};
    s.charge.species.push_back(rock);
    s.solver.time_step_s = 0.0008;
    const Outcome o = run_briefly(s, 2.0);
    expect_sound_or_clear_stop(o, "solver.time_step", "seed " + std::to_string(seed));
    EXPECT_TRUE(o.completed);
    EXPECT_GT(o.disks, 800u);
  }
}

TEST(StabilityMaterials, RestitutionZeroToAlmostOneIsSound) {
  for (double e : {0.0, 0.3, 0.8, 0.95}) {
    Scene s = tiny_mill();
    for (auto& sp : s.charge.species) sp.restitution = sp.restitution_liner = e;
    expect_sound_or_clear_stop(run_briefly(s, 1.0), "restitution", "restitution " + std::to_string(e));
  }
}

TEST(StabilityMaterials, FrictionZeroToOneIsSound) {
  for (double mu : {0.0, 0.1, 0.5, 1.0}) {
    Scene s = tiny_mill();
    for (auto& sp : s.charge.species) sp.friction = sp.friction_liner = mu;
    expect_sound_or_clear_stop(run_briefly(s, 1.0), "friction", "friction " + std::to_string(mu));
  }
}

// Friction 0 is sound but wears nothing: shear work is friction times slip, so a
// frictionless charge does none (up to rounding: 1e-9 of the work at friction 0.5).
TEST(StabilityMaterials, FrictionlessChargeDoesNoShearWork) {
  auto shear_power = [](double mu) {
    Scene s = tiny_mill();
    for (auto& sp : s.charge.species) sp.friction = sp.friction_liner = mu;
    const MillGeometry mill = build_scene_mill(s);
    auto engine = make_engine(s, mill, fill_charge(s, mill), accounting_options_for(s));
    settle_and_spin_up(*engine, s, 1.0);
    engine->step(steps_for(s.revolution_time_s(), engine->time_step_s()));
    double w = 0.0;
    for (double x : engine->accounting().shear_work_J) w += x;
    return w;
  };
  const double w = shear_power(0.5);
  EXPECT_GT(w, 0.0);
  EXPECT_LE(shear_power(0.0), 1e-9 * w);
}

}  // namespace millwear::stability
