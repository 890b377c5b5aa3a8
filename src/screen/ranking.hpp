#pragma once
// Ranking screened designs by lifter life, with the life's statistical uncertainty, ties
// within that uncertainty, and Pareto fronts of life against power draw and utilization.
//
// Life uncertainty (rule 2): each stage's measured lifter area-loss rate carries a
// batch-means relative error s_k (StageRecord::area_loss_rate_rel_sem). Stage k's rate sets
// the wear between its hours and the next stage's (the last measured rate carries the
// extrapolation to the life). The life is the time to lose a fixed amount of metal, so to
// first order its relative error is that of the mean rate over the life:
//     sigma_life / life = sqrt(sum_k (A_k s_k)^2) / sum_k A_k,
// with A_k = rate_k x (hours of the life spent in segment k), the area that segment's rate
// removes; segments are independent windows, so their errors add in quadrature.
// With replicates (`screen --replicates N`: N histories per design, seeds s .. s + N - 1),
// sigma is instead the standard error of their mean life, from their spread (summary.csv's
// life_h_se): the batch-means figure above is a lower bound, as the histories scatter more
// than one history's windows say.
// Ties: a finished design is tied with the best if their lives differ by at most twice the
// combined standard uncertainty, 2 sqrt(sigma_best^2 + sigma^2) (about 95%).
#include <string>
#include <vector>

#include "screen/screen.hpp"

namespace millwear::screen {

// One stage's figures needed for the life's uncertainty.
struct StageRate {
  double hours = 0.0;                   // operating hours of the stage
  double area_loss_rate_m2_per_s = 0.0; // lifter area lost per operating second
  double rel_sem = 0.0;
};

// sigma of the life (h) from the stages' rates (see above). NaN if life is not finite or
// there are no stages; 0 if no rate has an error.
double life_sigma_h(const std::vector<StageRate>& stages, double life_h);

// What a design's folder says.
struct DesignResult {
  Candidate design;
  std::string status = "missing";  // finished, failed, missing
  std::string reason;              // failed: the error; missing: what was found
  double life_h = std::nan("");
  double life_sigma_h = std::nan("");
  int replicates = 1;                                    // histories behind the figures
  std::string error_source = "batch_means_lower_bound";  // or "replicates" (their spread)
  bool life_extrapolated = false;
  double power_W = std::nan(""), collision_W = std::nan(""), utilization = std::nan("");  // new liner, per mill
  double power_se_W = std::nan(""), collision_se_W = std::nan(""), utilization_se = std::nan("");  // their errors
  double area_loss_mm2_per_1000h = std::nan("");  // over the simulated stages, from summary.csv's mm^2 and hours
  // Filled by rank_designs.
  int rank = 0;                    // 1 = longest life; 0 = not ranked
  bool tied_with_best = false;
  bool pareto_power = false, pareto_utilization = false;
};

// Reads OUT/designs/NAME: task.status (written by `millwear screen-task`), then the run
// folder's summary.csv and stage records. Never throws: a folder that cannot be read is a
// missing or failed design with the reason.
DesignResult read_design_result(const std::string& out, const Candidate& c);

// True where a point is on the Pareto front: no other point is at least as good in both
// (a larger, b larger if b_higher_is_better else smaller) and better in one. NaN: never.
std::vector<bool> pareto_front(const std::vector<double>& a, const std::vector<double>& b, bool b_higher_is_better);

// Ranks the finished designs by life (longest first; equal lives by task order), marks
// ties with the best and the Pareto fronts (life vs power, life vs utilization). Returns
// the rows in ranking order: ranked designs, then failed, then missing.
std::vector<DesignResult> rank_designs(std::vector<DesignResult> results, bool power_higher_is_better);

// OUT/ranking.csv. Columns: rank, design, status, life_h, life_sigma_h, life_extrapolated,
// tied_with_best, replicates, error_source, power_kw, power_kw_se, collision_kw,
// collision_kw_se, utilization, utilization_se, area_loss_mm2_per_1000h, pareto_power,
// pareto_utilization, the design's parameters, reason. No wall times: the file depends only
// on the designs' results (bit-identical for any number of workers).
void write_ranking(const std::string& out, const std::vector<DesignResult>& ranked);

}  // namespace millwear::screen
