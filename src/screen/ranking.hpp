#pragma once
// Ranking screened designs by lifter life, with the life's statistical uncertainty, ties
// within that uncertainty, and Pareto fronts of life against power draw and utilization.
//
// A design's life and its standard error (life_sigma_h) are the ones `millwear run` writes
// for it (summary.csv's life_h and life_h_se, study/design_estimates.hpp): with one history,
// propagated from the batch-means errors of the stages' wear; with replicates (`screen
// --replicates N`: N histories per design, seeds s .. s + N - 1), the standard error of their
// mean life, from their spread.
// Ties: a finished design is tied with the best when their lives' difference is not resolved
// by the rule of the run's verdicts (metrics/estimates.hpp): more than 2 combined standard
// errors with one history each; with replicates, Student's t at the same level for the
// histories both designs have.
#include <string>
#include <vector>

#include "screen/screen.hpp"

namespace millwear::screen {

// What a design's folder says.
struct DesignResult {
  Candidate design;
  std::string status = "missing";  // finished, failed, missing
  std::string reason;              // failed: the error; missing: what was found
  std::string figure_error;        // finished, but its run's figures failed (task.status's reason)
  double life_h = std::nan("");
  double life_sigma_h = std::nan("");
  int replicates = 1;                                    // histories behind the figures
  std::string error_source = "batch_means";  // or "replicates" (their spread)
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
