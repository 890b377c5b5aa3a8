// Screened designs: results read from their run folders, ranked by life with uncertainty,
// Pareto fronts. See ranking.hpp for the uncertainty and tie rules.
#include "common/units.hpp"
#include "screen/ranking.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "metrics/estimates.hpp"
#include "metrics/pareto.hpp"

namespace millwear::screen {

namespace fs = std::filesystem;

DesignResult read_design_result(const std::string& out, const Candidate& c) {
  DesignResult r;
  r.design = c;
  const std::string dir = design_dir(out, c.name);
  const std::string status_file = task_status_path(out, c.name);
  if (!io::file_exists(status_file)) {
    r.reason = "never run (no task.status)";
    return r;
  }
  try {
    const io::KeyValues kv = io::read_key_values(status_file);
    const std::string status = io::find_value(kv, "status");
    if (status == "running") {
      r.reason = "started but did not finish (killed, crashed, or still running)";
      return r;
    }
    if (status == "interrupted") {  // Ctrl-C or SIGTERM: its finished stages wait for it
      r.reason = io::find_value(kv, "reason", "interrupted; run it again to continue");
      return r;
    }
    if (status == "failed") {
      r.status = "failed";
      r.reason = io::find_value(kv, "reason", "failed (no reason recorded)");
      return r;
    }
    if (status != "finished") {
      r.reason = "unknown task status '" + status + "' in task.status";
      return r;
    }
    if (io::find_value(kv, "exit_code", "0") != "0") r.figure_error = io::find_value(kv, "reason", "figures failed");
    const io::CsvData s = io::read_csv(io::summary_path(dir));
    const std::size_t cd = s.column("design");
    std::map<int, std::size_t> rows;  // stage -> row
    for (std::size_t i = 0; i < s.row_count(); ++i)
      if (s.text(i, cd) == c.name) rows[static_cast<int>(s.number(i, "stage"))] = i;
    if (rows.empty() || !rows.count(0)) {
      r.status = "failed";
      r.reason = "no new-liner stage in summary.csv";
      return r;
    }
    const std::size_t first = rows.at(0), last = rows.rbegin()->second;
    r.life_h = s.number(first, "life_h");
    r.life_extrapolated = s.number(first, "life_extrapolated") != 0.0;
    // The new liner's charge figures are measured in every finished run: a nan there is a
    // damaged table, not a design to rank.
    r.power_W = watts_from_kW(s.finite_number(first, s.column("power_kw")));
    r.collision_W = watts_from_kW(s.finite_number(first, s.column("collision_kw")));
    r.utilization = s.finite_number(first, s.column("utilization"));
    r.power_se_W = watts_from_kW(s.number(first, "power_kw_se"));
    r.collision_se_W = watts_from_kW(s.number(first, "collision_kw_se"));
    r.utilization_se = s.number(first, "utilization_se");
    // A pattern of kinds: the liner's life is the kind's that reaches the replacement height
    // first (the shortest kindK_life_h in summary.csv); its own area counts.
    std::string area_col = "area_mm2";
    double shortest = std::numeric_limits<double>::infinity();
    for (int k = 0; s.has_column("kind" + std::to_string(k) + "_life_h"); ++k) {
      const double life_k = s.number(first, "kind" + std::to_string(k) + "_life_h");
      if (life_k < shortest) {
        shortest = life_k;
        area_col = "kind" + std::to_string(k) + "_area_mm2";
      }
    }
    const double hours = s.number(last, "hours") - s.number(first, "hours");
    r.area_loss_mm2_per_1000h =
        hours > 0.0 ? (s.number(first, area_col) - s.number(last, area_col)) / hours * 1000.0 : std::nan("");
    // The life's error as `millwear run` gives it: from the replicates' spread, or from one
    // history's batch means.
    r.replicates = s.has_column("replicates") ? static_cast<int>(s.number(first, "replicates")) : 1;
    r.life_sigma_h = s.number(first, "life_h_se");
    if (s.has_column("error_source")) r.error_source = s.text(first, s.column("error_source"));
    r.status = "finished";
  } catch (const InputError& e) {
    // The file named as it lies in OUT: the ranking holds no path of OUT's own (the same bytes
    // whatever OUT was called on the command line).
    r.status = "failed";
    const fs::path rel = fs::path(e.file).lexically_relative(out);
    const std::string file = e.file.empty() || rel.empty() || *rel.begin() == ".." ? e.file : rel.generic_string();
    r.reason = "results unreadable: " + InputError::format(file, e.where, e.expected);
  } catch (const std::exception& e) {
    r.status = "failed";
    r.reason = std::string("results unreadable: ") + e.what();
  }
  return r;
}

std::vector<DesignResult> rank_designs(std::vector<DesignResult> res, bool power_higher) {
  std::vector<DesignResult> done, failed, missing;
  for (auto& r : res)
    (r.status == "finished" ? done : r.status == "failed" ? failed : missing).push_back(r);
  // Longest life first; a life that does not exist last; equal lives in task order.
  std::stable_sort(done.begin(), done.end(), [](const DesignResult& x, const DesignResult& y) {
    const bool fx = std::isfinite(x.life_h), fy = std::isfinite(y.life_h);
    if (fx != fy) return fx;
    return fx && x.life_h > y.life_h;
  });
  // Only a life ranks: a design whose lifters never head for the replacement height (no wear,
  // or a height that does not fall) finished with no life, and stays unranked.
  for (std::size_t i = 0; i < done.size(); ++i) {
    if (std::isfinite(done[i].life_h)) {
      done[i].rank = static_cast<int>(i) + 1;
    } else {
      done[i].rank = 0;
      done[i].reason = "no life to rank: the lifters' height does not fall toward the replacement height";
    }
  }
  if (!done.empty() && std::isfinite(done[0].life_h)) {
    // Tied with the best: the lives' difference is not resolved by the comparison's own rule
    // (metrics/estimates.hpp's compare: Student's t over the replicates' spread, or one
    // history's batch-means errors). An unknown error counts as none: such a design ties only
    // with an equal life.
    const auto life_of = [](const DesignResult& r) {
      return Estimate{r.life_h, std::isfinite(r.life_sigma_h) ? r.life_sigma_h : 0.0};
    };
    const DesignResult& best = done[0];
    for (auto& r : done) {
      if (!std::isfinite(r.life_h)) continue;
      const bool spread = best.error_source == "replicates" && r.error_source == "replicates";
      const Difference d = compare(life_of(best), life_of(r), std::min(best.replicates, r.replicates),
                                   spread ? ErrorSource::Replicates : ErrorSource::BatchMeans);
      r.tied_with_best = !d.resolved;
    }
  }
  std::vector<double> life, power, util;
  for (const auto& r : done) {
    life.push_back(r.life_h);
    power.push_back(r.power_W);
    util.push_back(r.utilization);
  }
  const auto fp = pareto_front(life, Better::Higher, power, power_higher ? Better::Higher : Better::Lower);
  const auto fu = pareto_front(life, Better::Higher, util, Better::Higher);
  for (std::size_t i = 0; i < done.size(); ++i) {
    done[i].pareto_power = fp[i];
    done[i].pareto_utilization = fu[i];
  }
  std::vector<DesignResult> outv = done;
  outv.insert(outv.end(), failed.begin(), failed.end());
  outv.insert(outv.end(), missing.begin(), missing.end());
  return outv;
}

void write_ranking(const std::string& out, const std::vector<DesignResult>& ranked) {
  io::CsvTable t({"rank", "design", "status", "life_h", "life_sigma_h", "life_extrapolated", "tied_with_best",
                  "replicates", "error_source", "power_kw", "power_kw_se", "collision_kw", "collision_kw_se",
                  "utilization", "utilization_se", "area_loss_mm2_per_1000h", "pareto_power",
                  "pareto_utilization", "height_mm", "top_width_mm", "leading_face_angle_deg",
                  "trailing_face_angle_deg", "rows", "direction", "area_mm2", "reason"});
  for (const auto& r : ranked) {
    const Candidate& c = r.design;
    const bool done = r.status == "finished";
    t.add_row({r.rank, c.name, r.status, r.life_h, r.life_sigma_h, r.life_extrapolated, r.tied_with_best,
               done ? io::CsvCell(r.replicates) : io::CsvCell(std::string()), done ? r.error_source : std::string(),
               in_kW(r.power_W), in_kW(r.power_se_W), in_kW(r.collision_W), in_kW(r.collision_se_W), r.utilization,
               r.utilization_se, r.area_loss_mm2_per_1000h, r.pareto_power,
               r.pareto_utilization, c.height_mm, c.top_width_mm, c.leading_deg, c.trailing_deg, c.rows,
               c.direction, c.area_mm2, r.reason});
  }
  t.write(ranking_csv(out));
}

}  // namespace millwear::screen
