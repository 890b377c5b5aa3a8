// Stability: the wear side. An acceleration factor up to 1e9, a lifter worn to the shell,
// and profiles with a very sharp or very thin feature. Each either runs soundly or stops
// with a message that names the limit (docs/stability.md).
#include "stability_common.hpp"

#include "geometry/polyline.hpp"
#include "scene/fidelity.hpp"
#include "wear/wear.hpp"

namespace millwear::stability {

namespace {

bool any_event_has(const WearHistory& h, const std::string& text) {
  for (const auto& e : h.events)
    if (e.find(text) != std::string::npos) return true;
  return false;
}

bool finite_units(const WearHistory& h) {
  for (const auto& st : h.stages)
    for (const auto& u : st.units)
      for (const Vec2& p : u.surface)
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
  return true;
}

Scene tiny_wear_scene() {
  Scene s = tiny_mill();
  s.wear.wear_rate_m3_per_J = 1e-10;
  s.wear.stage_hours = 100.0;
  s.wear.stages = 1;
  s.wear.window_revolutions = 0.5;
  s.wear.target_rel_uncertainty = 0.0;  // a fixed window: each test is built on the steps it takes
  s.wear.update_interval_s = 0.25;
  s.solver.spinup_revolutions = 0.25;
  return s;
}

}  // namespace

// Continuous mode at factor 1e9: one update would wear far more than the lifter. The
// loop stops at the first update with rule 1's message naming wear.factor, and what it
// returns is finite.
TEST(StabilityWear, AccelerationFactorOfOneBillionStopsNamingTheFactor) {
  Scene s = tiny_wear_scene();
  s.wear.mode = WearMode::Continuous;
  s.wear.factor = 1e9;
  const WearHistory h = run_wear_history(s);
  EXPECT_TRUE(any_event_has(h, "wear.factor")) << (h.events.empty() ? "no events" : h.events.front());
  EXPECT_TRUE(finite_units(h));
}

// A factor inside rule 1 (1e5 on this mill: about 0.1 mm per update) runs the stage.
TEST(StabilityWear, ModerateFactorRunsSoundly) {
  Scene s = tiny_wear_scene();
  s.wear.mode = WearMode::Continuous;
  s.wear.factor = 1e5;
  s.wear.stage_hours = 20.0;  // 0.72 s simulated: three updates
  const WearHistory h = run_wear_history(s);
  EXPECT_TRUE(h.events.empty()) << h.events.front();
  EXPECT_TRUE(finite_units(h));
  EXPECT_EQ(h.stages.back().stage, 1);
}

// A wear rate that takes the whole lifter in one stage: the history ends with the
// "worn to the shell" event and a finite last geometry, not an exception.
TEST(StabilityWear, LifterWornToTheShellEndsTheHistoryWithAnEvent) {
  Scene s = tiny_wear_scene();
  s.wear.wear_rate_m3_per_J = 1e-6;
  s.wear.max_depth_step_m = 0.002;  // 10% of the lifter per update
  s.wear.stages = 3;
  const WearHistory h = run_wear_history(s);
  EXPECT_TRUE(any_event_has(h, "worn to the shell")) << (h.events.empty() ? "no events" : h.events.back());
  EXPECT_TRUE(finite_units(h));
  EXPECT_TRUE(h.stages.back().worn_out);
  EXPECT_LT(h.stages.size(), 4u);  // stopped before the last stage
}

// The same wear in updates of 40% of the lifter, re-smoothed with the default radius (the
// smallest particle's, 7.5 mm): the update leaves a feature narrower than the smoothing disk,
// which takes 9.8% of the new lifter's area beyond the wear. The update cannot be taken: a
// numerical failure reported as an error naming the stage, never booked as the lifter wearing
// out (which would make it a life). The stages finished before it reached the caller. (With
// the scene's 2 mm radius the folds are cut out and the lifter wears to the shell.)
TEST(StabilityWear, AWearUpdateTheReshapingCannotTakeIsAnErrorNotWearOut) {
  Scene s = tiny_wear_scene();
  s.wear.wear_rate_m3_per_J = 1e-6;
  s.wear.max_depth_step_m = 0.008;
  s.wear.smoothing_radius_m = 0.0;  // the default: the smallest particle radius
  s.wear.stages = 3;
  int stages_handed = 0;
  WearCallbacks cb;
  cb.on_stage = [&](const StageRecord& rec) {
    EXPECT_FALSE(rec.worn_out);
    ++stages_handed;
  };
  try {
    run_wear_history(s, cb);
    FAIL() << "the history finished";
  } catch (const NumericalError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("stage 1: "), std::string::npos) << what;
    EXPECT_NE(what.find("re-smoothing"), std::string::npos) << what;
  }
  EXPECT_EQ(stages_handed, 1);  // stage 0, measured on the new liner
}

// Profiles with a very thin fin (1.6 mm wide, 20 mm high) and a very sharp spike (14 deg
// apex): the charge runs on them soundly, no disk leaks through the thin metal.
Polyline thin_fin() {
  return {{-0.015, 0.0}, {-0.010, 0.005}, {-0.001, 0.005}, {-0.0008, 0.025},
          {0.0008, 0.025}, {0.001, 0.005}, {0.010, 0.005}, {0.015, 0.0}};
}
Polyline sharp_spike() { return {{-0.003, 0.0}, {0.0, 0.025}, {0.003, 0.0}}; }

// Metal thinner than the smallest particle radius lets a disk touch both of its faces at
// once (a sawtooth of thin teeth leaks disks through the liner): such a profile is refused
// before anything is placed, with the thickness found and the one needed. The fin is 1.6 mm
// at its top, the spike's 6 mm base narrows to a point; the tiny mill's smallest ball
// radius is 7.5 mm.
TEST(StabilityProfile, ThinFinAndSharpSpikeAreRefusedWithTheirThickness) {
  for (const auto& [name, pts] : {std::pair{"thin-fin", thin_fin()}, std::pair{"sharp-spike", sharp_spike()}}) {
    Scene s = tiny_mill();
    s.mill.lifter.points = pts;
    s.mill.lifter.name = name;
    s.mill.mesh.lifter_edge_m = 0.001;
    const Outcome o = run_briefly(s, 1.0);
    EXPECT_FALSE(o.completed) << name;
    EXPECT_EQ(o.disks, 0u) << name << ": refused before the fill";
    EXPECT_NE(o.error.find("lifters.profile"), std::string::npos) << o.error;
    EXPECT_NE(o.error.find("at least 7.5 mm thick"), std::string::npos) << o.error;
  }
}

// The limit of a thin feature is the re-smoothing, not the engine: the opening by the
// smoothing radius removes a feature narrower than twice that radius at the first wear
// update, whatever the wear. The fin (1.6 mm) goes under a 2 mm radius and stays under
// a 0.5 mm one. docs/stability.md: keep wear.smoothing_radius under half the thinnest
// feature the design must keep.
TEST(StabilityProfile, FeatureNarrowerThanTwiceTheSmoothingRadiusGoesAtTheFirstUpdate) {
  Scene s = tiny_mill();
  const double R = s.radius_m();
  const LinerUnit unit = make_liner_unit(thin_fin(), R, s.mill.rows, {0.010, 0.001});
  const std::vector<double> no_wear(unit.surface.size() - 1, 0.0);
  const double h0 = measure_lifter(unit, R).height_m;
  const double h_wide = measure_lifter(apply_wear(unit, no_wear, R, 0.002, {0.010, 0.001}), R).height_m;
  const double h_narrow = measure_lifter(apply_wear(unit, no_wear, R, 0.0005, {0.010, 0.001}), R).height_m;
  EXPECT_NEAR(h0, 0.025, 1e-4);
  EXPECT_LT(h_wide, 0.006);                // only the 5 mm base is left
  EXPECT_NEAR(h_narrow, h0, 0.02 * h0);    // a 0.5 mm disk rounds its tip (2%: the mesh)
}

// ...and the scene is refused before it runs: the message names wear.smoothing_radius and
// gives the largest radius that keeps the fin, which then passes the check.
TEST(StabilityProfile, SmoothingRadiusWiderThanTheThinnestFeatureIsRefused) {
  Scene s = tiny_mill();
  s.mill.lifter.points = thin_fin();
  s.mill.mesh = {0.010, 0.001};
  s.wear.smoothing_radius_m = 0.002;
  EXPECT_GT(smoothing_loss(s, 0.002).height_fraction, 0.5);
  std::string message;
  try {
    check_smoothing_radius(s, "fin.toml");
    FAIL() << "a 2 mm radius on a 1.6 mm fin should be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "fin.toml");
    EXPECT_EQ(e.where, "wear.smoothing_radius");
    message = e.what();
  }
  const auto at = message.find("at most ");
  ASSERT_NE(at, std::string::npos) << message;
  const double largest_mm = std::stod(message.substr(at + 8));
  EXPECT_GE(largest_mm, 0.5) << message;   // the radius the test above keeps it with
  EXPECT_LE(largest_mm, 1.05) << message;  // half the fin's widest part (2 mm at its base)
  s.wear.smoothing_radius_m = 0.0005;
  EXPECT_NO_THROW(check_smoothing_radius(s, "fin.toml"));
}

// The shipped scenes at their default radius (the smallest particle radius): re-smoothing
// the new lifter rounds its convex corners and takes exactly those fillets,
// r^2 (tan(phi/2) - phi/2) per corner turning by phi (to the disk polygon's 0.5% of r along
// each arc), and nothing of its height; what the closing would add at the lifter's feet is
// cut back (wear never adds metal). All inside the check's 5% bounds.
TEST(StabilityProfile, ShippedScenesSmoothInsideTheBound) {
  for (const char* f : {"scenarios/sag-2x30.toml", "scenarios/sag-1x30.toml", "scenarios/lab-mill.toml"}) {
    const Scene s = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/" + f);
    EXPECT_NO_THROW(check_smoothing_radius(s, f)) << f;
    const double r = s.wear.smoothing_radius_m > 0 ? s.wear.smoothing_radius_m : s.smallest_particle_radius_m();
    const SmoothingLoss l = smoothing_loss(s, r);
    const LinerUnit unit = make_liner_unit(s.mill.lifter.points, s.radius_m(), s.mill.rows, s.mill.mesh);
    const double area = measure_lifter(unit, s.radius_m()).area_m2;
    double fillets = 0.0, tolerance = 0.0;
    const Polyline& u = unit.surface;
    for (std::size_t i = 1; i + 1 < u.size(); ++i) {
      const Vec2 d0 = u[i] - u[i - 1], d1 = u[i + 1] - u[i];
      const double phi = std::atan2(cross(d0, d1), dot(d0, d1));
      if (phi < -1e-9) {  // a right turn with the metal below: a convex corner
        fillets += r * r * (std::tan(-0.5 * phi) + 0.5 * phi);
        tolerance += 0.005 * r * r * -phi;
      }
    }
    EXPECT_NEAR(l.area_fraction, fillets / area, tolerance / area + 1e-9) << f;
    EXPECT_LE(l.area_fraction, 0.05) << f;
    EXPECT_NEAR(l.height_fraction, 0.0, 1e-9) << f;
  }
}

// A worn lifter can grow what the new one lacks (a thin fin left between two wear
// grooves, say). The smoothing then takes area no shear work removed, which the wear loop
// measures after every update and stops on (resmoothing_loss_m2). Here: the fin worn
// evenly by 0.1 mm; nothing lost to a 0.5 mm radius, most of the fin to a 2 mm one.
TEST(StabilityProfile, ResmoothingLossIsZeroForASmallRadiusAndLargeForAWideOne) {
  Scene s = tiny_mill();
  const double R = s.radius_m();
  const MillMeshDef mesh{0.010, 0.001};
  const LinerUnit unit = make_liner_unit(thin_fin(), R, s.mill.rows, mesh);
  const std::vector<double> depth(unit.surface.size() - 1, 0.0001);
  const double area = measure_lifter(unit, R).area_m2;
  const double small = resmoothing_loss_m2(unit, apply_wear(unit, depth, R, 0.0005, mesh), depth, R);
  const double wide = resmoothing_loss_m2(unit, apply_wear(unit, depth, R, 0.002, mesh), depth, R);
  EXPECT_LT(std::fabs(small), 0.02 * area) << small / area;
  EXPECT_GT(wide, 0.1 * area) << wide / area;
}

// Wear never adds metal. A straight-skeleton smoothing re-sharpens every worn corner narrower
// than its radius and grows metal there (4 mm on the 1x30's trailing corner in one 750 h
// stage; at twice the radius a lifter 347 mm high). Every stage's surface must lie inside the
// one before. Twice the radius is refused before any work: re-smoothing the new lifter at
// 100 mm would take 6% of it.
bool inside_metal(const Polyline& surface, Vec2 p) {
  // Below the surface: an upward ray from p crosses it an odd number of times.
  int crossings = 0;
  for (std::size_t i = 0; i + 1 < surface.size(); ++i) {
    const Vec2 a = surface[i], b = surface[i + 1];
    if ((a.x > p.x) == (b.x > p.x)) continue;
    if (a.y + (b.y - a.y) * (p.x - a.x) / (b.x - a.x) > p.y) ++crossings;
  }
  return crossings % 2 == 1;
}

TEST(StabilityWear, WearNeverAddsMetalAndTwiceTheRadiusIsRefusedBeforeAnyWork) {
  Scene s = load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/sag-1x30.toml");
  apply_fidelity(s, "draft");
  s.wear.stages = 2;
  const WearHistory h = run_wear_history(s);
  ASSERT_EQ(h.stages.size(), 3u);
  for (std::size_t k = 1; k < h.stages.size(); ++k) {
    const Polyline& before = h.stages[k - 1].units[0].surface;
    double outside = 0.0;  // deepest point of the new surface in the old one's air, m
    for (const Vec2& p : h.stages[k].units[0].surface)
      if (p.x > before.front().x && p.x < before.back().x && !inside_metal(before, p))
        outside = std::max(outside, distance_to_polyline(p, before));
    // The ends (where the upward ray runs along the unit's edge) only go down.
    const Polyline& after = h.stages[k].units[0].surface;
    outside = std::max({outside, after.front().y - before.front().y, after.back().y - before.back().y});
    // Merging the cut's slivers may leave a hundredth of a lifter edge (0.3 mm at draft).
    EXPECT_LT(outside, kSliverEdgeFraction * s.mill.mesh.lifter_edge_m)
        << "stage " << k << ": " << outside * 1e3 << " mm outside the stage before";
  }
  s.wear.smoothing_radius_m = 2.0 * s.smallest_particle_radius_m();
  try {
    run_wear_history(s);
    FAIL() << "a 100 mm radius on the 1x30 should be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "wear.smoothing_radius") << e.what();
  }
}

}  // namespace millwear::stability
