// Limits of a scene (the reasons and the measured numbers are in limits.hpp and
// docs/stability.md).
#include "scene/limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "common/units.hpp"
#include "geometry/polyline.hpp"
#include "scene/filling.hpp"

namespace millwear {

namespace {

// The most geometry updates a run may take, however they arise (staged updates of at most
// wear.max_depth_step, continuous updates, reversals of a bidirectional mill): each is a
// reshape of the liner and, staged, a measuring window.
constexpr double kMaxUpdates = 100'000;

// A limit to three significant digits, rounded down, so that the value a message offers is
// one the check takes (0.010198 s is offered as 0.0101 s, not 0.0102 s).
double three_digits_down(double v) {
  if (!(v > 0.0) || !std::isfinite(v)) return v;
  const double unit = std::pow(10.0, std::floor(std::log10(v)) - 2.0);
  return std::floor(v / unit) * unit;
}

std::string count_text(double n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, n < 1e6 ? "%.0f" : "%.3g", n);
  return buf;
}

// A size in mm to three digits: 0.1 mm stays 0.1, not 0.
std::string size_text(double mm) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", mm);
  return buf;
}

// A size class in mm to four digits: 112.5 mm, 31.25 mm.
std::string fine_size_text(double mm) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", mm);
  return buf;
}

void check_steps(const std::string& file, const std::string& key, std::int64_t steps, const std::string& what) {
  if (steps <= kMaxPhaseSteps) return;
  throw InputError(file, key,
                   "expected at most " + count_text(double(kMaxPhaseSteps)) + " time steps for " + what + ", got " +
                       (steps == std::numeric_limits<std::int64_t>::max() ? std::string("more than 9.2e18")
                                                                          : count_text(double(steps))));
}

}  // namespace

double impact_speed_m_s(const Scene& scene) {
  return scene.angular_speed_rad_s() * scene.radius_m() + std::sqrt(2.0 * kGravity * scene.mill.diameter_m);
}

double step_travel_radii(const Scene& scene) {
  const double r = scene.smallest_particle_radius_m();
  return r > 0.0 ? scene.solver.time_step_s * impact_speed_m_s(scene) / r : 0.0;
}

std::int64_t steps_in(double seconds, double dt_s) {
  if (!(seconds > 0.0)) return 0;
  const double n = std::ceil(seconds / dt_s - 1e-9);
  // 9.2e18 is the largest double below INT64_MAX's range.
  if (!(n < 9.2e18)) return std::numeric_limits<std::int64_t>::max();
  return static_cast<std::int64_t>(n);
}

// "1 time step", "3 time steps".
std::string steps_text(std::int64_t n) { return std::to_string(n) + (n == 1 ? " time step" : " time steps"); }

double particle_mass_ratio(const Scene& scene) {
  double lightest = 0.0, heaviest = 0.0;
  for (const auto& s : scene.species_as_placed()) {
    if (!scene.species_in_use(s)) continue;
    const double lo = s.density_kg_m3 * s.smallest_diameter_m() * s.smallest_diameter_m();
    const double hi = s.density_kg_m3 * s.largest_diameter_m() * s.largest_diameter_m();
    if (!(lo > 0.0)) continue;
    lightest = lightest > 0.0 ? std::min(lightest, lo) : lo;
    heaviest = std::max(heaviest, hi);
  }
  return lightest > 0.0 ? heaviest / lightest : 0.0;
}

double time_step_limit_s(const Scene& scene) {
  const double r = scene.smallest_particle_radius_m();
  if (!(r > 0.0)) return 0.0;
  const double v = impact_speed_m_s(scene);
  if (scene.solver.backend != Backend::Soft) return kMaxStepTravelRadii * r / v;
  const int substeps = std::max(1, scene.solver.substeps);
  return std::min(kMaxStepTravelRadii * r * substeps, kMaxSoftStepTravelRadii * r) / v;
}

namespace {

// The bed's layers of disks: the depth of the circular segment that holds the filling over
// the mean diameter of the disks that fill it (each with its share of the packed area).
double bed_layers(const Scene& scene) {
  const double disks = expected_charge_disks(scene);
  const double fill = std::clamp(scene.charge.filling, 0.0, 1.0);
  if (!(disks > 0.0) || !(fill > 0.0)) return 0.0;
  // theta - sin(theta) = 2 pi fill, theta the segment's angle (increasing in theta).
  double lo = 0.0, hi = 2.0 * kPi;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid - std::sin(mid) < 2.0 * kPi * fill ? lo : hi) = mid;
  }
  const double r = scene.radius_m();
  const double depth_m = r * (1.0 - std::cos(0.5 * lo));
  const double packed_m2 = fill * kPi * r * r * scene.charge.bulk_packing;
  const double mean_diameter_m = std::sqrt(4.0 * packed_m2 / (kPi * disks));
  return depth_m / mean_diameter_m;
}

}  // namespace

double bed_overlap_radii(const Scene& scene) {
  const double r_min = scene.smallest_particle_radius_m();
  if (scene.solver.backend != Backend::Soft || !(r_min > 0.0)) return 0.0;
  const double w = 2.0 * kPi * scene.solver.contact_hertz_used();
  return 2.0 * bed_layers(scene) * kGravity / (w * w) / r_min;
}

std::vector<std::string> limit_notes(const Scene& scene) {
  std::vector<std::string> notes;
  if (const double sag = bed_overlap_radii(scene); sag > kSoundBedOverlapRadii) {
    const double hertz = scene.solver.contact_hertz_used();
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "solver: contacts of %.3g Hz are soft for this bed: under its weight the lowest disks overlap by "
                  "about %.2g smallest radii (sound measured up to %.2g; at 10 Hz disks end inside each other); "
                  "solver.contact_hertz %.3g Hz or more keeps them within it (docs/stability.md)",
                  hertz, sag, kSoundBedOverlapRadii, std::ceil(hertz * std::sqrt(sag / kSoundBedOverlapRadii)));
    notes.push_back(buf);
  }
  const double ratio = particle_mass_ratio(scene);
  if (ratio > kSoundMassRatio) {
    const double limit = time_step_limit_s(scene), dt = scene.solver.time_step_s;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "charge: the heaviest disk is %.0f times the lightest's mass (sound measured up to %.0f): a bed "
                  "of many light disks among heavy ones loses an occasional disk (the run fails, exit 1), fewer "
                  "at half the step limit; solver.time_step %.3g s is %.2f of the limit %.3g s "
                  "(docs/stability.md)",
                  ratio, kSoundMassRatio, dt, dt / limit, limit);
    notes.push_back(buf);
  }
  return notes;
}

void check_numerical_limits(const Scene& scene, const std::string& file) {
  // The soft backend substeps; its own limit is per substep.
  const int substeps = scene.solver.backend == Backend::Soft ? std::max(1, scene.solver.substeps) : 1;
  const double travel = step_travel_radii(scene) / substeps;
  if (travel > kMaxStepTravelRadii) {
    const double r = scene.smallest_particle_radius_m();
    const double dt_max = kMaxStepTravelRadii * r * substeps / impact_speed_m_s(scene);
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "a time step of at most %.3g s (1/%.0f s): at the impact speed %.2f m/s (shell speed + "
                  "free fall across the mill) a disk would move %.2f smallest radii (of %.3g mm) per %s, over the "
                  "limit of %.1f radii where disks start to leak through the liner; got %.3g s (1/%.0f s)",
                  three_digits_down(dt_max), std::ceil(1.0 / dt_max), impact_speed_m_s(scene), travel, r * 1e3,
                  substeps > 1 ? "substep" : "step", kMaxStepTravelRadii, scene.solver.time_step_s,
                  1.0 / scene.solver.time_step_s);
    throw InputError(file, "solver.time_step", buf);
  }
  const double step_travel = step_travel_radii(scene);
  if (substeps > 1 && step_travel > kMaxSoftStepTravelRadii) {
    const double dt_max = scene.solver.time_step_s * kMaxSoftStepTravelRadii / step_travel;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "a time step of at most %.3g s (1/%.0f s): the soft solver finds contacts once a step, and at the "
                  "impact speed %.2f m/s a disk would move %.1f smallest radii (of %.3g mm) per step, over the limit "
                  "of %.0f radii where disks start to leak whatever the substeps; got %.3g s (1/%.0f s)",
                  three_digits_down(dt_max), std::ceil(1.0 / dt_max), impact_speed_m_s(scene), step_travel,
                  scene.smallest_particle_radius_m() * 1e3, kMaxSoftStepTravelRadii, scene.solver.time_step_s,
                  1.0 / scene.solver.time_step_s);
    throw InputError(file, "solver.time_step", buf);
  }
}

void check_profile_features(const Scene& scene, const std::string& file) {
  const double needed = scene.smallest_particle_radius_m();
  if (!(needed > 0.0)) return;
  for (int k = 0; k < scene.mill.kind_count(); ++k) {
    const LifterProfile& lifter = scene.mill.kind(k);
    // A measured profile's noise makes spikes narrower than any particle; its surface is
    // checked once re-smoothed, as the wear loop starts from it (wear/reshape.hpp).
    if (!lifter.measured.empty()) continue;
    // Sampled at a quarter of the size needed: a part thinner than it is found to within that.
    const double thinnest = thinnest_part(lifter.points, 0.25 * needed);
    if (thinnest < needed) refuse_thin_lifter(scene, file, k, needed, thinnest, false);
  }
}

void refuse_thin_lifter(const Scene& scene, const std::string& file, int kind, double needed_m, double thinnest_m,
                        bool resmoothed) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "a lifter whose every part is at least %.3g mm thick (the smallest particle radius)%s: %s '%s' has a "
                "part about %.3g mm thick, so a disk can touch both of its faces at once and pass through the liner",
                in_mm(needed_m), resmoothed ? " once re-smoothed at wear.smoothing_radius" : "",
                resmoothed ? "measured profile" : "profile", scene.mill.kind(kind).name.c_str(), in_mm(thinnest_m));
  throw InputError(file, scene.mill.profile_key(kind), buf);
}

void check_step_counts(const Scene& scene, const std::string& file) {
  const SolverDef& v = scene.solver;
  const WearDef& w = scene.wear;
  const double dt = v.time_step_s;
  const double rev_s = scene.revolution_time_s();
  check_steps(file, "solver.settle_time", steps_in(v.settle_time_s, dt), "settling");
  check_steps(file, "mill.speed", steps_in(rev_s, dt), "one revolution of the mill");
  check_steps(file, "solver.spinup_revolutions", steps_in(v.spinup_revolutions * rev_s, dt), "the spin-up");
  check_steps(file, "run.revolutions", steps_in(scene.run.revolutions * rev_s, dt), "the measured revolutions");
  // The measured window is cut into kWindowBatches batches for the errors: an empty batch
  // would enter their spread as a zero.
  if (steps_in(scene.run.revolutions * rev_s, dt) < kWindowBatches)
    throw InputError(file, "run.revolutions",
                     "expected measured revolutions (run.revolutions, or --revolutions) of at least " +
                         std::to_string(kWindowBatches) + " time steps (one per batch of the errors), got " +
                         short_number(scene.run.revolutions) + " revolutions: " + steps_text(steps_in(scene.run.revolutions * rev_s, dt)) +
                         " of " + short_number(dt) + " s");

  const double stage_sim_s = w.stage_hours * kSecondsPerHour / w.factor;  // continuous mode
  if (w.mode == WearMode::Staged) {
    const std::int64_t batch = steps_in(w.window_revolutions * rev_s / kWindowBatches, dt);
    if (batch < 1)
      throw InputError(file, "wear.window_revolutions",
                       "expected a measuring window of at least " + std::to_string(kWindowBatches) +
                           " time steps (one per batch of the rule-2 error), got " +
                           count_text(w.window_revolutions * rev_s / dt));
    const int batches = w.target_rel_uncertainty > 0.0 ? kMaxWindowBatches : kWindowBatches;
    check_steps(file, "wear.window_revolutions", batch * batches < batch ? std::numeric_limits<std::int64_t>::max()
                                                                          : batch * batches,
                "a measuring window");
  } else {
    check_steps(file, "wear.update_interval", steps_in(w.update_interval_s, dt), "one continuous update");
    check_steps(file, "wear.factor", steps_in(stage_sim_s, dt),
                "a continuous stage (stage_hours / factor of simulated time)");
    const double updates = w.stages * std::ceil(stage_sim_s / w.update_interval_s);
    if (!(updates <= kMaxUpdates))
      throw InputError(file, "wear.update_interval",
                       "expected at most " + count_text(kMaxUpdates) + " geometry updates in the run, got " +
                           count_text(updates) + " (stages x stage_hours / factor / update_interval)");
  }
  if (scene.mill.direction == Direction::Bidirectional) {
    const double reversals = w.stages * w.stage_hours / scene.mill.reverse_every_hours;
    if (!(reversals <= kMaxUpdates))
      throw InputError(file, "mill.reverse_every",
                       "expected at most " + count_text(kMaxUpdates) + " reversals in the run, got " +
                           count_text(reversals));
  }
  if (w.mode == WearMode::Staged && !scene.mill.lifter.points.empty()) {
    // Updates of at most max_depth_step wear the lifter to the shell in height / step of them.
    const double height = measure_profile(scene.mill.lifter.points).height_m;
    const double updates = height / w.max_depth_step_m;
    if (!(updates <= kMaxUpdates))
      throw InputError(file, "wear.max_depth_step",
                       "expected at least " + size_text(height / kMaxUpdates * 1e3) + " mm (the lifter's height over " +
                           count_text(kMaxUpdates) + " updates), got " + size_text(in_mm(w.max_depth_step_m)) + " mm");
  }
}

void check_filling(const Scene& scene, const std::string& file) {
  if (scene.charge.species.size() > kMaxSpecies)
    throw InputError(file, "charge.species",
                     "at most " + std::to_string(kMaxSpecies) + " species (a disk's species is one byte), got " +
                         std::to_string(scene.charge.species.size()));
  const auto placed = scene.species_as_placed();
  for (std::size_t k = 0; k < placed.size(); ++k) {
    if (!scene.species_in_use(placed[k]) || species_gets_a_disk(scene, k)) continue;
    const SpeciesDef& sp = placed[k];
    const std::string name = "charge.species[" + std::to_string(k) + "] ('" + sp.name + "')";
    char why[300];
    if (sp.diameters_m.empty())
      std::snprintf(why, sizeof why,
                    "its share (%.3g m^2 of the slice) holds %.2f of its mean disk, and the draw places its first "
                    "disk whatever size it takes only with half the largest's area (%s mm, %.3g m^2)",
                    species_area_m2(scene, k), expected_disks(scene, k), fine_size_text(in_mm(sp.d_max_m)).c_str(),
                    0.25 * kPi * sp.d_max_m * sp.d_max_m);
    else
      std::snprintf(why, sizeof why,
                    "its share (%.3g m^2 of the slice) is under half a disk of its smallest size (%s mm, %.3g m^2)",
                    species_area_m2(scene, k), fine_size_text(in_mm(sp.smallest_diameter_m())).c_str(),
                    0.25 * kPi * sp.smallest_diameter_m() * sp.smallest_diameter_m());
    // A cut-off that leaves the species only its coarser sizes is what takes its last disk.
    Scene every_size = scene;
    every_size.solver.size_cutoff_m = 0.0;
    if (scene.solver.size_cutoff_m > 0.0 && species_gets_a_disk(every_size, k))
      throw InputError(file, "solver.size_cutoff",
                       "a cut-off that leaves " + name + " at least one disk: with its sizes from " +
                           fine_size_text(in_mm(sp.smallest_diameter_m())) + " mm only, " + why +
                           " (with every size it gets " + count_text(expected_disks(every_size, k)) +
                           "); lower the cut-off or raise the filling");
    throw InputError(file, sp.is_ball ? "charge.ball_filling" : "charge.filling",
                     "a filling that gives " + name + " at least one disk: " + why +
                         "; raise the filling or use smaller sizes");
  }
  const double total = expected_charge_disks(scene);
  if (!(total <= double(kMaxDisks)))
    throw InputError(file, "charge.filling",
                     "expected a charge of at most " + count_text(double(kMaxDisks)) + " disks, got about " +
                         count_text(total) + " (smallest particle " +
                         size_text(2e3 * scene.smallest_particle_radius_m()) +
                         " mm; raise solver.size_cutoff)");
}

void check_liner_size(const Scene& scene, const std::string& file) {
  // A lifter needs edges of its own to wear, a shell plate between two lifters at least one.
  if (!scene.mill.lifter.points.empty()) {
    const double height = measure_profile(scene.mill.lifter.points).height_m;
    if (scene.mill.mesh.lifter_edge_m > height)
      throw InputError(file, "lifters.lifter_edge",
                       "expected edges of at most the lifter's height (" + count_text(height * 1e3) +
                           " mm) so the lifter has edges of its own to wear, got " +
                           count_text(in_mm(scene.mill.mesh.lifter_edge_m)) + " mm");
  }
  const double pitch = 2.0 * kPi * scene.radius_m() / scene.mill.rows;
  if (scene.mill.mesh.shell_edge_m > pitch)
    throw InputError(file, "lifters.shell_edge",
                     "expected edges of at most the lifter pitch (" + count_text(pitch * 1e3) + " mm), got " +
                         count_text(in_mm(scene.mill.mesh.shell_edge_m)) + " mm");
  const double shell = 2.0 * kPi * scene.radius_m() / scene.mill.mesh.shell_edge_m;
  const double lifters =
      scene.mill.rows * polyline_length(scene.mill.lifter.points) / scene.mill.mesh.lifter_edge_m;
  if (shell + lifters <= double(kMaxLinerEdges)) return;
  throw InputError(file, shell > lifters ? "lifters.shell_edge" : "lifters.lifter_edge",
                   "expected a liner of at most " + count_text(double(kMaxLinerEdges)) + " edges, got about " +
                       count_text(shell + lifters) + " (" + count_text(shell) + " on the shell, " +
                       count_text(lifters) + " on the lifters)");
}

double down_to_3_digits(double x) {
  if (!(x > 0.0)) return 0.0;
  const double unit = std::pow(10.0, std::floor(std::log10(x)) - 2.0);
  return std::floor(x / unit) * unit;
}

double charge_placement_radius_m(const MillGeometry& mill, double largest_diameter_m) {
  double tip_radius = mill.radius_m;
  for (const Vec2& p : mill.boundary) tip_radius = std::min(tip_radius, length(p));
  return tip_radius - 0.05 * largest_diameter_m;
}

void check_charge_fits(const Scene& scene, const MillGeometry& mill, const std::string& file) {
  const double r_place = charge_placement_radius_m(mill, 2.0 * scene.largest_particle_radius_m());
  const auto placed = scene.species_as_placed();
  double solid_m2 = 0.0;
  for (std::size_t k = 0; k < placed.size(); ++k)
    if (scene.species_in_use(placed[k])) solid_m2 += species_area_m2(scene, k);
  const double room_m2 = kMaxTipCircleShare * kPi * r_place * r_place;
  if (r_place > 0.0 && solid_m2 <= room_m2) return;
  // The disks' area is proportional to the filling (balls to ball_filling): both scale alike.
  // The suggestion is rounded down to three digits, so that it is taken when given back.
  const double scale = r_place > 0.0 ? room_m2 / solid_m2 : 0.0;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "a charge that fits inside the lifter tips: its disks (%.4g m^2 at this filling) may take %.0f%% of "
                "the circle the charge is placed in (radius %.4g mm, inside the tips), %.4g m^2; a filling of at "
                "most %.3g",
                solid_m2, 100.0 * kMaxTipCircleShare, r_place * 1e3, std::max(0.0, room_m2),
                down_to_3_digits(scene.charge.filling * scale));
  std::string expected = buf;
  if (scene.charge.ball_filling > 0.0) {
    std::snprintf(buf, sizeof buf, " with a ball_filling of at most %.3g", down_to_3_digits(scene.charge.ball_filling * scale));
    expected += buf;
  }
  throw InputError(file, "charge.filling", expected);
}

void check_run_limits(const Scene& scene, const std::string& file) {
  check_step_counts(scene, file);
  check_filling(scene, file);
  check_liner_size(scene, file);
  check_numerical_limits(scene, file);
  check_profile_features(scene, file);
  check_charge_fits(scene, build_scene_mill(scene), file);
}

}  // namespace millwear
