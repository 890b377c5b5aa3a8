#pragma once
// A validated scene: the mill, its lifters, the charge, the solver and the wear settings,
// all in SI units. Read once from a TOML file by load_scene(); the engine and the wear
// loop take it by const reference and never see a bad value (model vs data split).
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "common/units.hpp"
#include "mill/mill.hpp"
#include "profiles/profile.hpp"

namespace millwear {

// Rotation of the mill seen from the feed end. Forward = counter-clockwise = toward the
// lifter's leading face (+x in lifter-local coordinates).
enum class Direction { Forward, Reverse, Bidirectional };

struct SpeciesDef {
  std::string name = "rock";
  bool is_ball = false;               // ball filling applies to balls, the rest to rocks
  double density_kg_m3 = 2700.0;
  // Size distribution (diameters): discrete sizes with mass fractions, or a uniform range.
  std::vector<double> diameters_m;    // discrete sizes (empty when uniform)
  std::vector<double> mass_fractions; // same length, sums to 1
  double d_min_m = 0.0, d_max_m = 0.0;  // uniform range (used when diameters_m is empty)
  // With a size distribution: the share of its mass the classes hold (the rest, finer than
  // the smallest class, goes to them when the fractions are normalised); 0 without one.
  double distribution_held = 0.0;
  // With a size distribution: the share of its mass coarser than the largest class's size
  // (which that class holds); 0 without one.
  double distribution_coarse = 0.0;
  double friction = 0.5;              // against other particles (pair: geometric mean)
  double restitution = 0.3;           // against other particles (pair: larger of the two)
  double friction_liner = 0.5;        // against the liner
  double restitution_liner = 0.3;     // against the liner
  double rolling_resistance = 0.0;    // dimensionless, times radius gives the lever arm
  // The smallest and largest sizes that get disks (a listed size with no share of the mass
  // gets none, and sets no limit).
  double smallest_diameter_m() const;
  double largest_diameter_m() const;
  // The same species with every size below cutoff_m left out: discrete sizes are dropped
  // and the remaining mass fractions renormalised; a uniform range starts at the cut-off.
  // The species' share of the filling is unchanged (its mass goes to the sizes kept).
  // A size within a billionth below the cut-off counts as at it (1.5 x 25 mm reached by
  // arithmetic is a hair above a 37.5 mm class read from a file): size_kept.
  // Precondition: size_kept(largest_diameter_m(), cutoff_m) (load_scene checks it).
  SpeciesDef without_sizes_below(double cutoff_m) const;
  static bool size_kept(double diameter_m, double cutoff_m) { return diameter_m >= cutoff_m * (1.0 - 1e-9); }
};

struct MillDef {
  double diameter_m = 10.0;         // inside the shell, before lifters
  double length_m = 5.0;            // belly length, for per-mill figures
  double slice_thickness_m = 0.0;   // 0: the largest particle diameter
  double speed_fraction_critical = 0.75;  // set from speed_rpm when given
  Direction direction = Direction::Forward;
  double reverse_every_hours = 750.0;     // bidirectional only
  int rows = 48;                          // lifter rows
  LifterProfile lifter;                   // every row's, or the first kind of a pattern
  // [lifters] pattern: kinds of lifter repeating over the rows (row k is of kind
  // k % pattern.size(); rows a multiple of it), e.g. a high and a low lifter. Empty: every
  // row is `lifter`.
  std::vector<LifterProfile> pattern;
  MillMeshDef mesh;
  int kind_count() const { return pattern.empty() ? 1 : static_cast<int>(pattern.size()); }
  // Every lifter of the liner is of kind 0's shape (one kind, or a pattern of one shape).
  bool one_lifter_shape() const;
  const LifterProfile& kind(int k) const { return pattern.empty() ? lifter : pattern[static_cast<std::size_t>(k)]; }
  // The scene key that names kind k's profile: lifters.profile, or lifters.pattern[k].
  std::string profile_key(int k) const {
    return pattern.empty() ? "lifters.profile" : "lifters.pattern[" + std::to_string(k) + "]";
  }
};

struct ChargeDef {
  double filling = 0.28;        // fraction of the mill area (bulk, voids included)
  double ball_filling = 0.12;   // part of filling made of balls
  double bulk_packing = 0.80;   // solid area fraction of a settled 2D disk bed
  std::vector<SpeciesDef> species;
};

enum class Backend { Box2D, Soft };

struct SolverDef {
  Backend backend = Backend::Soft;
  double time_step_s = 1.0 / 200.0;
  int velocity_iterations = 8;
  int position_iterations = 3;
  int substeps = 4;                  // soft backend only
  // Soft backend contact softness (Box2D v3's soft step): contact frequency and damping
  // ratio of particle-particle contacts (liner contacts get twice the frequency), and the
  // cap on the speed at which overlap is pushed out, in smallest particle radii per second.
  double contact_hertz = 0.0;        // 0: an eighth of the substep rate (substeps / dt / 8)
  // The particle-particle frequency the soft step uses: contact_hertz, at most an eighth of
  // the substep rate (Box2D v3's cap: stiffer is not resolved by one soft iteration per
  // substep), which is also what 0 asks for.
  double contact_hertz_used() const {
    const double cap = 0.125 / (time_step_s / substeps);
    return contact_hertz > 0.0 && contact_hertz < cap ? contact_hertz : cap;
  }
  double damping_ratio = 10.0;
  double push_out_radii_per_s = 20.0;
  double settle_time_s = 2.0;        // charge settles at rest before the mill turns
  double spinup_revolutions = 1.0;   // turning before anything is measured
  std::uint64_t seed = 1;
  double size_cutoff_m = 0.0;        // drop rock sizes below this (0: keep all)
  // Threads of one soft engine's step (not read from scene files: the command line's
  // --threads sets it). The results do not depend on it, bit for bit. With threads_fit_size
  // (no --threads given) it is the most the step uses: one thread per
  // kDisksPerStepThread disks of the charge (engine/engine.hpp), as a smaller share can
  // run slower on more.
  int threads = 1;
  bool threads_fit_size = false;
};

enum class WearMode { Staged, Continuous };
enum class WearRateSource { Given, AreaLossRate, HeightLossRate };

// A measuring window's batches: at least kWindowBatches (the smallest count whose batch means
// give a usable error), extended up to kMaxWindowBatches while the error misses its target
// (WearDef::target_rel_uncertainty; metrics/batch_means.hpp gives the error).
constexpr int kWindowBatches = 4;
constexpr int kMaxWindowBatches = 16;

struct WearDef {
  WearMode mode = WearMode::Staged;
  WearRateSource rate_source = WearRateSource::Given;
  double wear_rate_m3_per_J = 1e-12;      // C = K/H (real); 0 until calibrated when
                                          // rate_source is not Given
  // Shell plates of another material than the lifter bars (rubber plates between steel
  // bars): their own C, m^3/J. 0: the shell wears at the lifters' rate.
  double shell_wear_rate_m3_per_J = 0.0;
  // Operating hours of the liner the history starts from ([lifters] start_hours: a worn
  // liner measured at that time). Stage k is at start_hours + k * stage_hours.
  double start_hours = 0.0;
  // The measured loss rate C is calibrated to (rate_source AreaLossRate: lifter area, m^2/s;
  // HeightLossRate: lifter height, m/s).
  double target_loss_rate = 0.0;
  // The same rate as the file gave it (mm^2/1000 h or mm/h): the run's manifest records it,
  // and a later run or validation compares its settings with that record.
  double calibration_value = 0.0;
  double factor = 1e6;                    // C_model = factor * C
  double stage_hours = 750.0;
  int stages = 4;
  double window_revolutions = 1.5;        // staged: frozen-geometry window
  double max_depth_step_m = 0.006;        // staged: largest depth per geometry update
  double update_interval_s = 0.25;        // continuous: simulated seconds between updates
  double smoothing_radius_m = 0.0;        // 0: smallest particle radius
  bool average_rows = true;
  bool shell_wear = true;
  // Slip of disks packed against the liner (in contact for over a revolution) counts as
  // Archard shear work. Off: packed material rides with the liner and shields it, and the
  // disk's slip in a jam is its spin in place, whose size follows the soft contacts'
  // stiffness (README "Numerical limits").
  bool packed_wear = false;
  double replacement_height_m = 0.05;     // lifter life ends below this height
  double liner_density_kg_m3 = 7800.0;    // the liner's metal, for its mass lost (g/kWh)
  double target_rel_uncertainty = 0.10;   // rule 2: extend window until under (0: off)
};

// Which outputs the scene asks for; the engine switches off accounting nobody reads.
struct OutputsDef {
  bool collision_spectrum = true;
  bool shell_work = true;
  bool snapshot = true;
  bool contact_log = false;
  // ParaView files (io/vtk_files.hpp): the charge and the liner over each measuring window.
  bool vtk = false;
  int vtk_frames = 20;               // frames per measuring window
};

struct RunDef {
  double revolutions = 3.0;          // `millwear charge`: measured revolutions
};

struct Scene {
  std::string name;
  std::string source_file;
  MillDef mill;
  ChargeDef charge;
  SolverDef solver;
  WearDef wear;
  OutputsDef outputs;
  RunDef run;
  std::string fidelity = "standard";
  // Command-line overrides applied over the file, as given ("mill.speed=0.8"), in order.
  std::vector<std::string> overrides;
  // Dotted keys the scene file set ("solver.time_step", "lifters.shell_edge", ...). A key
  // set in the file beats the fidelity preset (apply_fidelity leaves it alone).
  std::set<std::string> explicit_keys;
  bool file_sets(const std::string& key) const { return explicit_keys.count(key) > 0; }

  double radius_m() const { return 0.5 * mill.diameter_m; }
  double critical_speed_rad_s() const;     // sqrt(g / R)
  double angular_speed_rad_s() const;      // magnitude
  double revolution_time_s() const;
  double slice_thickness() const;          // resolved (never 0)
  double smallest_particle_radius_m() const;
  double largest_particle_radius_m() const;
  // The species as the charge is filled: same order and count as charge.species, rock
  // species cut at solver.size_cutoff_m (balls are never cut). Smallest and largest particle
  // radius above are taken over these, counting only species with a share of the filling
  // (balls when ball_filling > 0, rocks when filling > ball_filling).
  std::vector<SpeciesDef> species_as_placed() const;
  bool species_in_use(const SpeciesDef& s) const;
};

// Read and validate a scene file. Every problem throws InputError naming the file, the key
// and what was expected; profile paths are relative to the scene file.
//
// `overrides` are `KEY=VALUE` texts (`--set` on the command line): KEY a dotted scene key
// ("mill.speed", "charge.species[1].density", "outputs.vtk"), VALUE a TOML value ("0.8",
// "true", "[100, 150]", "\"reverse\"") or a bare word taken as a string ("reverse"). Each is
// put into the file's table before anything is read, so it is typed, range-checked and
// cross-checked by the same readers as the file; an error in it names "--set KEY". Setting
// one of a pair of alternatives removes the file's other one (mill.speed / speed_rpm,
// solver.time_step / steps_per_second, the three wear-rate keys; a species' size_range
// removes its sizes, mass_fractions and distribution keys, and a distribution key its
// mass_fractions and size_range; a distribution's form removes the other form's scale).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
// Whether the override `later` (KEY=VALUE), put in after `earlier`, leaves nothing of it: the
// same key, a table or element that holds it, or a key whose setting removes it (above).
// False for a malformed override, which load_scene names.
bool override_replaces(const std::string& later, const std::string& earlier);
// The seeds s .. s + count - 1 a command derives from the scene's solver.seed s (replicates,
// rule 1's factors, a reseeded run) within what a scene file's seed holds (0 to 2^63 - 1), so
// that every seed a manifest records can be given back in a scene: throws
// InputError(source_file, "solver.seed", ...) naming `what` asked for them.
void check_derived_seeds(const Scene& scene, std::uint64_t count, const std::string& what);
// The scene file's TOML with `overrides` put in exactly as load_scene puts them (same errors),
// written back as TOML text (comments and layout not kept): where a command that writes
// scenes of its own from a scene (the screen's candidates) starts from. It does not check
// the scene; load_scene(path, overrides) does.
std::string overridden_scene_toml(const std::string& path, const std::vector<std::string>& overrides);
// The same for a scene's text as if read from `path` (errors name it; the profile path
// resolves from its folder): how an edited scene is checked before it is used or written.
Scene load_scene_text(const std::string& text, const std::string& path);
// A scene's built mill geometry (the lifters it starts from, one unit per kind shared by
// every row of that kind), and one kind's liner unit alone: the one place a scene's lifter
// becomes geometry. A measured profile's unit is its surface as measured (resampled).
MillGeometry build_scene_mill(const Scene& scene);
LinerUnit new_liner_unit(const Scene& scene, int kind = 0);

}  // namespace millwear
