#pragma once
// Limits of a scene, checked before anything is filled, simulated or written: what the
// stability suite (tests/stability_*.cpp, docs/stability.md) measured as safe, and the
// sizes a run can take. Every command runs check_run_limits after its own overrides
// (fidelity, revolutions) and before it creates its output folder; the filling and the
// settling check again, so a scene built in code meets the same limits.
//
// Checked here (InputError naming the file, the key and the limit):
// - time step against particle size: a disk must not travel more than
//   kMaxStepTravelRadii of the smallest radius in one step at the scene's impact speed
//   (impact_speed_m_s): beyond it contacts are found too late, the position correction
//   cannot push the overlap out, and disks leak through the one-sided liner.
// - the lifter's thinnest part against the particles: metal thinner than the smallest
//   particle radius lets a disk touch both of its faces at once, and disks leak through.
// - counts, in 64 bits: steps of every phase (settling, spin-up, a measuring window or
//   `charge`'s revolutions, a continuous stage), disks of the filling (none in a species
//   that has a share of it is an error), liner edges; at most kMaxSpecies species.
// Reported as events during a run instead (they depend on the run, not the input):
// escaped or non-finite disks (engine), a lifter worn to the shell and rule 1's one-update
// bound on wear.factor (wear loop).
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace millwear {

// The fastest a disk meets the liner or another disk in this mill: the shell speed plus a
// free fall across the mill, omega R + sqrt(2 g D) (an upper bound: a cataracting disk
// leaves the shell at the shell speed and falls at most a diameter).
double impact_speed_m_s(const Scene& scene);

// Distance a disk at the impact speed travels in one step, in smallest particle radii.
double step_travel_radii(const Scene& scene);

// The largest step travel found safe on the Box2D backend: the sweep (bench/stability_sweep,
// docs/stability.md) ran 6, 15 and 40 mm disks clean up to 1.57 radii per step and lost the
// first disks at 1.97-3.15 radii (leaks grow with disk count and run length, so the limit
// sits at the clean edge, not the first leak).
constexpr double kMaxStepTravelRadii = 1.6;
// The soft backend is held to kMaxStepTravelRadii per substep, and to this per step: it finds
// the contacts and fixes their normals once a step, so whatever the substeps a disk must not
// move too far within one. The sweep (bench/stability_sweep soft_step, docs/stability.md)
// ran 15 mm disks clean at 6 and 8 radii per step (12 runs) and lost a first disk in 2 of 6
// runs at 10: the limit sits at the clean edge.
constexpr double kMaxSoftStepTravelRadii = 8.0;

// The mill speed as a fraction of critical (mill.speed; mill.speed_rpm the same in rpm), and
// the view's speed control. 0.01: a mill turning slower hardly lifts its charge (and one
// revolution takes hours of simulated time in a large mill); 2: far past centrifuging.
constexpr double kMinSpeedFraction = 0.01;
constexpr double kMaxSpeedFraction = 2.0;

// Every time in hours, in files and on the command line, is at most 1e6 h (over a century of
// operation).
constexpr double kMaxHours = 1e6;
// The shortest stage, wear.stage_hours, in hours. A stage's first wear update re-smooths the
// liner, which takes a little metal whatever the hours; under an hour that is the stage's wear.
constexpr double kMinStageHours = 1.0;
// The most stages of one history, wear.stages.
constexpr int kMaxStages = 10000;

// The most steps of any one phase: settling, spin-up, `charge`'s revolutions, a measuring
// window (all its batches), the simulated time of a continuous stage. 1e8 steps of a
// thousand disks are days of computing; a count past it is a typo, not a plan.
constexpr std::int64_t kMaxPhaseSteps = 100'000'000;
// The most disks a filling may ask for, and the most edges of the liner.
constexpr std::int64_t kMaxDisks = 2'000'000;
constexpr std::int64_t kMaxLinerEdges = 1'000'000;

// Steps of `seconds` at time step dt (ceil, less a 1e-9 tolerance), in 64 bits;
// INT64_MAX when the count does not fit (or is not a number).
std::int64_t steps_in(double seconds, double dt_s);

// Each throws InputError(file, key, ...) for a scene outside its limit.
void check_numerical_limits(const Scene& scene, const std::string& file);  // time step
void check_profile_features(const Scene& scene, const std::string& file);
// The refusal of lifter kind `kind` whose thinnest part (thinnest_m) is under the smallest
// particle radius (needed_m); `resmoothed`: the surface measured is a scan's, once re-smoothed.
[[noreturn]] void refuse_thin_lifter(const Scene& scene, const std::string& file, int kind, double needed_m,
                                     double thinnest_m, bool resmoothed);
void check_step_counts(const Scene& scene, const std::string& file);
// A disk's species is one byte in the engines (engine/charge.hpp).
constexpr std::size_t kMaxSpecies = 256;
void check_filling(const Scene& scene, const std::string& file);
void check_liner_size(const Scene& scene, const std::string& file);
// The charge's disks go inside the circle through the lifter tips of `mill`: their area (the
// filling's, the same for every seed) at most kMaxTipCircleShare of that circle's, less a
// clearance of a twentieth of the largest diameter (engine/fill.cpp places them there).
constexpr double kMaxTipCircleShare = 0.6;
// The circle the fill places the charge in: through the lifter tips (the boundary's point
// nearest the centre), less the clearance of a twentieth of the largest diameter.
double charge_placement_radius_m(const MillGeometry& mill, double largest_diameter_m);
// x rounded down to three significant digits (0 for x <= 0): a suggested limit that holds
// when given back.
double down_to_3_digits(double x);
void check_charge_fits(const Scene& scene, const MillGeometry& mill, const std::string& file);

// The heaviest disk's mass over the lightest's, over the species in use and the sizes that
// get disks (a slice's disks: density x diameter^2); 0 with no disk.
double particle_mass_ratio(const Scene& scene);
// The largest time step the limits above allow (per substep on the soft backend, and the
// soft solver's per-step limit), at the scene's impact speed; 0 with no disk.
double time_step_limit_s(const Scene& scene);
// The stability suite ran small disks among heavy ones sound up to this mass ratio (with few
// small disks); beds of many light disks among far heavier ones lose an occasional disk
// (docs/stability.md, "Many light disks among heavy ones").
constexpr double kSoundMassRatio = 100.0;
// How far the lowest soft contacts of the settled bed overlap under its weight, in smallest
// radii: about 2 n g / w^2 for n layers of disks (the bed's depth at its filling over the
// disks' mean diameter) on contacts of angular frequency w = 2 pi contact_hertz_used, each
// carrying the disks above it on half a disk's mass. The lab mill measured 0.45 and 0.13 of
// the smallest radius at 40 and 80 Hz where this gives 0.42 and 0.11; at 10 Hz disks end
// inside each other (docs/stability.md). 0 on the library backend and with no disk.
double bed_overlap_radii(const Scene& scene);
// Past this the contacts are too soft for the bed: a note, as a softer contact is a choice.
constexpr double kSoundBedOverlapRadii = 0.25;
// What the scene asks beyond the measured sound range, for --check: a mass ratio above
// kSoundMassRatio, with the scene's time step against its limit; contacts that let the bed
// sink past kSoundBedOverlapRadii, with the frequency that would not.
std::vector<std::string> limit_notes(const Scene& scene);

// All of the above, in the order a user would fix them.
void check_run_limits(const Scene& scene, const std::string& file);

}  // namespace millwear
