// The run as its caller shows it (see run_progress.hpp).
#include "study/run_progress.hpp"

#include <cstdio>

#include "wear/life.hpp"

#include <algorithm>
#include <cmath>

namespace millwear::study {

DesignProgress design_progress(const RunState& ctx, std::size_t i) {
  const DesignInput& d = ctx.plan.designs[i];
  const DesignState& st = *ctx.designs[i];
  DesignProgress p;
  p.status = st.status;
  p.stages = d.scene.wear.stages;
  p.stage = st.progress.stage;
  p.resumed_stage = std::max(0, st.resumed_up_to);
  p.hours = st.progress.hours;
  p.simulated_s = st.progress.simulated_s;
  p.disk_steps_per_s = st.progress.disk_steps_per_s;
  p.wall_s = st.wall_s;
  p.error = st.error;
  if (st.status != DesignStatus::Running) return p;
  // Hours count from the liner's own start (lifters.start_hours: a worn liner).
  const double end_h = d.scene.wear.start_hours + d.scene.wear.stage_hours * d.scene.wear.stages;
  p.start_hours = st.resumed_up_to >= 0 && st.stages.count(st.resumed_up_to) ? st.stages.at(st.resumed_up_to).hours
                                                                              : d.scene.wear.start_hours;
  // The wear loop reports after each stage; before the first report only time runs.
  p.measuring = st.progress.simulated_s <= 0.0;
  const double done_h = st.progress.hours - p.start_hours, left_h = end_h - st.progress.hours;
  p.elapsed_s = std::chrono::duration<double>(Clock::now() - st.started).count();
  const double at_report = std::chrono::duration<double>(st.progress_at - st.started).count();
  const double since = std::chrono::duration<double>(Clock::now() - st.progress_at).count();
  p.left_s = done_h > 0 ? std::max(0.0, at_report * left_h / done_h - since) : std::nan("");
  return p;
}

std::vector<DesignLines> design_lines(const RunState& ctx) {
  std::vector<DesignLines> out;
  for (std::size_t i = 0; i < ctx.plan.designs.size(); ++i) {
    const DesignInput& d = ctx.plan.designs[i];
    const DesignState& st = *ctx.designs[i];
    DesignLines dl;
    dl.name = d.name;
    life_of(d, st, dl.life_h, dl.life_extrapolated);
    const auto own0 = st.stages.find(0);
    for (const auto& [k, r] : st.stages) {
      StageLine l;
      l.stage = k;
      l.hours = r.hours;
      l.area_m2 = r.lifter.area_m2;
      l.height_m = r.lifter.height_m;
      l.area_loss_fraction = own0 != st.stages.end() ? 1.0 - r.lifter.area_m2 / own0->second.lifter.area_m2
                                                     : std::nan("");
      if (d.scene.mill.kind_count() > 1)
        for (std::size_t k = 0; k < r.kinds.size(); ++k) {
          l.kind_area_m2.push_back(r.kinds[k].area_m2);
          l.kind_area_loss_rate_m2_per_s.push_back(
              k < r.kind_area_loss_rate_m2_per_s.size() ? r.kind_area_loss_rate_m2_per_s[k] : std::nan(""));
        }
      dl.stages.push_back(l);
    }
    dl.life_from_hours = d.continue_run.empty() ? d.scene.wear.start_hours : d.continue_hours;
    if (d.scene.mill.kind_count() > 1) {
      for (int k = 0; k < d.scene.mill.kind_count(); ++k) dl.kind_names.push_back(d.scene.mill.kind(k).name);
      WearHistory h;
      for (const auto& [k, r] : st.stages) h.stages.push_back(r);
      compute_life(h, d.scene.wear.replacement_height_m);
      dl.kind_life_h = h.kind_life_h;
      dl.kind_life_extrapolated = h.kind_life_extrapolated;
    }
    if (!d.continue_run.empty()) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " stage %d (%.6g h)", d.continue_stage, d.continue_hours);
      dl.continued_from = d.continue_run + buf;
      dl.changes = d.changes;
    }
    dl.status = st.status;
    dl.error = st.error;
    dl.events = st.events;
    out.push_back(std::move(dl));
  }
  return out;
}

}  // namespace millwear::study
