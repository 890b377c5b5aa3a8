#pragma once
// A run's figures with their errors: each design's stages from its one history (batch-means
// errors) or from its replicates, and the comparison of every design with the reference.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "metrics/estimates.hpp"
#include "scene/scene.hpp"
#include "wear/history.hpp"

namespace millwear::study {

// One lifter (the design's, or one kind of a pattern) at a stage: its area and height, the
// area-loss rate measured on it with the rate's batch-means relative error, and the standard
// errors of the area and height the stage's wear removed (StageRecord::worn_se). NaN: not
// recorded (stage files written before these errors were kept); the area's error is then
// approximated from the rate's over the stage's hours, and the height's from the area's in
// proportion to what each has lost.
struct LifterAtStage {
  double hours = 0.0, area_m2 = 0.0, height_m = 0.0, rate_m2_per_s = 0.0, rate_rel_sem = 0.0;
  double worn_area_se_m2 = std::nan(""), worn_height_se_m = std::nan("");
};

// The lifter through the stages with errors: the area's and the height's errors at stage k add
// up those of the area and height stages 0..k-1 removed, as independent; `life` is life_h (NaN
// if none) with life_error_h's error.
// area0 and height0 are the new lifter's.
std::vector<KindEstimate> track_lifter(const std::vector<LifterAtStage>& at, double area0, double height0,
                                       double life_h, double replacement_height_m, Estimate& life);

// The life's standard error, propagated through the estimator compute_life uses: the line
// through the heights of two stages a < b (wear/life.hpp's life_line) reaches the replacement
// height at life = h_a + (H_a - H_r)(h_b - h_a) / (H_a - H_b). Stage b's height error is stage
// a's plus that of the height removed between them, so the two are correlated. NaN without a
// life line (no stages, or no trend to extrapolate); 0 when the first stage is at or under the
// replacement height already.
double life_error_h(const std::vector<LifterAtStage>& at, double area0, double height0, double replacement_height_m);

// One history's figures with batch-means errors, from stage records (track_lifter). A pattern
// of kinds adds each kind's lifter and life (kind_life_h from compute_life) in the same way,
// from each kind's own rates, and its life is its shortest-lived kind's, with that kind's
// error.
DesignEstimate estimate_history(const std::string& name, const Scene& scene, const std::map<int, StageRecord>& stages,
                                double life_h, bool life_extrapolated, const std::vector<double>& kind_life_h = {},
                                const std::vector<bool>& kind_life_extrapolated = {});

// Every design against the reference: life; area loss at the last stage both finished at the
// same hours (none if their stages never meet); power, specific power, collision power,
// utilization, liner shear power and liner wear per energy at the new stage.
std::vector<Verdict> compare_designs(const std::vector<DesignEstimate>& designs, const std::string& reference);

}  // namespace millwear::study
