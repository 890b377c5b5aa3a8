#pragma once
// Figures with their standard errors, and the verdict of a comparison between two designs.
//
// A figure's error comes from one of two places. With several independent histories of a
// design (replicates: the same scene with seeds s, s+1, ...) it is the standard error of their
// mean, the spread a new set of seeds would show. With one history it comes from the batches
// of each measuring window (batch means), which takes the batches as independent, and the
// lifter's from the windows of each stage's wear (study/design_estimates.hpp). Neither bounds
// the spread between histories from either side: a charge's state carries over from one batch
// to the next, and a worn shape feeds back into the wear of the next stage (docs/run.md
// compares them with the spread of seeds).
//
// The verdict: design A is ahead of design B on a figure when the difference of their means
// exceeds a threshold of combined standard errors (sqrt(se_A^2 + se_B^2)): kResolvedSigmas for
// one history's batch means; with replicates, Student's t at the same level (a normal
// variable's chance of lying within kResolvedSigmas, 95.4%) for the Welch-Satterthwaite degrees
// of freedom of the two means, since a few histories' spread is itself uncertain (two
// replicates per design: 4.5 to 14 errors; four: 2.5 to 3.3; sixteen: 2.1 to 2.2; it falls to
// kResolvedSigmas as the histories grow). Otherwise the difference is not resolved, and the
// replicates that would resolve it are estimated from the per-history spread (se * sqrt(n)) as
// the smallest count at which the same difference would pass that count's threshold. (Designs
// of unequal replicate counts are compared at the smaller count: conservative.)
#include <cmath>
#include <string>
#include <vector>

namespace millwear {

struct Estimate {
  double mean = std::nan("");
  double se = std::nan("");  // standard error of the mean (NaN: unknown)
};

// Mean and standard error of independent values (se NaN for fewer than two).
Estimate mean_and_se(const std::vector<double>& values);

// Where the errors of a design's figures come from.
enum class ErrorSource { BatchMeans, Replicates };
const char* error_source_name(ErrorSource s);  // "batch_means", "replicates"

constexpr double kResolvedSigmas = 2.0;

struct Difference {
  double value = std::nan("");  // a - b
  double se = std::nan("");     // sqrt(se_a^2 + se_b^2)
  double threshold = kResolvedSigmas;  // combined errors a resolved difference exceeds
  bool resolved = false;        // |value| > threshold * se
  // Not resolved: replicates per design (each side the same count) about which the same
  // difference would be resolved; 0 when resolved; -1 when no count would (no difference or
  // no error known).
  int replicates_needed = -1;
};

// a and b with `replicates` histories each; their errors from those histories' spread
// (ErrorSource::Replicates) or from one history's batch means.
Difference compare(const Estimate& a, const Estimate& b, int replicates, ErrorSource source);

// Student's t at the level of kResolvedSigmas for `dof` degrees of freedom (kResolvedSigmas
// for infinitely many), and the Welch-Satterthwaite degrees of freedom of the difference of
// two means with standard errors se_a, se_b from n histories each.
double resolved_threshold(double dof);
double welch_dof(double se_a, double se_b, int n);

// One kind of lifter of a pattern at one stage (SI; the mean over the rows of the kind).
struct KindEstimate {
  Estimate area_m2, area_loss_fraction, height_m, area_loss_rate_m2_per_s;
};

// A design's figures at one stage of its wear history (SI; power per mill).
struct StageEstimate {
  int stage = 0;
  double hours = 0.0;
  Estimate area_m2, area_loss_fraction, height_m;  // lifter (row 0, or the first kind)
  Estimate power_W, collision_W, liner_shear_W, utilization;
  Estimate charge_mass_kg, specific_power_W_per_kg, liner_wear_kg_per_J;
  Estimate centre_of_mass_deg, toe_deg, shoulder_deg;  // toe, shoulder NaN where centrifuged
  Estimate packed_shear_share;
  int centrifuged = 0;  // histories whose charge centrifuged at this stage
  std::vector<KindEstimate> kinds;  // a pattern of kinds: each kind's lifter; else empty
};

// A design's figures over its history, with their errors.
struct DesignEstimate {
  std::string name;
  int replicates = 1;
  ErrorSource source = ErrorSource::BatchMeans;
  std::vector<StageEstimate> stages;  // the stages every history finished
  Estimate life_h;
  bool life_extrapolated = true;      // any history's life was extrapolated
  // A pattern of kinds: each kind's life (the liner's is the shortest) and whether any
  // history's was extrapolated; else empty.
  std::vector<Estimate> kind_life_h;
  std::vector<bool> kind_life_extrapolated;
};

// Mean and standard error over independent histories of one design: each figure's mean over
// the histories' values (NaN values left out), at the stages they all finished.
DesignEstimate combine_histories(const std::string& name, const std::vector<DesignEstimate>& histories);

// One figure of a design set against the reference design.
struct Verdict {
  std::string figure;     // summary.csv's column name, e.g. "life_h", "power_kw"
  std::string unit;       // at the file edge: "h", "kW", "%", "g/kWh", ...
  int stage = -1;         // the stage compared (-1: the whole history, as life)
  double hours = 0.0;
  std::string design, reference;
  Estimate value, reference_value;  // at the file edge's units
  Difference difference;
  int replicates = 1;
  ErrorSource source = ErrorSource::BatchMeans;
  std::string text;       // one line: which is ahead, by how much, resolved or not
};

}  // namespace millwear
