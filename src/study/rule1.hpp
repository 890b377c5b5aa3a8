#pragma once
// Rule 1 of the method: scaling C_model by n and simulated time by 1/n gives the same worn
// profiles, as long as the liner changes little within one update. Checked by running the
// wear history in continuous mode at several factors, each several times with different
// seeds, and asking whether each factor's profile parts from the smallest factor's by more
// than the tolerance once the scatter between seeds is taken into account.
//
// The statistic. The new lifter's surface is sampled at stations a fixed arc length apart;
// a replicate's worn depth at a station is its distance to the replicate's final surface.
// Per factor and station: the mean depth over the replicates and its standard error (their
// standard deviation / sqrt(N)). A factor's deviation at a station is the difference of its
// mean depth from the smallest factor's; its error, the two standard errors combined in
// quadrature. The noise floor, what seed-to-seed scatter alone gives, is twice that error.
// A factor agrees when at no station the deviation exceeds the tolerance by more than twice
// its error (not significantly above noise plus tolerance), and its seeds do not scatter
// significantly more than the smallest factor's: rule 1 asks for the same profile, so the
// same spread too. (A factor so large that a stage is a fraction of a revolution wears each
// seed by the few charge configurations it happens to meet; its mean may agree while single
// seeds gouge the lifter.) The scatter is the root mean square over the stations of the
// replicates' standard deviation; the test, the ratio of the two variances against Fisher's
// F distribution with N - 1 degrees of freedom each, one-sided at 5%. The recommendation is
// the largest factor that agrees, with every smaller one agreeing too.
#include <cstdint>
#include <string>
#include <limits>
#include <vector>

#include "geometry/polyline.hpp"
#include "scene/scene.hpp"

namespace millwear {

// The factors compared when none are given: half, once, twice and ten times the scene's.
std::vector<double> default_rule1_factors(double scene_factor);

struct Rule1Options {
  std::vector<double> factors;        // C_model / C; run in increasing order
  int replicates = 4;                 // histories per factor (seeds differ)
  double tolerance_pct_height = 5.0;  // allowed deviation, % of the new lifter's height
  int jobs = 0;                       // histories at once (0: the hardware's cores)
};

struct Rule1Replicate {
  std::uint64_t seed = 0;
  double simulated_s = 0.0;
  double wall_s = 0.0;
  Polyline profile;                   // final unit surface (lifter-local, m); empty on failure
  std::vector<std::string> events;    // a failure, or events that make the run suspect
};

enum class Rule1Verdict {
  Reference,    // the smallest factor: what the others are compared with
  Agrees,       // deviation not significantly above the tolerance
  Deviates,     // deviation significantly above the tolerance
  Scatters,     // the mean agrees, but the seeds scatter significantly more than the reference's
  Failed,       // a replicate failed or reported events (rule 1's bound, a lost disk)
};
const char* verdict_name(Rule1Verdict v);

struct Rule1Row {
  static constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  double factor = 0.0;
  std::vector<Rule1Replicate> replicates;
  std::vector<double> depth_mean_m;   // per station
  std::vector<double> depth_se_m;     // per station (0 with one replicate)
  // At the station where the deviation exceeds the tolerance by the most standard errors
  // (where it is largest when there is no error):
  // NaN where a figure needs an error and one of the two rows has one replicate (no error known).
  double deviation_m = 0.0;           // |mean depth - the smallest factor's|
  double deviation_se_m = kUnknown;   // its standard error
  double max_deviation_m = 0.0;       // largest |difference| over all stations
  double noise_floor_m = kUnknown;    // largest 2 x standard error over all stations
  double scatter_m = 0.0;             // rms over the stations of the replicates' standard deviation
  double scatter_ratio = kUnknown;    // (scatter / the smallest factor's)^2
  double scatter_p = kUnknown;        // chance of a ratio this large from equal spreads
  // Chance that the true deviation at that station is within the tolerance (normal
  // approximation).
  double chance_within = kUnknown;
  Rule1Verdict verdict = Rule1Verdict::Reference;
};

// The simulated time of a factor's histories, averaged over its replicates.
double mean_simulated_s(const Rule1Row& row);

struct Rule1Report {
  std::vector<Rule1Row> rows;         // increasing factor
  Polyline stations;                  // on the new lifter surface (lifter-local, m)
  Polyline new_profile;               // the new unit surface
  double lifter_height_m = 0.0;
  double tolerance_pct_height = 0.0;
  int replicates = 0;
  double recommended_factor = 0.0;    // 0: none (the smallest factor itself failed)
  double recommended_chance = 0.0;    // its chance_within (1 for the smallest factor; NaN: unknown)
  int recommended_row = -1;           // its index in rows
};

// The statistic on two rows whose depth_mean_m and depth_se_m are filled: sets row's
// deviation, error, noise floor, chance_within and verdict (Agrees, Deviates or, with
// replicates and scatter_m filled on both, Scatters) against ref.
void compare_rule1_row(Rule1Row& row, const Rule1Row& ref, double tolerance_m);

// Every factor's scene is checked against the run limits (InputError) before anything runs.
// Replicate k of factor i runs with seed scene.solver.seed + i * replicates + k, so two
// entries of the same factor are independent samples of it.
Rule1Report rule1_check(const Scene& scene, const Rule1Options& options);

// OUT/rule1.csv (one row per factor), OUT/rule1_replicates.csv, OUT/rule1_profiles.dat (the
// final profiles in mm as x,y rows, one gnuplot block per factor headed by its title line,
// one line per replicate, the new profile first), each written atomically. Returns the files.
std::vector<std::string> write_rule1_outputs(const std::string& out, const Scene& scene, const Rule1Report& r);

// The paper's Fig. 5 from OUT/rule1_profiles.dat: OUT/plots/fig5_rule1.{png,svg}. Returns the
// files; throws RunError when gnuplot is missing or fails (plots/plots.hpp).
std::vector<std::string> render_rule1_figure(const std::string& out, const Scene& scene, const Rule1Report& r);

}  // namespace millwear
